#include "libbrdf/geometry.h"

#include <algorithm>
#include <cmath>

#include "angular_simd.h"
#include "libbrdf/error.h"

namespace libbrdf {

ScatterGeometry make_scatter_geometry(const ScatterAngles& angles) {
  require_polar_angle("theta_i", angles.theta_i);
  require_polar_angle("theta_s", angles.theta_s);
  require_finite("phi_s", angles.phi_s);
  // The sines and cosines of the span version (make_scatter_geometries), so that a query gives
  // the same bits whichever path derives its geometry (batch.h: every front end agrees).
  double trig[6];
  detail::scatter_trig(&angles, 1, trig);
  return scatter_geometry_from_trig(trig[0], trig[1], trig[2], trig[3], trig[4], trig[5]);
}

ScatterGeometry scatter_geometry_from_trig(double cos_theta_i, double sin_theta_i, double cos_theta_s,
                                           double sin_theta_s, double cos_phi_s, double sin_phi_s) {
  ScatterGeometry geo{};
  geo.cos_theta_i = cos_theta_i;
  geo.sin_theta_i = sin_theta_i;
  geo.cos_theta_s = cos_theta_s;
  geo.sin_theta_s = sin_theta_s;
  geo.cos_phi_s = cos_phi_s;
  geo.sin_phi_s = sin_phi_s;
  const double sin_product = geo.sin_theta_i * geo.sin_theta_s;
  // eq. 5. Clamped to [-1, 1] only against rounding: |cos 2td| <= 1 holds exactly for real angles.
  geo.cos_2theta_d = std::clamp(geo.cos_theta_i * geo.cos_theta_s + sin_product * geo.cos_phi_s, -1.0, 1.0);
  geo.cos_theta_d = std::sqrt(0.5 * (1.0 + geo.cos_2theta_d));
  // eq. 6. cos td > 0 because both directions lie strictly above the horizon (ci + cs > 0).
  geo.cos_theta_h = std::min(1.0, (geo.cos_theta_i + geo.cos_theta_s) / (2.0 * geo.cos_theta_d));
  // eq. 10, written as |Delta alpha|^2 + |Delta beta|^2 (eq. 9) to keep it >= 0 under rounding.
  const double d_alpha = geo.sin_theta_s * geo.sin_phi_s;
  const double d_beta = geo.sin_theta_s * geo.cos_phi_s + geo.sin_theta_i;
  geo.eta_r2 = d_alpha * d_alpha + d_beta * d_beta;
  return geo;
}

void make_scatter_geometries(const ScatterAngles* angles, std::size_t count, ScatterGeometry* geos) {
  constexpr std::size_t kBlock = 256;
  double trig[6 * kBlock];
  for (std::size_t begin = 0; begin < count; begin += kBlock) {
    const std::size_t n = std::min(kBlock, count - begin);
    detail::scatter_trig(angles + begin, n, trig);
    for (std::size_t k = 0; k < n; ++k) {
      const double* t = trig + 6 * k;
      geos[begin + k] = scatter_geometry_from_trig(t[0], t[1], t[2], t[3], t[4], t[5]);
    }
  }
}

double tan2_theta_h(const ScatterGeometry& geo) {
  const double sum = geo.cos_theta_i + geo.cos_theta_s;
  return geo.eta_r2 / (sum * sum);  // eq. 19
}

double roughness_g(double sigma_s_over_lambda, double cos_theta_i, double cos_theta_s) {
  const double k = 2.0 * kPi * sigma_s_over_lambda * (cos_theta_i + cos_theta_s);
  return k * k;  // eq. 12
}

}  // namespace libbrdf
