#include "libbrdf/beckmann_kirchhoff.h"

#include <cmath>

namespace libbrdf {

double bk_geometric_factor_eq26(const ScatterGeometry& geo) {
  const double numerator = 1.0 + geo.cos_theta_i * geo.cos_theta_s + geo.sin_theta_i * geo.sin_theta_s * geo.cos_phi_s;
  const double ratio = numerator / (geo.cos_theta_i * (geo.cos_theta_i + geo.cos_theta_s));
  return ratio * ratio;
}

double bk_geometric_factor_eq27(const ScatterGeometry& geo) {
  const double cd2 = geo.cos_theta_d * geo.cos_theta_d, ch2 = geo.cos_theta_h * geo.cos_theta_h;
  return cd2 / (geo.cos_theta_i * geo.cos_theta_i * ch2);
}

double s_term(const ScatterGeometry& geo) {
  const double sum = geo.cos_theta_i + geo.cos_theta_s;
  const double ch2 = geo.cos_theta_h * geo.cos_theta_h;
  return 4.0 * geo.cos_theta_i * geo.cos_theta_s * ch2 * ch2 / (sum * sum);
}

double inverse_s_term_eq28(const ScatterGeometry& geo) {
  return geo.cos_theta_d * geo.cos_theta_d / (geo.cos_theta_i * geo.cos_theta_s * geo.cos_theta_h * geo.cos_theta_h);
}

double relative_difference_rd(const Complex& permittivity, const ScatterGeometry& geo) {
  const double two_f_over_q = 2.0 * fresnel_reflectance(permittivity, geo.cos_theta_d) /
                              stover_q(permittivity, geo).q_paper();
  return std::abs(two_f_over_q - s_term(geo)) / two_f_over_q;
}

}  // namespace libbrdf
