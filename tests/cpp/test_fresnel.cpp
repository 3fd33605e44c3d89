// Fresnel reflectance and Stover's polarization factors (conventions.md): limits and the specular
// identities Q_s = R_s, Q_p = R_p, Qbar = F. References in long-double complex arithmetic.
#include <gtest/gtest.h>
#include <hwy/targets.h>  // HWY_SCALAR

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "angular_simd.h"
#include "libbrdf/error.h"
#include "libbrdf/fresnel.h"
#include "libbrdf/geometry.h"
#include "test_support.h"

namespace {

using namespace libbrdf;
using libbrdf_test::deg;
using libbrdf_test::relative_difference;

// The indices the paper's metals and dielectrics span, incl. n < 1 (total internal reflection).
const std::vector<ComplexIndex> kIndices{{4.0, 10.0}, {1.5, 1.0}, {1.4, 0.0}, {1.7, 5.0}, {0.25, 3.0}, {0.8, 0.0}, {0.05, 0.0}};
const std::vector<double> kAnglesDeg{0, 1, 10, 30, 45, 60, 75, 85, 89, 89.9};

// |r_s|^2 and |r_p|^2 from the textbook (Born & Wolf sec. 13.4) in long double.
struct SP {
  long double s, p;
};
SP reference_fresnel(const ComplexIndex& index, long double theta) {
  using C = std::complex<long double>;
  const C n(index.n, index.kappa), eps = n * n;
  const long double c = std::cos(theta), s2 = std::sin(theta) * std::sin(theta);
  C w = std::sqrt(eps - s2);
  if (w.imag() < 0) w = -w;  // principal branch with Im w >= 0 (conventions.md)
  return {std::norm((c - w) / (c + w)), std::norm((eps * c - w) / (eps * c + w))};
}

std::string describe(const ComplexIndex& index) {
  return "n=" + std::to_string(index.n) + "+" + std::to_string(index.kappa) + "i";
}

TEST(Fresnel, ReflectancesMatchLongDoubleTextbookFormulas) {
  for (const ComplexIndex& index : kIndices) {
    for (double angle : kAnglesDeg) {
      const FresnelSP rsp = fresnel_sp(index.permittivity(), std::cos(deg(angle)));
      const SP ref = reference_fresnel(index, deg(angle));
      EXPECT_NEAR(rsp.r_s, static_cast<double>(ref.s), 1e-13) << describe(index) << " at " << angle << " deg";
      EXPECT_NEAR(rsp.r_p, static_cast<double>(ref.p), 1e-13) << describe(index) << " at " << angle << " deg";
    }
  }
}

TEST(Fresnel, QsEqualsRsAndQpEqualsRpAtSpecular) {
  for (const ComplexIndex& index : kIndices) {
    for (double angle : kAnglesDeg) {
      const ScatterGeometry geo = make_scatter_geometry({deg(angle), deg(angle), kPi});
      const PolarizationFactors q = stover_q(index.permittivity(), geo);
      const SP ref = reference_fresnel(index, deg(angle));
      EXPECT_NEAR(q.q_s(), static_cast<double>(ref.s), 1e-12) << describe(index) << " at " << angle << " deg";
      EXPECT_NEAR(q.q_p(), static_cast<double>(ref.p), 1e-12) << describe(index) << " at " << angle << " deg";
      // In the plane of incidence there is no cross-polarization (sin(pi) ~ 1e-16 rounding only).
      EXPECT_LE(q.sp, 1e-28) << describe(index) << " at " << angle << " deg";
      EXPECT_LE(q.ps, 1e-28) << describe(index) << " at " << angle << " deg";
    }
  }
}

TEST(Fresnel, QbarEqualsFAndPaperQEqualsTwoFAtSpecular) {
  for (const ComplexIndex& index : kIndices) {
    for (double angle : kAnglesDeg) {
      const ScatterGeometry geo = make_scatter_geometry({deg(angle), deg(angle), kPi});
      const PolarizationFactors q = stover_q(index.permittivity(), geo);
      const double f = fresnel_reflectance(index.permittivity(), std::cos(deg(angle)));
      EXPECT_LE(relative_difference(q.q_bar(), f), 1e-12) << describe(index) << " at " << angle << " deg: Qbar " << q.q_bar() << " F " << f;
      EXPECT_LE(relative_difference(q.q_paper(), 2.0 * f), 1e-12) << describe(index) << " at " << angle << " deg";
    }
  }
}

TEST(Fresnel, NormalIncidenceEqualsClosedForm) {
  for (const ComplexIndex& index : kIndices) {
    const double n = index.n, k = index.kappa;
    const double expected = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    const double f = fresnel_reflectance(index.permittivity(), 1.0);
    EXPECT_LE(relative_difference(f, expected), 1e-14) << describe(index) << ": F(0) = " << f << ", expected " << expected;
  }
}

TEST(Fresnel, ReflectanceTendsToOneAtGrazing) {
  for (const ComplexIndex& index : kIndices) {
    double previous_gap = 1.0;
    for (double cos_theta : {1e-2, 1e-4, 1e-6, 1e-9, 1e-12}) {
      const double f = fresnel_reflectance(index.permittivity(), cos_theta);
      const double gap = 1.0 - f;
      EXPECT_GE(gap, 0.0) << describe(index) << " F = " << f << " > 1 at cos = " << cos_theta;
      // 1 - F = O(cos theta) with a coefficient ~ 4 |eps| / |w| (< 100 for these indices).
      EXPECT_LE(gap, 100.0 * cos_theta) << describe(index) << " at cos theta = " << cos_theta;
      EXPECT_LE(gap, previous_gap + 1e-15) << describe(index) << " not approaching 1";
      previous_gap = gap;
    }
  }
}

TEST(Fresnel, TotalInternalReflectionBelowUnitIndex) {
  // n = 0.8: critical angle asin(0.8) = 53.13 deg; beyond it R_s = R_p = 1.
  const ComplexIndex index{0.8, 0.0};
  for (double angle : {54.0, 60.0, 80.0}) {
    const FresnelSP rsp = fresnel_sp(index.permittivity(), std::cos(deg(angle)));
    EXPECT_NEAR(rsp.r_s, 1.0, 1e-14) << angle;
    EXPECT_NEAR(rsp.r_p, 1.0, 1e-14) << angle;
  }
  EXPECT_LT(fresnel_reflectance(index.permittivity(), std::cos(deg(50.0))), 0.9);
}

TEST(Fresnel, PolarizationFactorsAreReciprocalAndNonNegative) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> polar(0.0, deg(89.5)), azimuth(-kPi, 3 * kPi);
  for (const ComplexIndex& index : kIndices) {
    for (int i = 0; i < 500; ++i) {
      const double ti = polar(rng), ts = polar(rng), phi = azimuth(rng);
      const PolarizationFactors a = stover_q(index.permittivity(), make_scatter_geometry({ti, ts, phi}));
      const PolarizationFactors b = stover_q(index.permittivity(), make_scatter_geometry({ts, ti, phi}));
      ASSERT_GE(std::min({a.ss, a.sp, a.ps, a.pp}), 0.0);
      // Swapping the directions swaps the cross terms and keeps ss, pp: Qbar is reciprocal.
      ASSERT_LE(relative_difference(a.ss, b.ss), 1e-12) << describe(index);
      ASSERT_LE(relative_difference(a.pp, b.pp), 1e-12) << describe(index) << " pp " << a.pp << " vs " << b.pp;
      ASSERT_LE(relative_difference(a.sp, b.ps), 1e-12) << describe(index);
      ASSERT_LE(relative_difference(a.q_bar(), b.q_bar()), 1e-12) << describe(index);
    }
  }
}

TEST(Fresnel, ValidateIndexRejectsNonPositiveNAndNegativeKappa) {
  auto parameter_of = [](const ComplexIndex& index) -> std::string {
    try {
      validate_index(index);
    } catch (const InvalidArgument& e) {
      return e.parameter();
    }
    return "accepted";
  };
  EXPECT_EQ(parameter_of({0.0, 1.0}), "n");
  EXPECT_EQ(parameter_of({std::nan(""), 1.0}), "n");
  EXPECT_EQ(parameter_of({1.5, -0.1}), "k");
  EXPECT_EQ(parameter_of({1.5, 0.0}), "accepted");
}

}  // namespace


namespace {
// The SIMD spans of Qbar and F(theta_d) (angular_simd.cpp: complex arithmetic in real/imag
// vectors) against stover_q / fresnel_reflectance: metals, a dielectric with total internal
// reflection (n < 1, kappa = 0: F = 1 exactly), kappa = 1000, grazing and normal incidence.
TEST(Fresnel, SimdSpansMatchScalarQbarAndF) {
  std::vector<ScatterGeometry> geos;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> polar(0.0, deg(89.9999)), azimuth(0.0, 2 * kPi);
  for (int k = 0; k < 4000; ++k) geos.push_back(make_scatter_geometry({polar(rng), polar(rng), azimuth(rng)}));
  for (double ti : {0.0, deg(60.0), deg(89.9999)})
    for (double ts : {0.0, deg(60.0), deg(89.9999)})
      for (double phi : {0.0, kPi / 2, kPi}) geos.push_back(make_scatter_geometry({ti, ts, phi}));
  const std::vector<ComplexIndex> indices{{0.2, 3.0}, {1.5, 0.0}, {0.6, 0.0}, {1.5, 1000.0}, {1000.0, 0.0}, {1e-3, 0.0}};
  std::vector<double> q(geos.size()), f(geos.size());
  for (const ComplexIndex& index : indices) {
    const Complex eps = index.permittivity();
    detail::stover_q_bar_span(eps.real(), eps.imag(), geos.data(), geos.size(), q.data());
    detail::fresnel_d_span(eps.real(), eps.imag(), geos.data(), geos.size(), f.data());
    double worst_q = 0.0, worst_f = 0.0;
    for (std::size_t k = 0; k < geos.size(); ++k) {
      worst_q = std::max(worst_q, relative_difference(q[k], stover_q(eps, geos[k]).q_bar()));
      const double f_ref = fresnel_reflectance(eps, geos[k].cos_theta_d);
      worst_f = std::max(worst_f, relative_difference(f[k], f_ref));
      if (f_ref == 1.0) {
        ASSERT_EQ(f[k], 1.0) << "total internal reflection, n = " << index.n;
      }
    }
    // |eps| ~ 1e6 at grazing forward scatter: Q_pp cancels, and the scalar formula itself is only
    // good to 8e-11 there (against long double; the SIMD one to 1.2e-10).
    const double q_bound = std::abs(eps) > 1e4 ? 3e-10 : 1e-13;
    EXPECT_LE(worst_q, q_bound) << index.n << " + " << index.kappa << "i";
    EXPECT_LE(worst_f, 1e-13) << index.n << " + " << index.kappa << "i";
  }
}

// Several channels' Qbar in one pass (the kernel layout's wavelengths share the geometry reads):
// each channel's values are its single-channel span's, bit for bit, at span lengths shorter than
// a vector, not a multiple of it, and long; the rows land at their stride.
TEST(Fresnel, MultiChannelQbarSpanGivesEachChannelsOwnBits) {
  std::vector<ScatterGeometry> geos;
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> polar(0.0, deg(89.9)), azimuth(0.0, 2 * kPi);
  for (int k = 0; k < 301; ++k) geos.push_back(make_scatter_geometry({polar(rng), polar(rng), azimuth(rng)}));
  const std::vector<ComplexIndex> indices{{0.2, 3.0}, {1.5, 0.0}, {0.6, 0.0}, {0.18, 3.4}};
  std::vector<double> eps_re, eps_im;
  for (const ComplexIndex& index : indices) eps_re.push_back(index.permittivity().real()), eps_im.push_back(index.permittivity().imag());
  const int channels = static_cast<int>(indices.size());
  for (std::size_t count : {std::size_t{1}, std::size_t{3}, std::size_t{13}, geos.size()}) {
    const std::size_t stride = count + 5;
    std::vector<double> all(channels * stride, -7.0), one(count);
    detail::stover_q_bar_span(eps_re.data(), eps_im.data(), channels, geos.data(), count, all.data(), stride);
    for (int c = 0; c < channels; ++c) {
      detail::stover_q_bar_span(eps_re[c], eps_im[c], geos.data(), count, one.data());
      for (std::size_t k = 0; k < count; ++k) ASSERT_EQ(all[c * stride + k], one[k]) << "channel " << c << " count " << count << " k " << k;
      for (std::size_t k = count; k < stride; ++k) ASSERT_EQ(all[c * stride + k], -7.0) << "written past the row, channel " << c;
    }
  }
}

// The kernel layout's single-precision Qbar (angular_simd.h): inside qbar_single_precision_range
// within 3e-5 of the double lanes on every Highway target, at metals up to |eps| = 100, dielectrics,
// n < 1 at and near its critical angle, and polar angles up to 89.999 deg; a query's value is the
// same bits alone as in a span (its lanes are paired two vectors at a time); the range refuses
// |eps| > 100 and eps ~ 1 (where the layout keeps the double lanes).
TEST(Fresnel, SinglePrecisionQbarWithinItsBoundOnEveryTarget) {
  std::vector<ScatterGeometry> geos;
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> polar(0.0, deg(89.999)), grazing(deg(89.0), deg(89.999)), azimuth(0.0, 2 * kPi);
  for (int k = 0; k < 400; ++k) geos.push_back(make_scatter_geometry({polar(rng), polar(rng), azimuth(rng)}));
  for (int k = 0; k < 100; ++k) geos.push_back(make_scatter_geometry({grazing(rng), grazing(rng), azimuth(rng)}));
  const double critical = std::asin(0.6);  // n = 0.6, kappa = 0: z = eps - sin^2 theta_i crosses 0
  for (double offset : {-1e-9, 0.0, 1e-9, 1e-6})
    geos.push_back(make_scatter_geometry({critical + offset, polar(rng), azimuth(rng)}));
  std::vector<double> eps_re, eps_im;
  for (double n : {0.05, 0.2, 0.6, 0.97, 1.03, 1.5, 4.0, 9.9})
    for (double kappa : {0.0, 1e-3, 0.5, 3.0, 9.9}) {
      const std::complex<double> eps = std::complex<double>(n, kappa) * std::complex<double>(n, kappa);
      if (!detail::qbar_single_precision_range(eps.real(), eps.imag())) continue;
      eps_re.push_back(eps.real()), eps_im.push_back(eps.imag());
    }
  ASSERT_GE(eps_re.size(), 30u);
  EXPECT_FALSE(detail::qbar_single_precision_range(101.0, 0.0));
  EXPECT_FALSE(detail::qbar_single_precision_range(-20.0, 98.0));
  EXPECT_FALSE(detail::qbar_single_precision_range(1.0, 5e-4));
  EXPECT_TRUE(detail::qbar_single_precision_range(-99.0, 10.0));
  const int channels = static_cast<int>(eps_re.size());
  const std::size_t count = geos.size();
  libbrdf_test::for_each_simd_target([&](std::int64_t target) {
    std::vector<double> single(channels * count), exact(channels * count);
    detail::stover_q_bar_span(eps_re.data(), eps_im.data(), channels, geos.data(), count, single.data(), count, detail::QBarPrecision::single);
    detail::stover_q_bar_span(eps_re.data(), eps_im.data(), channels, geos.data(), count, exact.data(), count);
    double worst = 0.0;
    for (std::size_t k = 0; k < single.size(); ++k) {
      ASSERT_TRUE(std::isfinite(single[k]) && single[k] > 0.0) << "k " << k;
      worst = std::max(worst, relative_difference(single[k], exact[k]));
    }
    EXPECT_LE(worst, 3e-5);
    if (target != HWY_SCALAR) {  // single precision indeed (one lane: the double lanes)
      EXPECT_GE(worst, 1e-8);
    }
    RecordProperty("max_rel_diff_" + std::string(hwy::TargetName(target)), std::to_string(worst));
    for (std::size_t length : {std::size_t{1}, std::size_t{5}, std::size_t{17}, std::size_t{37}}) {
      std::vector<double> part(length);
      for (int c : {0, channels - 1}) {
        detail::stover_q_bar_span(&eps_re[c], &eps_im[c], 1, geos.data() + 3, length, part.data(), 0, detail::QBarPrecision::single);
        for (std::size_t k = 0; k < length; ++k) ASSERT_EQ(part[k], single[c * count + 3 + k]) << "length " << length << " k " << k;
      }
    }
  });
}

}  // namespace
