// The models behind libbrdf::Model: reciprocity (Helmholtz), the original BK's non-reciprocity,
// the very-rough identity of eq. 29 (mbk-fg -> microfacet), the specular spike, and hard inputs
// for every model name (no NaN/Inf, no negative values), and the span path (evaluate_many) against
// evaluate() for every model.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "libbrdf/batch.h"
#include "libbrdf/error.h"
#include "libbrdf/fresnel.h"
#include "libbrdf/geometry.h"
#include "libbrdf/models.h"
#include "test_support.h"

namespace {

using namespace libbrdf;
using libbrdf_test::deg;
using libbrdf_test::relative_difference;

ModelParameters surface_parameters(double sigma, double lc, double wavelength, ComplexIndex index) {
  ModelParameters p;
  p.sigma_s_um = sigma;
  p.lc_um = lc;
  p.wavelength_um = wavelength;
  p.index = index;
  return p;
}

struct Case {
  const char* name;
  ModelParameters params;
};
std::vector<Case> reciprocity_cases() {
  return {{"polished-Al", surface_parameters(0.005, 1.0, 0.55, {1.0, 6.6})},
          {"intermediate-glass", surface_parameters(0.05, 1.5, 0.55, {1.5, 0.0})},
          {"rough-4+10i", surface_parameters(0.3, 2.0, 0.55, {4.0, 10.0})},
          {"very-rough-0.25+3i", surface_parameters(3.0, 20.0, 0.55, {0.25, 3.0})}};
}

// Random pairs over the upper hemisphere (fixed seed), in and out of the plane of incidence.
template <class Check>
void for_random_pairs(int count, Check&& check) {
  std::mt19937_64 rng(29100);
  std::uniform_real_distribution<double> polar(0.0, deg(88.0)), azimuth(0.0, 2 * kPi);
  for (int i = 0; i < count; ++i) {
    const double ti = polar(rng), ts = polar(rng);
    const double phi = (i % 5 == 0) ? kPi : azimuth(rng);
    check(ScatterAngles{ti, ts, phi}, ScatterAngles{ts, ti, phi});
  }
}

// Values below this fraction of the largest are compared absolutely (the far tails are ~1e-300).
constexpr double kTiny = 1e-280;

void expect_reciprocal(const Model& model, const char* label, bool divide_by_k) {
  int compared = 0;
  for_random_pairs(3000, [&](const ScatterAngles& a, const ScatterAngles& b) {
    double fa = model.evaluate(a), fb = model.evaluate(b);
    if (divide_by_k) {
      fa /= model.renormalization(a.theta_i);
      fb /= model.renormalization(b.theta_i);
    }
    if (std::max(fa, fb) < kTiny) return;
    ++compared;
    // 4e-12: the far tail (f ~ 1e-271 at c ~ 620) turns the few-ulp rounding of eta_r^2 (3-ulp
    // vector sines, make_scatter_geometry) into c times as much in exp(-c/m).
    ASSERT_LE(relative_difference(fa, fb), 4e-12)
        << label << " " << model_name(model.kind()) << ": f(" << a.theta_i << ", " << a.theta_s << ", " << a.phi_s
        << ") = " << fa << " but swapped " << fb;
  });
  EXPECT_GT(compared, 300) << label;
}

// mbk = K(ti) Qbar A: K depends on ti only and is not symmetric, so reciprocity holds for f / K(ti).
TEST(Reciprocity, MbkDividedByKOfIncidenceIsReciprocal) {
  for (const Case& c : reciprocity_cases()) expect_reciprocal(Model(ModelKind::mbk, c.params), c.name, true);
}

TEST(Reciprocity, MbkFgDividedByKOfIncidenceIsReciprocal) {
  for (const Case& c : reciprocity_cases()) {
    for (GeometricTerm term : {GeometricTerm::smith, GeometricTerm::vgroove, GeometricTerm::none}) {
      ModelParameters p = c.params;
      p.g_term = term;
      expect_reciprocal(Model(ModelKind::mbk_fg, p), c.name, true);
    }
  }
}

TEST(Reciprocity, MbkPolishedIsReciprocal) {
  for (const Case& c : reciprocity_cases()) expect_reciprocal(Model(ModelKind::mbk_polished, c.params), c.name, false);
}

TEST(Reciprocity, BkModifiedIsReciprocal) {
  for (const Case& c : reciprocity_cases()) expect_reciprocal(Model(ModelKind::bk_modified, c.params), c.name, false);
}

// With rho_s given (not K(ti)) the microfacet model is reciprocal for every G and a Lambertian part.
TEST(Reciprocity, MicrofacetWithGivenRhoSIsReciprocal) {
  for (const Case& c : reciprocity_cases()) {
    for (GeometricTerm term : {GeometricTerm::smith, GeometricTerm::vgroove, GeometricTerm::none}) {
      ModelParameters p = c.params;
      p.g_term = term;
      p.rho_s = 0.9;
      p.rho_d = 0.1;
      expect_reciprocal(Model(ModelKind::microfacet, p), c.name, false);
    }
  }
}

// eq. 26: F_bk^2 = (1 + cos 2td)^2 / (ci^2 (ci + cs)^2), so f_bk(ti, ts) / f_bk(ts, ti) = (cs/ci)^2.
TEST(Reciprocity, OriginalBkIsNotReciprocal) {
  const Model bk(ModelKind::bk, surface_parameters(0.05, 1.5, 0.55, {1.5, 0.0}));
  const double forward = bk.evaluate(ScatterAngles{deg(10), deg(60), kPi});
  const double swapped = bk.evaluate(ScatterAngles{deg(60), deg(10), kPi});
  const double expected_ratio = std::pow(std::cos(deg(60)) / std::cos(deg(10)), 2);
  EXPECT_GT(relative_difference(forward, swapped), 0.01) << forward << " vs " << swapped;
  EXPECT_NEAR(forward / swapped, expected_ratio, 1e-12 * expected_ratio);
}

// eq. 29 in libbrdf's convention (Qbar, rho_s = K): for a very rough surface the mbk-fg form with
// the rough ASF is exactly the microfacet model with sigma_g = sqrt(2) sigma_s / l_c (eq. 20) and
// rho_s = K. With the full series the two differ by the rough form's O(1/g) error.
TEST(Models, MbkFgTendsToMicrofacetForVeryRoughSurfacesEq29) {
  ModelParameters p = surface_parameters(10.0, 100.0, 1.0, {1.5, 0.0});
  p.sigma_g_mapping = SigmaGMapping::rough;
  p.tolerance = 0.0;  // always the series
  const Model fg(ModelKind::mbk_fg, p), micro(ModelKind::microfacet, p);
  int compared = 0;
  for (double ti : {0.0, 20.0, 45.0, 60.0}) {
    for (double ts = 0.0; ts < 80.0; ts += 2.5) {
      for (double phi : {180.0, 150.0, 90.0}) {
        const ScatterAngles a = scatter_angles_from_degrees(ti, ts, phi);
        const ScatterGeometry geo = make_scatter_geometry(a);
        const double u = tan2_theta_h(geo) * std::pow(p.lc_um.value() / (2 * p.sigma_s_um.value()), 2);  // c / g
        if (u > 4.0) continue;  // the lobe (values above e^-4 of the peak)
        const double g = roughness_g(10.0, geo.cos_theta_i, geo.cos_theta_s);
        // Sigma / rough = 1 + (u^2 - 4u + 2)/(2g) + O((1 + u)^4 / g^2) (delta method; at u = 0
        // the exact expansion is 1 + 1/g + 2/g^2 + 6/g^3 + ...).
        const double bound = (std::fabs(u * u - 4 * u + 2) / 2 + 3 * std::pow(1 + u, 4) / g) / g;
        ++compared;
        EXPECT_NEAR(fg.evaluate(a) / micro.evaluate(a), 1.0, bound)
            << "ti=" << ti << " ts=" << ts << " phi=" << phi << " g=" << g << " u=" << u;
      }
    }
  }
  EXPECT_GT(compared, 50);
}

// microfacet-q is microfacet with Qbar in place of F(td): their ratio is Qbar / F(td) at every
// geometry (rho_d = 0), and 1 at specular (Qbar = F there, eq. 22's 2F/Q = 1).
TEST(Models, MicrofacetQIsMicrofacetWithQbarForF) {
  for (const Case& c : reciprocity_cases()) {
    const Model micro(ModelKind::microfacet, c.params), micro_q(ModelKind::microfacet_q, c.params);
    const Complex eps = c.params.index->permittivity();
    int compared = 0;
    for_random_pairs(200, [&](const ScatterAngles& a, const ScatterAngles&) {
      const ScatterGeometry geo = make_scatter_geometry(a);
      const double f = micro.evaluate(a);
      if (!(f > kTiny)) return;
      const double ratio = stover_q(eps, geo).q_bar() / fresnel_reflectance(eps, geo.cos_theta_d);
      EXPECT_NEAR(micro_q.evaluate(a) / f, ratio, 1e-12 * ratio) << c.name << " " << a.theta_i << " " << a.theta_s << " " << a.phi_s;
      ++compared;
    });
    EXPECT_GT(compared, 100) << c.name;
    for (double t : {0.0, 20.0, 60.0}) {
      const ScatterAngles specular{deg(t), deg(t), kPi};
      EXPECT_NEAR(micro_q.evaluate(specular), micro.evaluate(specular), 1e-12 * micro.evaluate(specular)) << c.name << " " << t;
    }
  }
}

// The m = 0 term: R_spec(ti) = F(ti) exp(-g(ti, ti)).
TEST(Models, SpecularSpikeIsFresnelTimesExpMinusG) {
  const ComplexIndex index{0.25, 3.0};
  const Model mbk(ModelKind::mbk, surface_parameters(0.04, 2.0, 0.5, index));
  for (double ti : {0.0, 30.0, 70.0, 89.0}) {
    const double ci = std::cos(deg(ti));
    const double expected = fresnel_reflectance(index.permittivity(), ci) * std::exp(-std::pow(4 * kPi * 0.04 / 0.5 * ci, 2));
    EXPECT_NEAR(mbk.specular_reflectance(deg(ti)), expected, 1e-14) << ti;
  }
}

// ---------------------------------------------------------------------------------------------
// Hard inputs for every model name.

struct HardSurface {
  const char* name;
  ModelParameters params;
};

std::vector<HardSurface> hard_surfaces() {
  const double lambda = 0.5;
  // sigma with g(0, 0) = (4 pi sigma / lambda)^2 = target.
  auto sigma_for_g = [&](double target) { return std::sqrt(target) * lambda / (4 * kPi); };
  std::vector<HardSurface> out{
      {"g=1e-8", surface_parameters(sigma_for_g(1e-8), 1.0, lambda, {1.5, 0.0})},
      {"g=1e4", surface_parameters(sigma_for_g(1e4), 5.0, lambda, {1.5, 0.0})},
      {"n=4+10i", surface_parameters(0.05, 1.0, lambda, {4.0, 10.0})},
      {"n=0.25+3i", surface_parameters(0.05, 1.0, lambda, {0.25, 3.0})},
      {"n=0.8 (TIR)", surface_parameters(0.05, 1.0, lambda, {0.8, 0.0})},
      {"lc/lambda=1e3", surface_parameters(0.005, 1e3 * lambda, lambda, {1.5, 0.2})},
      {"lc/lambda=0.05", surface_parameters(0.05, 0.05 * lambda, lambda, {1.5, 0.0})},
      {"mirror sigma_s=0", surface_parameters(0.0, 1.0, lambda, {1.5, 1.0})},
  };
  HardSurface tis{"k-mode tis, rough", surface_parameters(0.2, 1.0, lambda, {1.5, 0.0})};
  tis.params.k_mode = KMode::tis;
  out.push_back(tis);
  HardSurface series_only{"tolerance 0", surface_parameters(0.1, 1.0, lambda, {1.5, 0.0})};
  series_only.params.tolerance = 0.0;
  out.push_back(series_only);
  return out;
}

std::vector<ScatterAngles> hard_angles() {
  std::vector<ScatterAngles> out;
  const std::vector<double> polar{0.0, 1e-6, 30.0, 60.0, 85.0, 89.9, 89.999};
  const std::vector<double> azimuth{0.0, 180.0, 360.0, -90.0, -180.0, -725.5, 45.0, 1e4};
  for (double ti : polar)
    for (double ts : polar)
      for (double phi : azimuth) out.push_back(scatter_angles_from_degrees(ti, ts, phi));
  return out;
}

TEST(HardCases, EveryModelIsFiniteAndNonNegative) {
  const std::vector<ScatterAngles> angles = hard_angles();
  int evaluated = 0;
  for (const HardSurface& s : hard_surfaces()) {
    for (ModelKind kind : all_models()) {
      const Model model(kind, s.params);
      for (const ScatterAngles& a : angles) {
        if (kind == ModelKind::k && a.theta_s != 0.0) continue;  // k depends on theta_i only (slow, direct)
        const double value = model.evaluate(a);
        ++evaluated;
        ASSERT_TRUE(std::isfinite(value) && value >= 0.0)
            << model_name(kind) << " on " << s.name << " at (" << a.theta_i << ", " << a.theta_s << ", " << a.phi_s
            << ") rad = " << value;
      }
      const double spike = model.specular_reflectance(deg(89.9));
      ASSERT_TRUE(std::isfinite(spike) && spike >= 0.0 && spike <= 1.0) << model_name(kind) << " on " << s.name;
      const double k = model.renormalization(deg(89.9));
      ASSERT_TRUE(std::isfinite(k) && k >= 0.0) << model_name(kind) << " on " << s.name;
    }
  }
  EXPECT_GT(evaluated, 50000);
}

TEST(HardCases, PhiPeriodicAndEvenInAzimuth) {
  const Model mbk(ModelKind::mbk, surface_parameters(0.05, 1.0, 0.5, {1.7, 5.0}));
  for (double phi : {0.0, 30.0, 180.0, 271.0}) {
    const double base = mbk.evaluate(scatter_angles_from_degrees(35, 50, phi));
    EXPECT_LE(relative_difference(base, mbk.evaluate(scatter_angles_from_degrees(35, 50, phi + 360))), 1e-12) << phi;
    EXPECT_LE(relative_difference(base, mbk.evaluate(scatter_angles_from_degrees(35, 50, -phi))), 1e-12) << phi;
  }
}

// sigma_s = 0 is a perfect mirror (conventions.md, "Domain"): A = 0, every diffuse BRDF is 0 and
// the whole reflectance is the spike R_spec = F(ti).
TEST(HardCases, MirrorHasZeroAsfAndSpikeEqualToFresnel) {
  const ComplexIndex index{1.5, 1.0};
  const ModelParameters p = surface_parameters(0.0, 1.0, 0.5, index);
  for (ModelKind kind : {ModelKind::asf, ModelKind::mbk, ModelKind::mbk_polished, ModelKind::mbk_rough,
                         ModelKind::mbk_fg, ModelKind::bk, ModelKind::bk_modified, ModelKind::microfacet}) {
    const Model model(kind, p);
    for (const ScatterAngles& a : {scatter_angles_from_degrees(30, 30, 180), scatter_angles_from_degrees(0, 0, 0),
                                   scatter_angles_from_degrees(60, 20, 90)})
      EXPECT_EQ(model.evaluate(a), 0.0) << model_name(kind);
  }
  const Model mbk(ModelKind::mbk, p);
  for (double ti : {0.0, 45.0, 89.9}) {
    const FresnelSP rsp = fresnel_sp(index.permittivity(), std::cos(deg(ti)));
    EXPECT_NEAR(mbk.specular_reflectance(deg(ti)), 0.5 * (rsp.r_s + rsp.r_p), 1e-15) << ti;
  }
}

TEST(HardCases, InvalidParametersNameTheParameter) {
  auto parameter_of = [](ModelKind kind, const ModelParameters& p) -> std::string {
    try {
      Model model(kind, p);
    } catch (const InvalidArgument& e) {
      return e.parameter();
    }
    return "accepted";
  };
  const ModelParameters good = surface_parameters(0.05, 1.0, 0.5, {1.5, 0.0});
  ModelParameters p = good;
  p.sigma_s_um = -0.1;
  EXPECT_EQ(parameter_of(ModelKind::mbk, p), "sigma_s");
  p = good;
  p.sigma_s_um = std::nan("");
  EXPECT_EQ(parameter_of(ModelKind::mbk, p), "sigma_s");
  p = good;
  p.lc_um = 0.0;
  EXPECT_EQ(parameter_of(ModelKind::mbk, p), "lc");
  p = good;
  p.wavelength_um = -1.0;
  EXPECT_EQ(parameter_of(ModelKind::mbk, p), "wavelength");
  p = good;
  p.index = ComplexIndex{1.5, -1.0};
  EXPECT_EQ(parameter_of(ModelKind::mbk, p), "k");
  p = good;
  p.index.reset();
  EXPECT_EQ(parameter_of(ModelKind::bk, p), "n");
  p = good;
  p.lc_um.reset();
  EXPECT_EQ(parameter_of(ModelKind::asf, p), "lc");
  p = good;
  p.tolerance = 1.5;
  EXPECT_EQ(parameter_of(ModelKind::mbk, p), "tolerance");
  EXPECT_EQ(parameter_of(ModelKind::mbk, good), "accepted");

  try {
    model_from_name("mbk-smooth");
    ADD_FAILURE() << "unknown model accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.parameter(), "model");
  }
  for (ModelKind kind : all_models()) EXPECT_EQ(model_from_name(model_name(kind)), kind);
}


// ---------------------------------------------------------------------------------------------
// The span path (Model::evaluate_many: SIMD K, Qbar, F(theta_d); batched ASF) against evaluate().

TEST(SpanPath, EvaluateManyMatchesEvaluateForEveryModel) {
  std::vector<ScatterAngles> angles = hard_angles();
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> polar(0.0, deg(89.99)), azimuth(-kPi, kPi);
  for (int k = 0; k < 1500; ++k) angles.push_back({polar(rng), polar(rng), azimuth(rng)});
  std::vector<HardSurface> surfaces = hard_surfaces();
  surfaces.push_back({"kappa=1000", surface_parameters(0.05, 1.0, 0.5, {1.5, 1000.0})});
  HardSurface given_rho{"microfacet rho_s given", surface_parameters(0.05, 1.0, 0.5, {1.5, 0.1})};
  given_rho.params.rho_s = 0.7;
  given_rho.params.rho_d = 0.1;
  surfaces.push_back(given_rho);
  HardSurface table{"tolerance 1e-4 (kernel table)", surface_parameters(0.1, 2.0, 0.55, {0.2, 3.0})};
  table.params.tolerance = 1e-4;
  surfaces.push_back(table);
  for (const HardSurface& s : surfaces) {
    for (ModelKind kind : all_models()) {
      const Model model(kind, s.params);
      std::vector<ScatterGeometry> geos;
      for (const ScatterAngles& a : angles)
        if (kind != ModelKind::k || a.theta_s == 0.0) geos.push_back(make_scatter_geometry(a));  // k: direct, slow
      std::vector<double> asf(geos.size()), with_asf(geos.size()), without(geos.size());
      for (std::size_t j = 0; j < geos.size(); ++j) asf[j] = model.asf_at(geos[j]);
      model.evaluate_many(geos.data(), geos.size(), with_asf.data(), asf.data());
      model.evaluate_many(geos.data(), geos.size(), without.data());
      double worst_given = 0.0, worst_auto = 0.0;
      for (std::size_t j = 0; j < geos.size(); ++j) {
        const double given = model.evaluate(geos[j], asf[j]), automatic = model.evaluate(geos[j]);
        ASSERT_TRUE(std::isfinite(without[j]) && without[j] >= 0.0) << model_name(kind) << " on " << s.name;
        if (std::max(given, with_asf[j]) > kTiny) worst_given = std::max(worst_given, relative_difference(with_asf[j], given));
        if (std::max(automatic, without[j]) > kTiny) worst_auto = std::max(worst_auto, relative_difference(without[j], automatic));
      }
      // With the ASF given only the SIMD factors differ (a few ulp each); without it the ASFs of
      // asf_auto_batch and asf_auto are each within the tolerance of the series.
      // kappa = 1000 (|eps| = 1e6): Qbar at grazing is conditioned to ~1e-10 (test_fresnel.cpp).
      const double bound = s.params.index && s.params.index->kappa > 100.0 ? 3e-10 : 1e-12;
      EXPECT_LE(worst_given, bound) << model_name(kind) << " on " << s.name;
      EXPECT_LE(worst_auto, std::max(bound, 2.0 * s.params.tolerance)) << model_name(kind) << " on " << s.name;
    }
  }
}

// A query's value does not depend on the batch it is evaluated in (batch.h: a scalar call and an
// array call agree): alone, first, in the middle and last of 13 (whole vectors plus a remainder on
// every target), bit for bit, every model, on every Highway target this machine runs. F(theta_d)'s
// span once differed in its last bits (~1/3 of the queries of fresnel, mbk-fg, bk, bk-modified):
// its kernel was inlined twice and contracted differently (angular_simd.cpp: ForEachBlock).
TEST(SpanPath, ValueDependsOnItsOwnQueryOnlyForEveryModel) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> polar(0.0, deg(89.9)), azimuth(-kPi, kPi);
  std::vector<ScatterAngles> angles;
  for (int k = 0; k < 13 * 40; ++k) angles.push_back({polar(rng), polar(rng), azimuth(rng)});
  ModelParameters p = surface_parameters(0.1, 2.0, 0.55, {0.2, 3.0});
  p.rho_d = 0.1;
  libbrdf_test::for_each_simd_target([&](std::int64_t) {
    for (double tolerance : {1e-6, 1e-4}) {
      p.tolerance = tolerance;
      for (ModelKind kind : all_models()) {
        if (kind == ModelKind::k) continue;  // K's direct quadrature per query: slow, no span kernel
        ModelParameters q = p;
        if (kind != ModelKind::microfacet) q.rho_d = 0.0;
        const Model model(kind, q);
        for (std::size_t batch = 0; batch < angles.size(); batch += 13) {
          double together[13];
          evaluate_batch(model, angles.data() + batch, 13, together);
          for (std::size_t k : {0, 6, 12}) {
            double alone = 0.0;
            evaluate_batch(model, angles.data() + batch + k, 1, &alone);
            ASSERT_EQ(alone, together[k]) << model_name(kind) << " tol " << tolerance << " query " << batch + k;
          }
        }
      }
    }
  });
}

}  // namespace
