#include "libbrdf/renormalization.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <tuple>

#include "libbrdf/error.h"
#include "libbrdf/geometry.h"
#include "libbrdf/mbk_series.h"
#include "poisson.h"
#include "quadrature.h"

namespace libbrdf {
namespace {

// Distance from the specular point (0, s) to the unit circle along azimuth psi (psi = 0 points
// to +beta, away from the normal's foot). Root of rho^2 + 2 s rho cos psi + s^2 - 1 = 0.
double distance_to_unit_circle(double s, double psi) {
  const double cos_psi = std::cos(psi), sin_psi = std::sin(psi);
  return std::max(0.0, -s * cos_psi + std::sqrt(std::max(0.0, 1.0 - s * s * sin_psi * sin_psi)));
}

// Disk integral D of the ASF with the true g(ti, ts): polar coordinates (rho, psi) centred on the
// specular point, where eta_r = rho exactly (eq. 10), so the Gaussian lobes are radial. The radial
// range is cut into panels growing geometrically from a quarter of the narrowest lobe width
// (m = 1: 1/(pi l_c/lambda)), so lobes from l_c/lambda ~ 1e3 to rough surfaces are resolved.
double disk_integral(const Surface& surface, double theta_i, const RenormalizationQuadrature& quad) {
  const double s = std::sin(theta_i), ci = std::cos(theta_i);
  const double lc_over_lambda = surface.lc_over_lambda();
  const double prefactor = kPi * lc_over_lambda * lc_over_lambda;
  const double sigma_over_lambda = surface.sigma_over_lambda();
  const double first_panel = 0.25 / (kPi * lc_over_lambda);
  const auto& radial_rule = detail::gauss_legendre(quad.radial_nodes);
  const auto& azimuth_rule = detail::gauss_legendre(quad.azimuth_nodes / 2);
  SeriesOptions series;
  series.relative_tolerance = 1e-13;

  auto radial_integral = [&](double psi) {
    const double rho_max = distance_to_unit_circle(s, psi);
    const double cos_psi = std::cos(psi);
    auto integrand = [&](double rho) {
      // cos ts of the scattered direction at (alpha, beta) = (rho sin psi, s + rho cos psi).
      const double cos2_ts = std::max(0.0, 1.0 - s * s - 2.0 * s * rho * cos_psi - rho * rho);
      const double g = roughness_g(sigma_over_lambda, ci, std::sqrt(cos2_ts));
      const double c = kPi * prefactor * rho * rho;
      return prefactor * mbk_series_sum(g, c, series) * rho;
    };
    double total = 0.0, a = 0.0, b = std::min(first_panel, rho_max);
    while (a < rho_max) {
      total += detail::integrate_gauss_legendre(radial_rule, a, b, integrand);
      a = b;
      b = std::min(2.0 * b, rho_max);
    }
    return total;
  };
  // Symmetric in alpha: twice the half disk. The azimuth range is split at pi/2, where the
  // boundary distance has a kink at grazing incidence.
  const double half = detail::integrate_gauss_legendre(azimuth_rule, 0.0, 0.5 * kPi, radial_integral) +
                      detail::integrate_gauss_legendre(azimuth_rule, 0.5 * kPi, kPi, radial_integral);
  return 2.0 * half;
}

// Integral outside the unit disk of the ASF with the constant g1, done per series term m in
// closed form radially: each term is a Poisson weight P(m; g1) times a unit-mass Gaussian of
// rho with 1/(2 variance) = pi^2 (l_c/lambda)^2 / m, whose mass beyond rho_max(psi) is
// exp(-a_m rho_max^2). No cancellation against the disk integral.
double outside_integral(const Surface& surface, double theta_i, const RenormalizationQuadrature& quad) {
  const double ci = std::cos(theta_i), s = std::sin(theta_i);
  const double g1 = roughness_g(surface.sigma_over_lambda(), ci, 0.0);
  if (!(g1 > 0.0)) return 0.0;
  const double lc_over_lambda = surface.lc_over_lambda();
  const double a1 = kPi * kPi * lc_over_lambda * lc_over_lambda;
  const auto& azimuth_rule = detail::gauss_legendre(quad.azimuth_nodes / 2);
  auto outside_fraction = [&](double m) {
    auto f = [&](double psi) {
      const double r = distance_to_unit_circle(s, psi);
      return std::exp(-a1 * r * r / m);
    };
    return (detail::integrate_gauss_legendre(azimuth_rule, 0.0, 0.5 * kPi, f) +
            detail::integrate_gauss_legendre(azimuth_rule, 0.5 * kPi, kPi, f)) / kPi;
  };
  // Poisson weights from the mode outward until they no longer matter against 1 - e^-g1.
  const int mode = std::max(1, static_cast<int>(std::floor(g1)));
  const double total_weight = -std::expm1(-g1);
  double sum = 0.0;
  for (int direction : {+1, -1}) {
    for (int m = (direction > 0 ? mode : mode - 1); m >= 1; m += direction) {
      const double weight = std::exp(detail::log_poisson_weight(m, g1));
      sum += weight * outside_fraction(m);
      if (weight < 1e-17 * total_weight && (direction < 0 || m > g1)) break;
    }
  }
  return sum;
}

}  // namespace

RenormalizationParts renormalization_direct(const Surface& surface, double theta_i, KMode mode,
                                            const RenormalizationQuadrature& quadrature) {
  validate_surface(surface);
  if (!std::isfinite(theta_i) || theta_i < 0.0 || theta_i > 0.5 * kPi)
    throw InvalidArgument("theta_i", "must be in [0, 90] degrees for K");
  RenormalizationParts parts;
  const double ci = std::cos(theta_i);
  parts.total_scatter = -std::expm1(-roughness_g(surface.sigma_over_lambda(), ci, ci));
  if (surface.sigma_s_um == 0.0) return parts;  // no scatter: K = 1 by convention
  parts.disk = disk_integral(surface, theta_i, quadrature);
  if (!(parts.disk > 0.0)) return parts;  // nothing scattered into the disk at all: K = 1
  if (mode == KMode::plane) {
    parts.outside = outside_integral(surface, theta_i, quadrature);
    parts.k = 1.0 + parts.outside / parts.disk;  // eq. 13 with the plane read of conventions.md
  } else {
    parts.k = parts.total_scatter / parts.disk;  // TIS renormalization (Krywonos et al. 2011)
  }
  return parts;
}

RenormalizationTable::RenormalizationTable(const Surface& surface, KMode mode, int nodes)
    : mode_(mode), step_(0.5 * kPi / (nodes - 1)), k_(nodes), slope_(nodes) {
  validate_surface(surface);
  tbb::parallel_for(0, nodes, [&](int i) {
    k_[i] = renormalization_direct(surface, std::min(0.5 * kPi, i * step_), mode).k;
  });
  // Fritsch-Carlson monotone cubic Hermite slopes: no overshoot near the steep grazing rise.
  std::vector<double> secant(nodes - 1);
  for (int i = 0; i + 1 < nodes; ++i) secant[i] = (k_[i + 1] - k_[i]) / step_;
  slope_[0] = secant[0];
  slope_[nodes - 1] = secant[nodes - 2];
  for (int i = 1; i + 1 < nodes; ++i) {
    if (secant[i - 1] * secant[i] <= 0.0) {
      slope_[i] = 0.0;
    } else {
      slope_[i] = 2.0 / (1.0 / secant[i - 1] + 1.0 / secant[i]);  // harmonic mean
    }
  }
}

double RenormalizationTable::operator()(double theta_i) const {
  const double x = std::clamp(theta_i / step_, 0.0, static_cast<double>(k_.size() - 1));
  const int i = std::min(static_cast<int>(x), static_cast<int>(k_.size()) - 2);
  const double t = x - i, t2 = t * t, t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  return h00 * k_[i] + h10 * step_ * slope_[i] + h01 * k_[i + 1] + h11 * step_ * slope_[i + 1];
}

std::shared_ptr<const RenormalizationTable> cached_renormalization_table(const Surface& surface, KMode mode) {
  using Key = std::tuple<double, double, int>;
  static std::mutex mutex;
  static std::map<Key, std::shared_ptr<const RenormalizationTable>> cache;
  const Key key{surface.sigma_over_lambda(), surface.lc_over_lambda(), static_cast<int>(mode)};
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = cache.find(key);
    if (it != cache.end()) return it->second;
  }
  auto table = std::make_shared<const RenormalizationTable>(surface, mode);
  std::lock_guard<std::mutex> lock(mutex);
  return cache.emplace(key, std::move(table)).first->second;
}

}  // namespace libbrdf
