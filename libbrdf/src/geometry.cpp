#include "libbrdf/geometry.h"

#include <algorithm>
#include <cmath>

#include "angular_simd.h"
#include "libbrdf/error.h"

namespace libbrdf {

namespace {
// The sines and cosines of the span version (make_scatter_geometries), so that a query gives the
// same bits whichever path derives its geometry (batch.h: every front end agrees); after the
// angles' validation. trig: cos, sin of theta_i, theta_s, phi_s.
void validated_scatter_trig(const ScatterAngles& angles, double* trig) {
  require_polar_angle("theta_i", angles.theta_i);
  require_polar_angle("theta_s", angles.theta_s);
  require_finite("phi_s", angles.phi_s);
  detail::scatter_trig(&angles, 1, trig);
}
}  // namespace

ScatterGeometry make_scatter_geometry(const ScatterAngles& angles) {
  double trig[6];
  validated_scatter_trig(angles, trig);
  return scatter_geometry_from_trig(trig[0], trig[1], trig[2], trig[3], trig[4], trig[5]);
}

namespace {
// sin and cos of a polar angle in [0, 90] degrees with the argument reduced in degrees: above
// 45 deg from the complement, so that a cosine near 0 is as precise as a sine near 0.
void polar_sin_cos_degrees(double degrees, double* sine, double* cosine) {
  if (degrees <= 45.0) {
    const double r = degrees_to_radians(degrees);
    *sine = std::sin(r), *cosine = std::cos(r);
  } else {
    const double r = degrees_to_radians(90.0 - degrees);  // exact subtraction (Sterbenz)
    *sine = std::cos(r), *cosine = std::sin(r);
  }
}
}  // namespace

ScatterGeometry make_scatter_geometry_degrees(double theta_i_deg, double theta_s_deg, double phi_s_deg) {
  // Validation and the azimuth's sine and cosine as the radian path (its rounding is harmless: it
  // moves eta_r^2 by ~1e-32 at the exact specular direction).
  double radian_trig[6];
  validated_scatter_trig(scatter_angles_from_degrees(theta_i_deg, theta_s_deg, phi_s_deg), radian_trig);
  double sin_i, cos_i, sin_s, cos_s;
  polar_sin_cos_degrees(theta_i_deg, &sin_i, &cos_i);
  polar_sin_cos_degrees(theta_s_deg, &sin_s, &cos_s);
  return scatter_geometry_from_trig(cos_i, sin_i, cos_s, sin_s, radian_trig[4], radian_trig[5]);
}

ScatterGeometry scatter_geometry_from_trig(double cos_theta_i, double sin_theta_i, double cos_theta_s,
                                           double sin_theta_s, double cos_phi_s, double sin_phi_s) {
  const double trig[6] = {cos_theta_i, sin_theta_i, cos_theta_s, sin_theta_s, cos_phi_s, sin_phi_s};
  ScatterGeometry geo;
  detail::geometries_from_trig(trig, 1, &geo);  // eqs 5, 6, 10 (angular_simd.cpp)
  return geo;
}

void make_scatter_geometries(const ScatterAngles* angles, std::size_t count, ScatterGeometry* geos) {
  detail::scatter_geometries(angles, count, geos);
}

double tan2_theta_h(const ScatterGeometry& geo) {
  const double sum = geo.cos_theta_i + geo.cos_theta_s;
  return geo.eta_r2 / (sum * sum);  // eq. 19
}

}  // namespace libbrdf
