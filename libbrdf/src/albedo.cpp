#include "libbrdf/albedo.h"

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include "libbrdf/error.h"
#include "libbrdf/geometry.h"
#include "quadrature.h"  // distance_to_unit_circle

namespace libbrdf {
namespace {

using Rule = boost::math::quadrature::gauss_kronrod<double, 15>;
constexpr unsigned kMaxDepth = 12;

// Narrowest lobe width (direction cosines) the model can have at this surface: the first radial
// breakpoint is a quarter of it.
double lobe_width(const Model& model, double theta_i) {
  const Surface surface = model.surface();
  double width = 1.0 / (kPi * surface.lc_over_lambda());  // m = 1 Gaussian of eq. 11
  if (model_traits(model.kind()).albedo == AlbedoPath::facet_lobe && model.sigma_g() > 0.0)
    width = std::min(width, model.sigma_g() * std::max(std::cos(theta_i), 0.05));  // D_g in half-vector slopes
  return std::clamp(width, 1e-9, 1.0);
}

}  // namespace

DirectionalAlbedo directional_albedo(const Model& model, double theta_i, const AlbedoOptions& options) {
  if (!is_brdf(model.kind()))
    throw InvalidArgument("model", std::string(model_name(model.kind())) + " is not a BRDF: it has no albedo");
  require_polar_angle("theta_i", theta_i);
  if (!(options.relative_tolerance > 0.0 && options.relative_tolerance < 1e-2))
    throw InvalidArgument("tolerance", "albedo quadrature tolerance must be in (0, 0.01)");
  const double tol = options.relative_tolerance;
  const double s = std::sin(theta_i);
  const double first_panel = 0.25 * lobe_width(model, theta_i);
  std::atomic<long long> evaluations{0};

  // f at the point (rho, psi) around the specular direction. The scattered direction's
  // components in the plane: x = -(s + rho cos psi) (specular is phi_s = 180 deg), y = rho sin psi.
  auto brdf = [&](double rho, double psi) {
    const double x = -(s + rho * std::cos(psi)), y = rho * std::sin(psi);
    const double sin2_ts = x * x + y * y;
    if (!(sin2_ts < 1.0)) return 0.0;
    ScatterAngles angles{theta_i, std::asin(std::sqrt(sin2_ts)), std::atan2(y, x)};
    if (angles.phi_s < 0.0) angles.phi_s += 2.0 * kPi;
    ++evaluations;
    const double value = model.evaluate(make_scatter_geometry(angles));
    return std::isfinite(value) ? value : 0.0;
  };
  auto radial = [&](double psi) {
    const double rho_max = detail::distance_to_unit_circle(s, psi);
    double total = 0.0, a = 0.0, b = std::min(first_panel, rho_max), error = 0.0;  // radial estimates unused
    auto integrand = [&](double rho) { return brdf(rho, psi) * rho; };
    while (b < rho_max) {
      total += Rule::integrate(integrand, a, b, kMaxDepth, tol, &error);
      a = b;
      b = std::min(2.0 * b, rho_max);
    }
    const double u_max = std::sqrt(std::max(0.0, rho_max - a));
    total += Rule::integrate([&](double u) { return 2.0 * u * integrand(rho_max - u * u); }, 0.0, u_max, kMaxDepth, tol, &error);
    return total;
  };
  // Symmetric in y: twice the half plane psi in [0, pi], split at pi/2 (kink of rho_max at grazing).
  double error_a = 0.0, error_b = 0.0;
  const double half = Rule::integrate(radial, 0.0, 0.5 * kPi, kMaxDepth, tol, &error_a) +
                      Rule::integrate(radial, 0.5 * kPi, kPi, kMaxDepth, tol, &error_b);
  // The azimuth rules' estimates (the radial rules' errors show up in them as noise of the integrand).
  const double error_sum = 2.0 * (error_a + error_b);

  DirectionalAlbedo out;
  out.theta_i_rad = theta_i;
  out.lobe = 2.0 * half;
  out.specular = model.specular_reflectance(theta_i);
  out.total = out.lobe + out.specular;
  out.error_estimate = error_sum;
  out.evaluations = evaluations.load();
  return out;
}

}  // namespace libbrdf
