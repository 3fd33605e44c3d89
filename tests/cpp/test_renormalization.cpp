// Renormalization K(theta_i) of eq. 13 (conventions.md: plane and tis modes) and energy
// conservation, checked against the test's own hemispherical quadrature in (theta_s, phi_s).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include "libbrdf/error.h"
#include "libbrdf/geometry.h"
#include "libbrdf/mbk_series.h"
#include "libbrdf/renormalization.h"
#include "libbrdf/surface.h"
#include "test_support.h"

namespace {

using namespace libbrdf;
using libbrdf_test::deg;

// Hemispherical integral of A(ti, ts, phi_s) cos ts dOmega (= the direction-cosine disk integral),
// by nested adaptive Gauss-Legendre in (theta_s, phi_s) with panels graded towards the specular
// direction (ts = ti, phi_s = 180 deg). With constant_g > 0 every point uses that g instead of
// g(ti, ts) (the D(g1) of conventions.md). The ASF itself is Sigma(g, c) with c and g computed here
// from the angles (eqs 10, 12); Sigma is checked against a brute-force sum in test_series.cpp.
double hemisphere_integral(const Surface& surface, double theta_i, double constant_g = 0.0) {
  const double lc = surface.lc_over_lambda(), sigma = surface.sigma_over_lambda();
  const double prefactor = kPi * lc * lc;
  const double ci = std::cos(theta_i), si = std::sin(theta_i);
  const double g_spec = std::pow(4 * kPi * sigma * ci, 2);
  const double width = std::max(1.0, std::sqrt(g_spec)) / (kPi * lc);  // lobe width in direction cosines
  SeriesOptions series;
  series.method = SeriesMethod::every_term;
  const libbrdf_test::AdaptiveIntegrator integrator;
  const std::vector<double> theta_breaks =
      libbrdf_test::graded_breaks(0.0, 0.5 * kPi, theta_i, 0.25 * width / std::max(ci, 0.05));
  auto inner = [&](double ts) {
    const double cs = std::cos(ts), ss = std::sin(ts);
    const double g = constant_g > 0 ? constant_g : std::pow(2 * kPi * sigma * (ci + cs), 2);
    auto integrand = [&](double phi) {
      const long double eta2 = static_cast<long double>(si) * si + static_cast<long double>(ss) * ss +
                               2.0L * si * ss * std::cos(static_cast<long double>(phi));  // eq. 10
      const double c = kPi * kPi * lc * lc * static_cast<double>(std::max(0.0L, eta2));
      return prefactor * mbk_series_sum(g, c, series);
    };
    const double finest = 0.25 * width / std::max(ss, 0.02);
    const double half = integrator.integrate(integrand, libbrdf_test::graded_breaks(0.0, kPi, kPi, finest), 1e-11);
    return 2.0 * half * cs * ss;  // phi_s in [0, 2 pi): symmetric about the plane of incidence
  };
  return integrator.integrate(inner, theta_breaks, 1e-10);
}

struct NamedSurface {
  const char* name;
  Surface surface;
};
const std::vector<NamedSurface> kSurfaces{
    {"polished", Surface{0.01, 5.0, 1.0}},      // g(0,0) = 0.016, narrow lobe
    {"intermediate", Surface{0.1, 2.0, 1.0}},   // g(0,0) = 1.6
    {"rough", Surface{0.5, 3.0, 1.0}},          // g(0,0) = 39, lobe spans the hemisphere
};

// Energy (F = 1): the scattered power K * integral of A cos ts dOmega equals the power the plane
// read of eq. 13 assigns, (1 - e^-g1) - D(g1) + D, with D and D(g1) from the quadrature above.
// In tis mode K * D equals the total integrated scatter 1 - e^-g(ti, ti) exactly.
TEST(Renormalization, HemisphericalScatterTimesKEqualsPlaneIntegralAndTis) {
  for (const NamedSurface& s : kSurfaces) {
    for (double angle : {0.0, 40.0, 75.0}) {
      const double ti = deg(angle);
      const double ci = std::cos(ti);
      const double hemisphere = hemisphere_integral(s.surface, ti);
      const double g1 = std::pow(2 * kPi * s.surface.sigma_over_lambda() * ci, 2);
      const double hemisphere_g1 = hemisphere_integral(s.surface, ti, g1);
      const double plane = -std::expm1(-g1) - hemisphere_g1 + hemisphere;
      const double tis = -std::expm1(-std::pow(4 * kPi * s.surface.sigma_over_lambda() * ci, 2));

      const RenormalizationParts parts = renormalization_direct(s.surface, ti, KMode::plane);
      const double k_tis = renormalization_direct(s.surface, ti, KMode::tis).k;
      const double plane_error = std::fabs(parts.k * hemisphere - plane) / plane;
      const double tis_error = std::fabs(k_tis * hemisphere - tis) / tis;
      std::cout << "[ measured ] " << s.name << " ti=" << angle << ": D(quadrature) " << hemisphere << " vs library "
                << parts.disk << " (rel " << std::fabs(parts.disk - hemisphere) / hemisphere << "), K " << parts.k
                << ", K_tis " << k_tis << ", plane error " << plane_error << ", tis error " << tis_error << "\n";
      EXPECT_LE(plane_error, 1e-4) << s.name << " ti=" << angle << ": K D = " << parts.k * hemisphere
                                   << ", plane integral " << plane;
      EXPECT_LE(tis_error, 1e-4) << s.name << " ti=" << angle << ": K_tis D = " << k_tis * hemisphere << ", TIS " << tis;
      EXPECT_NEAR(parts.total_scatter, tis, 1e-14 + 1e-12 * tis);
    }
  }
}

// Short correlation lengths (l_c/lambda <= 1, lobes as wide as the disk), at incidence angles where
// the library's radial panels once ended just short of the unit circle along some azimuths: D off
// by 1.5e-5 at sigma_s/lambda = 1, l_c/lambda = 0.5, 31.699 deg, 2.8e-6 at (0.3, 0.3, 3.567 deg)
// (found by tools/audit/asf_reference_audit.py against its own quadrature of eq. 13).
TEST(Renormalization, DiskIntegralOfWideLobesMatchesTheIndependentQuadrature) {
  const struct {
    Surface surface;
    double angle;
  } cases[] = {{Surface{1.0, 0.5, 1.0}, 31.699112}, {Surface{0.3, 0.3, 1.0}, 3.566568}, {Surface{0.5, 1.0, 0.8}, 56.170113}};
  for (const auto& c : cases) {
    const double hemisphere = hemisphere_integral(c.surface, deg(c.angle));
    const double disk = renormalization_direct(c.surface, deg(c.angle), KMode::plane).disk;
    std::cout << "[ measured ] sigma/lambda " << c.surface.sigma_over_lambda() << ", l_c/lambda " << c.surface.lc_over_lambda()
              << ", ti " << c.angle << ": D relative difference " << std::fabs(disk / hemisphere - 1.0) << "\n";
    EXPECT_NEAR(disk / hemisphere, 1.0, 1e-7) << c.angle;  // was 1.5e-5, 2.8e-6, 1.0e-6
  }
}

// Near grazing the distance to the unit circle has a kink of width ~cos ti at azimuth pi/2 (and the
// rough lobe a layer of width ~lambda/(2 pi sigma_s) in cos ts at the circle): the default rule
// within a few 1e-6 of one 4x finer in both directions at 89.9 deg, for a very rough surface and a
// very narrow lobe, both modes (before the graded panels: 8.7e-5 and 5.6e-6).
TEST(Renormalization, DefaultRuleConvergedAtGrazing) {
  const RenormalizationQuadrature finer{4 * RenormalizationQuadrature{}.azimuth_nodes, 4 * RenormalizationQuadrature{}.radial_nodes};
  for (const Surface& surface : {Surface{3.0, 1.0, 0.5}, Surface{0.02, 500.0, 0.5}}) {
    for (const KMode mode : {KMode::plane, KMode::tis}) {
      for (const double angle : {89.0, 89.9}) {
        const double k = renormalization_direct(surface, deg(angle), mode).k;
        const double k_finer = renormalization_direct(surface, deg(angle), mode, finer).k;
        EXPECT_NEAR(k / k_finer, 1.0, 1e-5) << surface.sigma_over_lambda() << " " << angle;
      }
    }
  }
}

TEST(Renormalization, PlaneKIsAtLeastOneOverAnglesAndSurfaces) {
  int checked = 0;
  for (double sigma : {0.0, 0.003, 0.05, 0.2, 1.0}) {
    for (double lc : {0.3, 2.0, 30.0}) {
      for (double angle = 0.0; angle <= 89.5; angle += 4.5) {
        const double k = renormalization_direct(Surface{sigma, lc, 1.0}, deg(angle), KMode::plane).k;
        ASSERT_TRUE(std::isfinite(k)) << "sigma=" << sigma << " lc=" << lc << " ti=" << angle;
        ASSERT_GE(k, 1.0) << "sigma=" << sigma << " lc=" << lc << " ti=" << angle;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 5 * 3 * 20);
}

// At normal incidence a narrow lobe (l_c/lambda >> 1) lies deep inside the unit disk: nothing is
// evanescent, K = 1; and the disk holds all of the scatter, so K_tis - 1 is the variation of g over
// the lobe, ~ E[1 - cos ts] ~ <eta^2>/2 <= 1/(pi l_c/lambda)^2 (m = 1 Gaussian: <eta^2> = 1/(pi L)^2).
TEST(Renormalization, KIsOneAtNormalIncidenceForNarrowLobes) {
  for (double lc : {10.0, 100.0, 1000.0}) {
    for (double sigma : {0.001, 0.01, 0.05}) {
      const Surface surface{sigma, lc, 1.0};
      const double k = renormalization_direct(surface, 0.0, KMode::plane).k;
      EXPECT_NEAR(k, 1.0, 1e-9) << "sigma=" << sigma << " lc=" << lc;
      const double k_tis = renormalization_direct(surface, 0.0, KMode::tis).k;
      EXPECT_NEAR(k_tis, 1.0, 1.0 / std::pow(kPi * lc, 2)) << "sigma=" << sigma << " lc=" << lc;
    }
  }
}

TEST(Renormalization, TisModeIsTotalScatterOverDisk) {
  // K_tis = (1 - e^-g(ti,ti)) / D with D the same disk integral the plane mode uses.
  for (const NamedSurface& s : kSurfaces) {
    for (double angle : {0.0, 30.0, 60.0, 85.0}) {
      const RenormalizationParts plane = renormalization_direct(s.surface, deg(angle), KMode::plane);
      const RenormalizationParts tis = renormalization_direct(s.surface, deg(angle), KMode::tis);
      const double ci = std::cos(deg(angle));
      const double expected = -std::expm1(-std::pow(4 * kPi * s.surface.sigma_over_lambda() * ci, 2)) / plane.disk;
      EXPECT_NEAR(tis.k, expected, 1e-13 * expected) << s.name << " ti=" << angle;
      EXPECT_EQ(tis.disk, plane.disk);
    }
  }
}

TEST(Renormalization, MirrorSurfaceHasKOne) {
  for (KMode mode : {KMode::plane, KMode::tis}) {
    const RenormalizationParts parts = renormalization_direct(Surface{0.0, 1.0, 0.5}, deg(60), mode);
    EXPECT_EQ(parts.k, 1.0);
    EXPECT_EQ(parts.disk, 0.0);
  }
}

TEST(Renormalization, RejectsBadSurfaceAndAngle) {
  auto parameter_of = [](const Surface& surface, double theta) -> std::string {
    try {
      renormalization_direct(surface, theta, KMode::plane);
    } catch (const InvalidArgument& e) {
      return e.parameter();
    }
    return "accepted";
  };
  EXPECT_EQ(parameter_of(Surface{-0.1, 1.0, 0.5}, 0.1), "sigma_s");
  EXPECT_EQ(parameter_of(Surface{0.1, 0.0, 0.5}, 0.1), "lc");
  EXPECT_EQ(parameter_of(Surface{0.1, 1.0, -0.5}, 0.1), "wavelength");
  EXPECT_EQ(parameter_of(Surface{0.1, 1.0, 0.5}, std::nan("")), "theta_i");
  EXPECT_EQ(parameter_of(Surface{0.1, 1.0, 0.5}, 2.0), "theta_i");
}

// The K table against the direct computation between its nodes (at a quarter and three quarters
// of every interval up to 89.5 deg).
double max_table_error(const Surface& surface, KMode mode, double* worst_angle) {
  const RenormalizationTable table(surface, mode);
  const std::vector<double>& nodes = table.node_angles();
  double worst = 0;
  for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
    for (double fraction : {0.25, 0.75}) {
      const double ti = nodes[i] + fraction * (nodes[i + 1] - nodes[i]);
      if (ti > deg(89.5)) continue;
      const double direct = renormalization_direct(surface, ti, mode).k;
      const double error = std::fabs(table(ti) - direct) / direct;
      if (error > worst) {
        worst = error;
        *worst_angle = ti * 180.0 / kPi;
      }
    }
  }
  return worst;
}

// Bound: the table interpolates smooth factors of K (ln D and the outside fraction) by cubic
// Hermite with fourth-order slopes, so its own error is O(h^4): measured <= 4e-6 from polished to
// rough and for l_c/lambda up to 1e4; the direct quadrature it is compared with is itself only
// converged to ~1e-6 (RenormalizationQuadrature's note). 1e-5 leaves room for both, 10x below
// the 1e-4 the brief asks for.
TEST(RenormalizationTable, MatchesDirectBetweenNodesTo1e5) {
  std::vector<NamedSurface> surfaces = kSurfaces;
  surfaces.push_back({"narrow-lobe", Surface{0.001, 1000.0, 1.0}});
  for (const NamedSurface& s : surfaces) {
    for (KMode mode : {KMode::plane, KMode::tis}) {
      double angle = 0;
      const double error = max_table_error(s.surface, mode, &angle);
      std::cout << "[ measured ] K table (" << (mode == KMode::plane ? "plane" : "tis") << ") " << s.name
                << ": max relative error vs direct over [0, 89.5] deg " << error << " at " << angle << " deg\n";
      RecordProperty(std::string(s.name) + (mode == KMode::plane ? "_plane" : "_tis"), std::to_string(error));
      EXPECT_LE(error, 1e-5) << s.name << " worst at " << angle << " deg";
    }
  }
}

TEST(RenormalizationTable, ReproducesDirectAtNodes) {
  const Surface surface{0.1, 2.0, 1.0};
  for (KMode mode : {KMode::plane, KMode::tis}) {
    const RenormalizationTable table(surface, mode);
    const std::vector<double>& nodes = table.node_angles();
    for (std::size_t i : {std::size_t{0}, std::size_t{10}, nodes.size() / 2, nodes.size() - 2}) {
      const double direct = renormalization_direct(surface, nodes[i], mode).k;
      EXPECT_NEAR(table(nodes[i]), direct, 1e-13 * direct) << "node " << i;
      EXPECT_NEAR(table.node_values()[i], direct, 1e-13 * direct) << "node " << i;
    }
  }
}

TEST(RenormalizationTable, GrazingLimitIsOneInPlaneModeAndZeroInTisMode) {
  // At 90 deg g1 = g(ti, ti) = 0: nothing is evanescent (K = 1) and the TIS is 0 (K_tis = 0).
  const Surface surface{0.2, 2.0, 1.0};
  EXPECT_NEAR(RenormalizationTable(surface, KMode::plane)(0.5 * kPi), 1.0, 1e-12);
  EXPECT_NEAR(RenormalizationTable(surface, KMode::tis)(0.5 * kPi), 0.0, 1e-12);
}

TEST(RenormalizationTable, NarrowLobesGetMoreNodes) {
  EXPECT_EQ(RenormalizationTable::automatic_node_count(Surface{0.1, 2.0, 1.0}), RenormalizationTable::kDefaultNodes);
  EXPECT_GT(RenormalizationTable::automatic_node_count(Surface{0.001, 1000.0, 1.0}), RenormalizationTable::kDefaultNodes);
}

}  // namespace

namespace {
// The span lookup (node coordinate from the geometry's cos theta_i, same Hermite cubic) against
// operator() at theta_i = atan2(sin, cos) of each geometry, from normal incidence to 0.0001 deg
// below grazing, both modes, a narrow-lobe table (l_c/lambda = 1e3: more nodes) and a mirror.
TEST(RenormalizationTable, SpanLookupMatchesScalarLookup) {
  std::vector<ScatterGeometry> geos;
  for (int k = 0; k <= 20000; ++k) {
    const double ti = deg(89.9999) * k / 20000.0;
    geos.push_back(make_scatter_geometry({ti, 0.3, 2.0}));
  }
  std::vector<double> k_span(geos.size());
  for (const Surface& surface : {Surface{0.01, 5.0, 1.0}, Surface{0.1, 2.0, 1.0}, Surface{0.5, 3.0, 1.0},
                                 Surface{0.005, 500.0, 0.5}, Surface{0.0, 1.0, 0.5}}) {
    for (KMode mode : {KMode::plane, KMode::tis}) {
      const auto table = cached_renormalization_table(surface, mode);
      table->at_geometries(geos.data(), geos.size(), k_span.data());
      double worst = 0.0;
      for (std::size_t j = 0; j < geos.size(); ++j)
        worst = std::max(worst, libbrdf_test::relative_difference(
                                    k_span[j], (*table)(std::atan2(geos[j].sin_theta_i, geos[j].cos_theta_i))));
      EXPECT_LE(worst, 1e-13) << "sigma_s " << surface.sigma_s_um << " l_c " << surface.lc_um << " tis " << (mode == KMode::tis);
    }
  }
}
}  // namespace
