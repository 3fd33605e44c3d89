// NAME_Fit: Blinn lobes fitted to the model (fit.h, shape blinn) and the mirror reflection fitted
// to R_spec (povray.h).
//
// POV-Ray 3.7.0's lighting, per parallel light of colour E (checked against renders, see
// tests/povray/): Blinn specular S (N.H)^(1/roughness) Cs E where N.L > 0, with
// Cs = 1 + metallic (1 - F_m)(c - 1) and the empirical weight F_m(N.L) (fit::povray_metallic_weight);
// variable reflection min + (max - min)(1 - cos theta)^falloff.
#include <cmath>
#include <limits>

#include "exporters/povray.h"
#include "povray_internal.h"

namespace libbrdf::povray {

using namespace detail;  // NOLINT: shared pieces of the exporter

double fit_radiance(const FinishFit& fit, int channel, double n_dot_l, double n_dot_v, double n_dot_h) {
  return fit.lobes.radiance(channel, n_dot_l, n_dot_v, n_dot_h);
}

FinishFit fit_finish(const HalfVectorSlice& slice, const std::vector<Model>& models, double target_error) {
  const int channels = static_cast<int>(models.size());
  if (channels != 3) throw InvalidArgument("wavelength", "the POV-Ray fit needs exactly 3 channels (R, G, B)");
  const SliceGeometry& g = slice.geometry;
  FinishFit fit;
  fit::FitRequest request;
  request.shape = fit::LobeShape::blinn;
  request.target_error = target_error;
  request.max_lobes = 8;  // a lobe is one more texture of the average: cheap in POV-Ray
  // Exponents following N.V (fit.h, blinn_exponent_at_node). POV-Ray renders at random suns
  // (tests/povray/test_fit_random.py, docs/fit.md), median: bk Cu sigma_s 0.021 um at 64 deg 6.7% ->
  // 1.5%, bk-modified Cu sigma_s 0.014 um at 86 deg 14.9% -> 3.0%.
  request.view_dependent_roughness = true;
  fit.lobes = fit::fit_native_lobes(models, request);
  for (int k = 0; k < channels; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    // At N = H: N.L = N.V = cos(theta_d).
    fit.peak_ratio[ku] = slice.peak[ku] > 0.0 ? fit_radiance(fit, k, g.cos_theta_d, g.cos_theta_d, 1.0) / slice.peak[ku] : 0.0;
  }

  // Specular spike: R_spec(theta) = F(theta) exp(-g(theta, theta)) -> 1 at grazing (F -> 1, g -> 0),
  // so max = 1 and min = R_spec(0); the falloff is fitted with weight sin(theta) cos(theta).
  std::vector<double> thetas, weights;
  std::vector<std::array<double, 3>> r_spec;
  for (int i = 0; i < 180; ++i) {
    const double theta = (i + 0.5) * 0.5 * kPi / 180.0;
    thetas.push_back(theta);
    weights.push_back(std::sin(theta) * std::cos(theta));
    std::array<double, 3> r{};
    for (std::size_t k = 0; k < 3; ++k) r[k] = models[k].specular_reflectance(theta);
    r_spec.push_back(r);
  }
  for (int k = 0; k < 3; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    fit.reflection_min[ku] = models[ku].specular_reflectance(0.0);
    fit.reflection_max[ku] = 1.0;
  }
  auto reflection_error = [&](double falloff) {
    double sum = 0.0, weight_sum = 0.0;
    for (std::size_t i = 0; i < thetas.size(); ++i) {
      const double frac = std::pow(1.0 - std::cos(thetas[i]), falloff);
      for (std::size_t k = 0; k < 3; ++k) {
        const double d = fit.reflection_min[k] + (fit.reflection_max[k] - fit.reflection_min[k]) * frac - r_spec[i][k];
        sum += weights[i] * d * d;
        weight_sum += weights[i];
      }
    }
    return std::sqrt(sum / weight_sum);
  };
  double best_falloff = 1.0, best_error = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 400; ++i) {
    const double falloff = std::pow(10.0, -1.5 + 4.5 * i / 400.0);  // 0.03 .. 1000
    const double e = reflection_error(falloff);
    if (e < best_error) {
      best_error = e;
      best_falloff = falloff;
    }
  }
  fit.reflection_falloff = best_falloff;
  fit.reflection_rms_error = best_error;
  return fit;
}

}  // namespace libbrdf::povray
