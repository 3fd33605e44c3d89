// Geometry identities of the paper (eqs 5, 6, 10, 17-19) and the BK / S identities (eqs 22, 26-28),
// over random in-plane and out-of-plane angles (fixed seed). References in long double.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "libbrdf/batch.h"
#include "libbrdf/beckmann_kirchhoff.h"
#include "libbrdf/error.h"
#include "libbrdf/geometry.h"
#include "libbrdf/models.h"
#include "test_support.h"

namespace {

using namespace libbrdf;
using libbrdf_test::deg;
using libbrdf_test::relative_difference;

// Random geometry: polar angles in [0, 89.9] deg, azimuth in [0, 360) deg; every fourth sample
// in the plane of incidence (phi_s = 0 or 180 deg), where the identities meet their edge cases.
struct AngleSampler {
  std::mt19937_64 rng{20151029};
  std::uniform_real_distribution<double> polar{0.0, deg(89.9)}, azimuth{0.0, 2.0 * kPi};
  int count = 0;
  ScatterAngles next() {
    ScatterAngles a{polar(rng), polar(rng), azimuth(rng)};
    if (count++ % 4 == 0) a.phi_s = (count % 8 == 1) ? kPi : 0.0;
    return a;
  }
};

constexpr int kSamples = 20000;

TEST(Geometry, DerivedAnglesMatchLongDoubleEqs5_6_10) {
  AngleSampler sampler;
  for (int i = 0; i < kSamples; ++i) {
    const ScatterAngles a = sampler.next();
    const ScatterGeometry geo = make_scatter_geometry(a);
    const long double ti = a.theta_i, ts = a.theta_s, ps = a.phi_s;
    const long double cos2d = std::cos(ti) * std::cos(ts) + std::sin(ti) * std::sin(ts) * std::cos(ps);  // eq. 5
    const long double eta2 = std::sin(ti) * std::sin(ti) + std::sin(ts) * std::sin(ts) +
                             2 * std::sin(ti) * std::sin(ts) * std::cos(ps);  // eq. 10
    const long double cos_h = (std::cos(ti) + std::cos(ts)) / (2 * std::sqrt((1 + cos2d) / 2));  // eq. 6
    ASSERT_NEAR(geo.cos_2theta_d, static_cast<double>(cos2d), 1e-15) << "ti=" << a.theta_i << " ts=" << a.theta_s << " phi=" << a.phi_s;
    ASSERT_NEAR(geo.eta_r2, static_cast<double>(eta2), 4e-15) << "ti=" << a.theta_i << " ts=" << a.theta_s << " phi=" << a.phi_s;
    ASSERT_LE(relative_difference(geo.cos_theta_h, static_cast<double>(cos_h)), 1e-12)
        << "cos th " << geo.cos_theta_h << " vs " << static_cast<double>(cos_h);
  }
}

// eq. 19: tan^2 th (from eq. 6's cos th, or eq. 17's cos td) equals eta_r^2 / (cos ti + cos ts)^2.
// eq. 18 is the identity of the numerators, 4 cos^2 td - (ci + cs)^2 = eta_r^2 (all O(1) terms).
TEST(Geometry, TanSquaredHalfAngleEqualsEtaOverCosineSumEq19) {
  AngleSampler sampler;
  double worst18 = 0, worst19 = 0;
  for (int i = 0; i < kSamples; ++i) {
    const ScatterAngles a = sampler.next();
    const ScatterGeometry geo = make_scatter_geometry(a);
    const long double ti = a.theta_i, ts = a.theta_s, ps = a.phi_s;
    const long double sum = std::cos(ti) + std::cos(ts);
    const long double cos2d = std::cos(ti) * std::cos(ts) + std::sin(ti) * std::sin(ts) * std::cos(ps);
    const long double numerator17 = 2 + 2 * cos2d - sum * sum;  // 4 cos^2 td - (ci + cs)^2, eq. 17/18
    const long double eta2 = std::sin(ti) * std::sin(ti) + std::sin(ts) * std::sin(ts) +
                             2 * std::sin(ti) * std::sin(ts) * std::cos(ps);
    const double err18 = static_cast<double>(std::fabs(numerator17 - eta2));
    worst18 = std::max(worst18, err18);
    ASSERT_LE(err18, 1e-15) << "eq. 18 at ti=" << a.theta_i << " ts=" << a.theta_s << " phi=" << a.phi_s;

    // The library's tan^2 th (eq. 19's right-hand side) against tan^2 th = 1/cos^2 th - 1 from its
    // own eq. 6 cos th. 1 - cos^2 th has rounding ~1e-16, so the comparison is relative to max(1, value).
    const double rhs = tan2_theta_h(geo);
    const double ch2 = geo.cos_theta_h * geo.cos_theta_h;
    const double lhs = (1.0 - ch2) / ch2;
    const double err19 = std::fabs(lhs - rhs) / std::max(1.0, rhs);
    worst19 = std::max(worst19, err19);
    ASSERT_LE(err19, 1e-12) << "eq. 19: 1/cos^2 th - 1 = " << lhs << " vs eta^2/(ci+cs)^2 = " << rhs << " at ti="
                            << a.theta_i << " ts=" << a.theta_s << " phi=" << a.phi_s;
    // And against the long-double eq. 17.
    const double ref17 = static_cast<double>(numerator17 / (sum * sum));
    ASSERT_LE(std::fabs(ref17 - rhs) / std::max(1.0, rhs), 1e-12) << rhs << " vs eq. 17 " << ref17;
  }
  RecordProperty("worst_eq18_abs", std::to_string(worst18));
  RecordProperty("worst_eq19_rel", std::to_string(worst19));
}

TEST(BeckmannKirchhoff, GeometricFactorEq27EqualsEq26) {
  AngleSampler sampler;
  for (int i = 0; i < kSamples; ++i) {
    const ScatterAngles a = sampler.next();
    const ScatterGeometry geo = make_scatter_geometry(a);
    const double f26 = bk_geometric_factor_eq26(geo), f27 = bk_geometric_factor_eq27(geo);
    // Long-double eq. 26 as printed in the paper.
    const long double ti = a.theta_i, ts = a.theta_s, ps = a.phi_s;
    const long double r = (1 + std::cos(ti) * std::cos(ts) + std::sin(ti) * std::sin(ts) * std::cos(ps)) /
                          (std::cos(ti) * (std::cos(ti) + std::cos(ts)));
    ASSERT_LE(relative_difference(f26, f27), 1e-12) << "eq. 26 " << f26 << " vs eq. 27 " << f27 << " at ti=" << a.theta_i
                                                    << " ts=" << a.theta_s << " phi=" << a.phi_s;
    ASSERT_LE(relative_difference(f26, static_cast<double>(r * r)), 1e-12) << f26 << " vs long-double eq. 26 " << static_cast<double>(r * r);
  }
}

TEST(BeckmannKirchhoff, InverseSEq28EqualsOneOverSEq22) {
  AngleSampler sampler;
  for (int i = 0; i < kSamples; ++i) {
    const ScatterAngles a = sampler.next();
    const ScatterGeometry geo = make_scatter_geometry(a);
    const double inv_s = inverse_s_term_eq28(geo), s = s_term(geo);
    ASSERT_LE(relative_difference(inv_s, 1.0 / s), 1e-12) << "eq. 28 " << inv_s << " vs 1/eq. 22 " << 1.0 / s << " at ti="
                                                          << a.theta_i << " ts=" << a.theta_s << " phi=" << a.phi_s;
    // eq. 22 in long double from the angles alone.
    const long double ti = a.theta_i, ts = a.theta_s, ps = a.phi_s;
    const long double ci = std::cos(ti), cs = std::cos(ts);
    const long double cos2d = ci * cs + std::sin(ti) * std::sin(ts) * std::cos(ps);
    const long double ch2 = (ci + cs) * (ci + cs) / (2 * (1 + cos2d));
    const long double s_ref = 4 * ci * cs * ch2 * ch2 / ((ci + cs) * (ci + cs));
    ASSERT_LE(relative_difference(s, static_cast<double>(s_ref)), 1e-12) << s << " vs long-double eq. 22 " << static_cast<double>(s_ref);
  }
}

TEST(BeckmannKirchhoff, InverseSEqualsFbkSquaredOnlyAtEqualAngles) {
  // eq. 26 vs eq. 28: F_bk^2 / (1/S) = cs / ci, so they agree exactly when ti = ts.
  const ScatterGeometry same = make_scatter_geometry({deg(35), deg(35), deg(120)});
  EXPECT_NEAR(bk_geometric_factor_eq26(same) / inverse_s_term_eq28(same), 1.0, 1e-14);
  const ScatterGeometry other = make_scatter_geometry({deg(10), deg(60), deg(180)});
  const double ratio = bk_geometric_factor_eq26(other) / inverse_s_term_eq28(other);
  EXPECT_NEAR(ratio, std::cos(deg(60)) / std::cos(deg(10)), 1e-13) << "F_bk^2 S = cs/ci expected";
}

TEST(Geometry, RoughnessGMatchesEq12) {
  // g = (2 pi sigma/lambda)^2 (ci + cs)^2: at normal incidence and scatter, (4 pi sigma/lambda)^2.
  EXPECT_NEAR(roughness_g(0.1, 1.0, 1.0), std::pow(4.0 * kPi * 0.1, 2), 1e-13);
  EXPECT_NEAR(roughness_g(0.25, std::cos(deg(60)), std::cos(deg(30))),
              std::pow(2.0 * kPi * 0.25 * (0.5 + std::sqrt(3.0) / 2.0), 2), 1e-13);
}

TEST(Geometry, RejectsPolarAnglesAtOrBelowHorizonAndNaN) {
  for (double bad : {kPi / 2, 2.0, -1e-9, std::nan("")}) {
    try {
      make_scatter_geometry({bad, 0.1, kPi});
      ADD_FAILURE() << "theta_i = " << bad << " accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.parameter(), "theta_i") << e.what();
    }
    try {
      make_scatter_geometry({0.1, bad, kPi});
      ADD_FAILURE() << "theta_s = " << bad << " accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.parameter(), "theta_s") << e.what();
    }
  }
  try {
    make_scatter_geometry({0.1, 0.2, std::numeric_limits<double>::infinity()});
    ADD_FAILURE() << "phi_s = inf accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.parameter(), "phi_s") << e.what();
  }
}

}  // namespace

namespace {
// The span path and make_scatter_geometry give the same bits (one SIMD sine/cosine routine, 3 ulp),
// and both agree with the C library's sines and cosines to rounding: every field, over random
// angles, grazing ones and azimuths beyond Highway's range (|phi| > 39000 rad: the C library's).
// Bounds: the measured maxima (a few 1e-16) with margin.
// Polar angles up to 1e-13 deg from the horizon: the degree path's cosines keep their relative
// precision, against long double sines of the complement (the radian path's cos theta is off by
// ~1e-16 rad / cos theta: 1.1e-3 at 89.99999999999 deg), and the derived fields follow.
TEST(Geometry, DegreePathKeepsGrazingCosinesPrecise) {
  const long double pi = 3.141592653589793238462643383279502884L;
  for (double t : {0.0, 30.0, 45.0, 60.0, 89.9, 89.9999999, 89.999999999, 89.99999999999, 89.9999999999999}) {
    const ScatterGeometry geo = make_scatter_geometry_degrees(t, t, 180.0);  // the specular direction
    const long double cos_exact = std::sin((90.0L - t) * pi / 180.0L), sin_exact = std::cos((90.0L - t) * pi / 180.0L);
    EXPECT_LE(relative_difference(geo.cos_theta_i, static_cast<double>(cos_exact)), 3e-16) << t;
    EXPECT_LE(relative_difference(geo.cos_theta_s, static_cast<double>(cos_exact)), 3e-16) << t;
    EXPECT_NEAR(geo.sin_theta_i, static_cast<double>(sin_exact), 3e-16 * static_cast<double>(sin_exact) + 1e-19) << t;
    EXPECT_NEAR(geo.cos_theta_h, 1.0, 1e-15) << t;  // specular: the half vector is the normal
    EXPECT_LE(geo.eta_r2, 1e-30) << t;
  }
  // A degree batch uses it above kGrazingDegrees (there the radian geometry's value is 1e-3 off),
  // and the radian geometry below; batch and per-query values agree to rounding (batch.h).
  ModelParameters p;
  p.sigma_s_um = 0.4, p.lc_um = 4.6, p.wavelength_um = 0.86, p.index = ComplexIndex{1.5, 0.0};
  const Model asf(ModelKind::asf, p);
  const std::vector<double> ti = {89.99999999999, 30.0, 89.9, 89.95}, ts = {89.99999999999, 40.0, 10.0, 20.0},
                            ps = {0.0, 200.0, 180.0, 90.0};
  std::vector<double> batch(ti.size());
  evaluate_degrees_batch(asf, ti.data(), ts.data(), ps.data(), ti.size(), batch.data());
  for (std::size_t k = 0; k < ti.size(); ++k) {
    const bool grazing = ti[k] > kGrazingDegrees || ts[k] > kGrazingDegrees;
    const double from_degrees = asf.evaluate(make_scatter_geometry_degrees(ti[k], ts[k], ps[k]));
    const double from_radians = asf.evaluate(scatter_angles_from_degrees(ti[k], ts[k], ps[k]));
    EXPECT_LE(relative_difference(batch[k], grazing ? from_degrees : from_radians), 1e-12) << k;
    if (k == 0) {
      EXPECT_GT(relative_difference(from_degrees, from_radians), 1e-4);  // why the degree path
    }
  }
}

TEST(Geometry, SpanGeometriesMatchScalarToRounding) {
  std::vector<ScatterAngles> angles;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> polar(0.0, deg(89.999)), azimuth(-4 * kPi, 4 * kPi);
  for (int k = 0; k < 20000; ++k) angles.push_back({polar(rng), polar(rng), azimuth(rng)});
  for (double ti : {0.0, 1e-9, deg(45.0), deg(89.99999)})
    for (double ts : {0.0, 1e-9, deg(30.0), deg(89.99999)})
      for (double phi : {0.0, kPi, -kPi / 2, 1e5, -3e6}) angles.push_back({ti, ts, phi});
  // An odd count: the tail takes the shifted last vector (or the padded copy).
  for (std::size_t count : {angles.size(), std::size_t{3}, std::size_t{1}}) {
    std::vector<ScatterGeometry> span(count);
    make_scatter_geometries(angles.data(), count, span.data());
    double worst_trig = 0.0, worst_derived = 0.0;
    for (std::size_t k = 0; k < count; ++k) {
      const ScatterGeometry scalar = make_scatter_geometry(angles[k]), &got = span[k];
      for (int field = 0; field < 10; ++field)
        ASSERT_EQ((&got.cos_theta_i)[field], (&scalar.cos_theta_i)[field]) << "field " << field << ", query " << k;
      const ScatterAngles& a = angles[k];
      const ScatterGeometry ref = scatter_geometry_from_trig(std::cos(a.theta_i), std::sin(a.theta_i), std::cos(a.theta_s),
                                                             std::sin(a.theta_s), std::cos(a.phi_s), std::sin(a.phi_s));
      for (double diff : {got.cos_theta_i - ref.cos_theta_i, got.sin_theta_i - ref.sin_theta_i, got.cos_theta_s - ref.cos_theta_s,
                          got.sin_theta_s - ref.sin_theta_s, got.cos_phi_s - ref.cos_phi_s, got.sin_phi_s - ref.sin_phi_s})
        worst_trig = std::max(worst_trig, std::abs(diff));
      // Derived fields: absolute in cos 2td and eta_r^2 (both O(1)); cos td, cos th relative to
      // cos td (which the rounding of cos 2td near -1 amplifies like 1/cos td).
      worst_derived = std::max({worst_derived, std::abs(got.cos_2theta_d - ref.cos_2theta_d), std::abs(got.eta_r2 - ref.eta_r2),
                                std::abs(got.cos_theta_d - ref.cos_theta_d) * ref.cos_theta_d,
                                std::abs(got.cos_theta_h - ref.cos_theta_h) * ref.cos_theta_d * ref.cos_theta_d});
    }
    EXPECT_LE(worst_trig, 1e-15) << count;
    EXPECT_LE(worst_derived, 4e-15) << count;
  }
}
}  // namespace
