// NAME_Fit: a native POV-Ray 3.7 finish least-squares fitted to the slice's exact radiance.
//
// POV-Ray 3.7.0's lighting, per parallel light of colour E (checked against renders, see
// tests/povray/): diffuse d c (N.L)^brilliance E and Blinn specular S (N.H)^(1/roughness) Cs E,
// both only where N.L > 0, with Cs = 1 + metallic (1 - F_m)(c - 1) and the empirical weight
// F_m = clamp(0.014567225 / (x - 1.12)^2 - 0.011612903, 0, 1), x = acos(N.L) / (pi/2)
// (POV-Ray's "metallic"); variable reflection min + (max - min)(1 - cos theta)^falloff.
#include <cmath>
#include <limits>
#include <random>

#include "exporters/povray.h"
#include "povray_internal.h"

namespace libbrdf::povray {

using namespace detail;  // NOLINT: shared pieces of the exporter

namespace {

double metallic_weight(double n_dot_l) {
  const double x = std::acos(std::clamp(n_dot_l, -1.0, 1.0)) / (0.5 * kPi);
  return std::clamp(0.014567225 / ((x - 1.12) * (x - 1.12)) - 0.011612903, 0.0, 1.0);
}

struct Sample {
  double u, a, weight, metallic;
  std::array<double, 3> exact;
};

// Lit, visible normals weighted as pixels of a sphere seen along V: target measure N.V dOmega.
// alpha (angle from H) is drawn half uniformly in cos(alpha), half uniformly in alpha (the peak),
// so the weight is N.V / pdf_Omega with pdf_Omega = (sin a / 2 + 1/pi) / (2 pi sin a).
std::vector<Sample> sphere_samples(const SliceGeometry& g, const std::vector<Model>& models, int count,
                                   std::uint64_t seed) {
  const SliceRadiance radiance(g, models);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Sample> samples;
  std::array<double, 3> r{};
  for (int n = 0; n < count; ++n) {
    const double alpha = (n % 2 == 0) ? std::acos(uniform(rng)) : 0.5 * kPi * uniform(rng);
    const NormalCosines c = normal_at(g, alpha, 2.0 * kPi * uniform(rng));
    if (models.size() > r.size() || !radiance.evaluate(c.a, c.u, r.data())) continue;
    const double v = 2.0 * g.cos_theta_d * c.a - c.u;
    const double sin_alpha = std::sin(alpha);
    const double weight = v * 2.0 * kPi * sin_alpha / (0.5 * sin_alpha + 1.0 / kPi);
    samples.push_back({c.u, c.a, weight, metallic_weight(c.u), r});
  }
  return samples;
}

struct LobeFit {
  double objective = std::numeric_limits<double>::infinity();
  std::array<double, 3> p{};  // specular x pigment per channel
  double s = 0.0, w = 0.0, n = 1.0;
};

// For a fixed exponent n and diffuse-to-specular ratio w the fit is linear in (p_k = S c_k, S):
//   R_k ~ p_k X + S Y,  X = w u + (1 - F_m) a^n,  Y = F_m a^n.
// The normal equations give p_k = (b_k - B S) / A and S from the channel sum.
struct Moments {
  double uu = 0, uz = 0, zz = 0, uy = 0, zy = 0, yy = 0, rr = 0;
  std::array<double, 3> ur{}, zr{}, yr{};
};

Moments moments(const std::vector<Sample>& samples, double n, int channels) {
  Moments m;
  for (const Sample& s : samples) {
    const double lobe = std::pow(s.a, n);
    const double z = (1.0 - s.metallic) * lobe, y = s.metallic * lobe, w = s.weight;
    m.uu += w * s.u * s.u;
    m.uz += w * s.u * z;
    m.zz += w * z * z;
    m.uy += w * s.u * y;
    m.zy += w * z * y;
    m.yy += w * y * y;
    for (int k = 0; k < channels; ++k) {
      const auto ku = static_cast<std::size_t>(k);
      m.ur[ku] += w * s.u * s.exact[ku];
      m.zr[ku] += w * z * s.exact[ku];
      m.yr[ku] += w * y * s.exact[ku];
      m.rr += w * s.exact[ku] * s.exact[ku];
    }
  }
  return m;
}

LobeFit solve(const Moments& m, double n, double w, int channels) {
  LobeFit fit;
  const double A = w * w * m.uu + 2.0 * w * m.uz + m.zz;
  const double B = w * m.uy + m.zy;
  const double C = m.yy;
  if (!(A > 0.0)) return fit;
  std::array<double, 3> b{}, e{};
  double sum_b = 0.0, sum_e = 0.0;
  for (int k = 0; k < channels; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    b[ku] = w * m.ur[ku] + m.zr[ku];
    e[ku] = m.yr[ku];
    sum_b += b[ku];
    sum_e += e[ku];
  }
  const double denominator = channels * (C - B * B / A);
  double s = 0.0;
  if (denominator > 1e-12 * std::max(C, 1e-300)) s = (sum_e - B / A * sum_b) / denominator;
  double objective = m.rr;
  for (int k = 0; k < channels; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    fit.p[ku] = std::max(0.0, (b[ku] - B * s) / A);
  }
  if (!(s > 0.0)) {
    // S undetermined (F_m ~ 0 over the lobe) or its optimum negative: POV-Ray needs S > 0, so take
    // S = max p (pigment <= 1) and let the objective below count what the F_m term then adds.
    s = std::max({fit.p[0], fit.p[1], fit.p[2], 1e-300});
  }
  for (int k = 0; k < channels; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    const double p = fit.p[ku];
    objective += p * p * A + 2.0 * p * s * B + s * s * C - 2.0 * p * b[ku] - 2.0 * s * e[ku];
  }
  fit.objective = objective;
  fit.s = s;
  fit.w = w;
  fit.n = n;
  return fit;
}

}  // namespace

double fit_radiance(const FinishFit& fit, int channel, double n_dot_l, double n_dot_h) {
  if (!(n_dot_l > 0.0)) return 0.0;
  const auto k = static_cast<std::size_t>(channel);
  const double c = fit.pigment[k];
  double value = fit.diffuse * c * n_dot_l;
  if (n_dot_h > 0.0 && fit.specular > 0.0) {
    const double f_m = metallic_weight(n_dot_l);
    value += fit.specular * std::pow(n_dot_h, 1.0 / fit.roughness) * (f_m + (1.0 - f_m) * c);
  }
  return value;
}

FinishFit fit_finish(const HalfVectorSlice& slice, const std::vector<Model>& models, std::uint64_t seed) {
  const int channels = static_cast<int>(models.size());
  if (channels != 3) throw InvalidArgument("wavelength", "the POV-Ray fit needs exactly 3 channels (R, G, B)");
  const SliceGeometry& g = slice.geometry;
  const std::vector<Sample> samples = sphere_samples(g, models, 10000, seed);

  // Exponent: coarse log scan, then golden-section refinement around the best; the diffuse ratio
  // is scanned for every exponent (cheap once the moments are known).
  std::vector<double> ratios{0.0};
  for (int i = 0; i <= 60; ++i) ratios.push_back(std::pow(10.0, -5.0 + 8.0 * i / 60.0));
  auto best_for = [&](double n) {
    const Moments m = moments(samples, n, channels);
    LobeFit best;
    for (double w : ratios) {
      const LobeFit f = solve(m, n, w, channels);
      if (f.objective < best.objective) best = f;
    }
    return best;
  };
  LobeFit best;
  double best_log_n = 0.0;
  for (int i = 0; i <= 72; ++i) {
    const double log_n = 6.0 * i / 72.0;  // n from 1 to 1e6
    const LobeFit f = best_for(std::pow(10.0, log_n));
    if (f.objective < best.objective) {
      best = f;
      best_log_n = log_n;
    }
  }
  double lo = best_log_n - 6.0 / 72.0, hi = best_log_n + 6.0 / 72.0;
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 30; ++it) {
    const double x1 = hi - golden * (hi - lo), x2 = lo + golden * (hi - lo);
    const LobeFit f1 = best_for(std::pow(10.0, x1)), f2 = best_for(std::pow(10.0, x2));
    if (f1.objective < best.objective) best = f1;
    if (f2.objective < best.objective) best = f2;
    if (f1.objective < f2.objective) hi = x2;
    else lo = x1;
  }

  FinishFit fit;
  fit.specular = best.s;
  fit.diffuse = best.w * best.s;
  fit.roughness = 1.0 / best.n;
  for (int k = 0; k < 3; ++k) fit.pigment[static_cast<std::size_t>(k)] = best.p[static_cast<std::size_t>(k)] / best.s;

  // Error on fresh samples (not the ones fitted).
  const std::vector<Sample> check = sphere_samples(g, models, 10000, seed + 1);
  double num = 0.0, den = 0.0;
  for (const Sample& s : check)
    for (int k = 0; k < channels; ++k) {
      const double d = fit_radiance(fit, k, s.u, s.a) - s.exact[static_cast<std::size_t>(k)];
      num += s.weight * d * d;
      den += s.weight * s.exact[static_cast<std::size_t>(k)] * s.exact[static_cast<std::size_t>(k)];
    }
  fit.relative_l2_error = den > 0.0 ? std::sqrt(num / den) : 0.0;
  for (int k = 0; k < channels; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    fit.peak_ratio[ku] = slice.peak[ku] > 0.0 ? fit_radiance(fit, k, g.cos_theta_d, 1.0) / slice.peak[ku] : 0.0;
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
