// The POV-Ray exporter's table, fit and include (issue #4), without POV-Ray (the renders are
// checked by test_exact_render.py).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "exporters/povray.h"
#include "libbrdf/error.h"
#include "libbrdf/materials.h"

namespace {

using namespace libbrdf;
using namespace libbrdf::povray;

SliceRequest gold(ModelKind model, double sigma_s_um, Direction light = {-1, 1, -1}, Direction view = {0, 0, -1}) {
  SliceRequest request;
  request.model = model;
  for (double wavelength : {0.65, 0.55, 0.45}) {
    ModelParameters p;
    p.sigma_s_um = sigma_s_um;
    p.lc_um = 2.0;
    p.wavelength_um = wavelength;
    p.index = material_index("Au", wavelength);
    request.channels.push_back(p);
  }
  request.light = light;
  request.view = view;
  request.error_samples = 4000;
  return request;
}

std::vector<Model> models_of(const SliceRequest& request) { return channel_models(request.model, request.channels); }

TEST(SlopePattern, MapsTheDotProductLikePovRay37) {
  // Measured with POV-Ray 3.7.0: s = 1/2 + asin(N.d)/pi (not the linear (1 + N.d)/2 of 3.5).
  EXPECT_DOUBLE_EQ(slope_value(1.0), 1.0);
  EXPECT_DOUBLE_EQ(slope_value(0.0), 0.5);
  EXPECT_DOUBLE_EQ(slope_value(-1.0), 0.0);
  EXPECT_NEAR(slope_value(0.5), 0.5 + 1.0 / 6.0, 1e-15);
  for (double x = -1.0; x <= 1.0; x += 0.125) EXPECT_NEAR(slope_inverse(slope_value(x)), x, 1e-15) << x;
}

TEST(SliceGeometry, RejectsZeroNonFiniteAndOppositeDirections) {
  auto parameter_of = [](const Direction& light, const Direction& view) -> std::string {
    try {
      make_slice_geometry(light, view);
    } catch (const InvalidArgument& e) {
      return e.parameter();
    }
    return "";
  };
  EXPECT_EQ(parameter_of({0, 0, 0}, {0, 0, -1}), "light-dir");
  EXPECT_EQ(parameter_of({0, 1, 0}, {0, 0, 0}), "view-dir");
  EXPECT_EQ(parameter_of({0, NAN, 1}, {0, 0, -1}), "light-dir");
  EXPECT_EQ(parameter_of({0, 0, 1}, {0, 0, -1}), "light-dir");  // opposite: nothing is lit and seen
  const SliceGeometry g = make_slice_geometry({-2, 2, -2}, {0, 0, -3});
  EXPECT_NEAR(g.cos_theta_d * g.cos_theta_d - g.sin_theta_d * g.sin_theta_d, g.cos_2theta_d, 1e-15);
  EXPECT_NEAR(g.half[0] * g.half[0] + g.half[1] * g.half[1] + g.half[2] * g.half[2], 1.0, 1e-15);
}

TEST(SliceGeometry, AnglesFromTheTwoCosinesSatisfyEq5) {
  const SliceGeometry g = make_slice_geometry({-1, 1, -1}, {0, 0, -1});
  for (double a : {0.7, 0.9, 0.99})
    for (double t : {0.2, 0.5, 0.8}) {
      const double reach = g.sin_theta_d * std::sqrt(1 - a * a);
      const double u = g.cos_theta_d * a - reach + t * 2 * reach;  // inside the feasible interval
      const ScatterAngles angles = angles_at(g, a, u);
      const double cos_2theta_d = std::cos(angles.theta_i) * std::cos(angles.theta_s) +
                                  std::sin(angles.theta_i) * std::sin(angles.theta_s) * std::cos(angles.phi_s);
      EXPECT_NEAR(cos_2theta_d, g.cos_2theta_d, 1e-12) << "a " << a << " u " << u;
      EXPECT_NEAR(std::cos(angles.theta_i) + std::cos(angles.theta_s), 2 * g.cos_theta_d * a, 1e-12);
    }
}

TEST(HalfVectorSlice, FeasibleNodesHoldTheModelsRadiance) {
  const SliceRequest request = gold(ModelKind::mbk, 0.0275);
  const HalfVectorSlice slice = bake_half_vector_slice(request);
  const std::vector<Model> models = models_of(request);
  const SliceGeometry& g = slice.geometry;
  int checked = 0;
  for (std::size_t i = 0; i < slice.half_nodes.size(); ++i)
    for (std::size_t j = 0; j < slice.light_nodes.size(); ++j) {
      const double a = slice.half_nodes[i], u = slice.light_nodes[j];
      const double reach = g.sin_theta_d * std::sqrt(std::max(0.0, 1 - a * a));
      const double v = 2 * g.cos_theta_d * a - u;
      if (u < 1e-3 || v < 1e-3 || std::abs(u - g.cos_theta_d * a) > reach * (1 - 1e-9)) continue;
      for (int k = 0; k < 3; ++k) {
        const double expected = models[static_cast<std::size_t>(k)].evaluate(angles_at(g, a, u)) * u;
        EXPECT_NEAR(slice.value(k, i, j), expected, 1e-12 * std::abs(expected)) << "node " << i << "," << j;
      }
      ++checked;
    }
  EXPECT_GT(checked, 500);
}

TEST(HalfVectorSlice, RowsReachingTheTerminatorAreBlackThere) {
  const HalfVectorSlice slice = bake_half_vector_slice(gold(ModelKind::mbk, 0.275));
  int rows = 0;
  for (std::size_t i = 0; i < slice.half_nodes.size(); ++i) {
    if (slice.half_nodes[i] > slice.geometry.sin_theta_d) continue;  // N.L = 0 is reachable below a = sin theta_d
    for (int k = 0; k < 3; ++k) EXPECT_EQ(slice.value(k, i, 0), 0.0) << "row " << i;
    ++rows;
  }
  EXPECT_GE(rows, 2);  // at least a = 0 and a = sin(theta_d)
  // a = sin(theta_d) is a node, so no interval mixes rows that reach N.L = 0 with rows that do not.
  bool has_node = false;
  for (double a : slice.half_nodes) has_node = has_node || std::abs(a - slice.geometry.sin_theta_d) < 1e-12;
  EXPECT_TRUE(has_node);
}

// POV-Ray's interpolation (reproduced by lookup) against the model at random lit, visible normals,
// independent of the bake's own error measure.
void expect_lookup_accurate(const SliceRequest& request, double tolerance) {
  const HalfVectorSlice slice = bake_half_vector_slice(request);
  const std::vector<Model> models = models_of(request);
  const SliceGeometry& g = slice.geometry;
  EXPECT_LE(slice.half_nodes.size(), static_cast<std::size_t>(kMaxMapEntries));
  EXPECT_LE(slice.light_nodes.size(), static_cast<std::size_t>(kMaxMapEntries));
  EXPECT_LT(slice.error.max_relative, tolerance) << "the bake's own measure";
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss;
  double worst = 0.0;
  int counted = 0;
  for (int n = 0; n < 40000; ++n) {
    // Normals concentrated around H (the peak) and spread over the sphere, half each.
    const double spread = (n % 2 == 0) ? 0.1 : 10.0;
    double N[3] = {g.half[0] + spread * gauss(rng), g.half[1] + spread * gauss(rng), g.half[2] + spread * gauss(rng)};
    const double norm = std::sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
    for (double& c : N) c /= norm;
    const double a = N[0] * g.half[0] + N[1] * g.half[1] + N[2] * g.half[2];
    const double u = N[0] * g.light[0] + N[1] * g.light[1] + N[2] * g.light[2];
    const double v = N[0] * g.view[0] + N[1] * g.view[1] + N[2] * g.view[2];
    if (u < 1e-6 || v < 1e-6) continue;
    for (int k = 0; k < 3; ++k) {
      const double exact = models[static_cast<std::size_t>(k)].evaluate(angles_at(g, a, u)) * u;
      if (exact < 1e-3 * slice.peak[static_cast<std::size_t>(k)]) continue;
      worst = std::max(worst, std::abs(slice.lookup(k, a, u) - exact) / exact);
      ++counted;
    }
  }
  EXPECT_GT(counted, 1000);
  EXPECT_LT(worst, tolerance) << "over " << counted << " normal-channels";
}

TEST(HalfVectorSlice, PolishedPeakWithinHalfPercent) { expect_lookup_accurate(gold(ModelKind::mbk, 0.0011), 0.005); }
TEST(HalfVectorSlice, RoughLobeWithinHalfPercent) { expect_lookup_accurate(gold(ModelKind::mbk, 0.275), 0.005); }
TEST(HalfVectorSlice, BkAtAnotherLightWithinHalfPercent) {
  expect_lookup_accurate(gold(ModelKind::bk, 0.0275, {0.9, 0.35, -0.6}), 0.005);
}
TEST(HalfVectorSlice, MicrofacetNearRetroreflectionWithinHalfPercent) {
  // theta_d -> 0: light and view nearly coincide, the feasible rows shrink to points.
  expect_lookup_accurate(gold(ModelKind::microfacet, 0.275, {0.02, 0.01, -1}), 0.005);
}

TEST(HalfVectorSlice, RejectsOutOfRangeResolutionAndNonBrdfModels) {
  SliceRequest request = gold(ModelKind::mbk, 0.03);
  request.entries = kMaxMapEntries + 1;
  try {
    bake_half_vector_slice(request);
    FAIL() << "entries beyond POV-Ray 3.7's map limit accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_EQ(e.parameter(), "resolution");
  }
  request = gold(ModelKind::fresnel, 0.03);
  EXPECT_THROW(bake_half_vector_slice(request), InvalidArgument);
}

TEST(FinishFit, FittedBlinnLobesFollowPovRaysLightingAndMeetTheirMeasure) {
  const SliceRequest request = gold(ModelKind::mbk, 0.275);
  const HalfVectorSlice slice = bake_half_vector_slice(request);
  const FinishFit fit = fit_finish(slice, models_of(request));
  const double cd = slice.geometry.cos_theta_d;
  ASSERT_FALSE(fit.lobes.lobes.empty());
  EXPECT_EQ(fit.lobes.shape, libbrdf::fit::LobeShape::blinn);
  for (const libbrdf::fit::Lobe& l : fit.lobes.lobes) {
    EXPECT_GT(l.specular, 0.0) << "POV-Ray needs specular > 0";
    EXPECT_GE(l.roughness, 1.0) << "exponent n = 1/roughness";
    for (const auto& c : l.colour)
      for (double v : c) EXPECT_GE(v, 0.0) << "pigments are non-negative";
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(fit_radiance(fit, k, -0.1, 0.9, 0.9), 0.0) << "unlit side";
    EXPECT_GT(fit_radiance(fit, k, cd, cd, 1.0), fit_radiance(fit, k, cd * std::cos(0.3), cd, std::cos(0.3)));
    EXPECT_TRUE(std::isfinite(fit.peak_ratio[static_cast<std::size_t>(k)]));
  }
  // The fit's own measure (fit.h) on a rough gold lobe; the renders in test_fit_render.py check it
  // against POV-Ray per pixel.
  EXPECT_GT(fit.lobes.quality.values, 1000u);
  EXPECT_LT(fit.lobes.quality.median, 0.20);  // N.V-coloured Blinn/Phong lobes miss the lobe's theta_d dependence
  // R_spec -> 1 at grazing (F -> 1, g -> 0); min is R_spec at normal incidence, tiny when rough.
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(fit.reflection_max[static_cast<std::size_t>(k)], 1.0);
    EXPECT_LT(fit.reflection_min[static_cast<std::size_t>(k)], 1e-6);
  }
}

TEST(Include, IsGuardedPrefixedAndWithinPovRaysMapLimit) {
  const SliceRequest request = gold(ModelKind::mbk, 0.0275);
  const HalfVectorSlice slice = bake_half_vector_slice(request);
  const FinishFit fit = fit_finish(slice, models_of(request));
  const std::string text = include_text("Gold", request.model, request.channels, slice, fit);
  for (const char* needle : {"#ifndef(Gold_Inc_Temp)", "#declare Gold_Inc_Temp = version;", "#version 3.7;",
                             "#ifndef(Gold_Irradiance) #declare Gold_Irradiance = 1; #end",
                             "#declare Gold_Exact = texture", "#declare Gold_Fit = texture",
                             "#declare Gold_Fit_Lobe_1 = texture", "#declare Gold_Fit_Error_P95",
                             "#declare Gold_Light_Direction", "#declare Gold_View_Direction",
                             "#version Gold_Inc_Temp;", "emission Gold_Irradiance",
                             "#declare Gold_Fit_Sun_Angle_Deg = array[6] {0, 30, 60, 90, 120, 140};",
                             "#declare Gold_Fit_Error_Median_By_Angle = array[5] {",
                             "#declare Gold_Fit_Error_P95_By_Angle = array[5] {"})
    EXPECT_NE(text.find(needle), std::string::npos) << needle;
  // The error per band of sun-camera angle (fit.h): measured on pixels in every band, and the
  // header's line for each band quotes it.
  ASSERT_EQ(fit.lobes.by_sun_angle.size(), 5u);
  for (const libbrdf::fit::SunAngleQuality& band : fit.lobes.by_sun_angle) {
    EXPECT_GT(band.quality.values, 100u) << band.from_deg << "-" << band.to_deg << " deg";
    EXPECT_LE(band.quality.median, band.quality.p95);
    char line[96];
    std::snprintf(line, sizeof line, "//     %g-%g deg: median %.3g%%", band.from_deg, band.to_deg, 100.0 * band.quality.median);
    EXPECT_NE(text.find(line), std::string::npos) << line;
  }
  // Every map line: one outer entry holding <= 256 inner entries.
  std::istringstream lines(text);
  std::string line;
  std::size_t outer = 0;
  while (std::getline(lines, line)) {
    // NAME_Exact's table rows (the Fit lobes' pigments are colour maps over the view slope).
    if (line.find("color_map") == std::string::npos || line.find("_View_Direction") != std::string::npos) continue;
    ++outer;
    std::size_t inner = 0;
    for (std::size_t p = line.find(" rgb "); p != std::string::npos; p = line.find(" rgb ", p + 1)) ++inner;
    EXPECT_EQ(inner, slice.light_nodes.size());
    EXPECT_LE(inner, static_cast<std::size_t>(kMaxMapEntries));
  }
  EXPECT_EQ(outer, slice.half_nodes.size());
  EXPECT_EQ(text.find("nan"), std::string::npos);
  EXPECT_EQ(text.find("inf"), std::string::npos);
}

TEST(Include, NameMustBeAPovRayIdentifierPrefix) {
  validate_include_name("Gold_2");
  for (const std::string& bad : std::vector<std::string>{"", "2Gold", "Gold-2", "Gold 2", std::string(25, 'a')}) {
    try {
      validate_include_name(bad);
      FAIL() << "accepted '" << bad << "'";
    } catch (const InvalidArgument& e) {
      EXPECT_EQ(e.parameter(), "name");
    }
  }
}

}  // namespace
