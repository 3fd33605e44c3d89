#include "libbrdf/microfacet.h"

#include <algorithm>
#include <cmath>

namespace libbrdf {

double gaussian_facet_distribution(double cos_theta_h, double sigma_g) {
  const double cos2 = cos_theta_h * cos_theta_h;
  const double tan2 = std::max(0.0, 1.0 - cos2) / cos2;
  const double two_var = 2.0 * sigma_g * sigma_g;
  return std::exp(-tan2 / two_var) / (kPi * two_var * cos2 * cos2);  // eq. 7
}

namespace {
// Smith Lambda for Gaussian slopes with per-axis slope deviation sigma_g (eq. 7 <=> Beckmann
// alpha = sqrt(2) sigma_g): Lambda(a) = (erf(a) - 1)/2 + exp(-a^2) / (2 a sqrt(pi)),
// a = cot(theta) / (sqrt(2) sigma_g). Lambda -> 0 at normal incidence (a -> inf).
double smith_lambda(double cos_theta, double sin_theta, double sigma_g) {
  if (sin_theta <= 0.0) return 0.0;
  const double a = cos_theta / (std::sqrt(2.0) * sigma_g * sin_theta);
  if (a > 26.0) return 0.0;  // erfc(26) ~ 1e-296: Lambda is 0 to double precision
  return 0.5 * (std::exp(-a * a) / (a * std::sqrt(kPi)) - std::erfc(a));
}
}  // namespace

double geometric_term(GeometricTerm term, const ScatterGeometry& geo, double sigma_g) {
  switch (term) {
    case GeometricTerm::none:
      return 1.0;
    case GeometricTerm::smith:
      return 1.0 / ((1.0 + smith_lambda(geo.cos_theta_i, geo.sin_theta_i, sigma_g)) *
                    (1.0 + smith_lambda(geo.cos_theta_s, geo.sin_theta_s, sigma_g)));
    case GeometricTerm::vgroove: {
      // Torrance & Sparrow (1967); Cook & Torrance (1982): v.h = i.h = cos theta_d.
      const double scale = 2.0 * geo.cos_theta_h / geo.cos_theta_d;
      return std::min({1.0, scale * geo.cos_theta_s, scale * geo.cos_theta_i});
    }
  }
  return 1.0;
}

double sigma_g_from_rough_surface(double sigma_s_um, double lc_um) { return std::sqrt(2.0) * sigma_s_um / lc_um; }

double sigma_g_from_polished_surface(double lc_um, double wavelength_um) {
  return wavelength_um / (kPi * lc_um * std::sqrt(2.0));
}

}  // namespace libbrdf
