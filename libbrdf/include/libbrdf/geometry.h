#pragma once
// Scattering geometry of Butler, Nauyoks & Marciniak, Opt. Express 23, 29100 (2015).
//
// Conventions (docs/conventions.md, "Angles and units"):
//   theta from the surface normal z; both directions point away from the surface;
//   phi_i = 0; in-plane forward (specular) scatter is phi_s = pi, back-scatter phi_s = 0.
//   Code works in radians; user-facing interfaces speak degrees.
//
// | symbol      | meaning                                      | eq. | unit |
// |-------------|----------------------------------------------|-----|------|
// | theta_i/s   | incident / scattered polar angle             | 1   | rad  |
// | phi_s       | scattered azimuth (phi_i = 0)                | 9   | rad  |
// | theta_d     | difference angle (incidence on the facet)    | 5   | rad  |
// | theta_h     | half angle (bisector from the normal)        | 6   | rad  |
// | eta_r^2     | squared direction-cosine distance to specular| 10  | 1    |
// | g           | roughness (Rayleigh) parameter               | 12  | 1    |

#include <cstddef>

namespace libbrdf {

inline constexpr double kPi = 3.14159265358979323846;

// Inline: the batch loops convert every query (the same arithmetic everywhere, the same bits).
inline double degrees_to_radians(double degrees) { return degrees * (kPi / 180.0); }
inline double radians_to_degrees(double radians) { return radians * (180.0 / kPi); }

// One query: incident and scattered directions. Angles in radians.
struct ScatterAngles {
  double theta_i = 0.0;
  double theta_s = 0.0;
  double phi_s = kPi;
};

// Converts degrees (the CLI / file convention) to ScatterAngles in radians.
inline ScatterAngles scatter_angles_from_degrees(double theta_i_deg, double theta_s_deg, double phi_s_deg) {
  return {degrees_to_radians(theta_i_deg), degrees_to_radians(theta_s_deg), degrees_to_radians(phi_s_deg)};
}

// Everything the models need about one (theta_i, theta_s, phi_s), computed once.
struct ScatterGeometry {
  double cos_theta_i, sin_theta_i;
  double cos_theta_s, sin_theta_s;
  double cos_phi_s, sin_phi_s;
  double cos_2theta_d;  // eq. 5
  double cos_theta_d;   // sqrt((1 + cos 2theta_d)/2), >= 0
  double cos_theta_h;   // eq. 6: (cos ti + cos ts) / (2 cos theta_d)
  double eta_r2;        // eq. 10: sin^2 ti + sin^2 ts + 2 sin ti sin ts cos phi_s
};

// Validates (theta in [0, pi/2), all finite) and derives the quantities above.
// Throws InvalidArgument naming theta_i, theta_s or phi_s.
ScatterGeometry make_scatter_geometry(const ScatterAngles& angles);

// The same from angles in degrees (the CLI and Python convention), with the polar angles' sines and
// cosines from their arguments reduced in degrees (above 45 deg, from the complement 90 - theta,
// exact in floating point): cos theta near 90 deg keeps its relative precision, which a radian
// theta cannot carry (its rounding, ~1e-16 rad, is 1.1e-3 of cos(89.99999999999 deg) = 1.7e-13).
// Same validation. The degree batches (batch.h) use it for polar angles above kGrazingDegrees.
ScatterGeometry make_scatter_geometry_degrees(double theta_i_deg, double theta_s_deg, double phi_s_deg);
// Below this polar angle the radian path's cos theta is within ~1e-16 / cos(89.9 deg) = 6e-14.
inline constexpr double kGrazingDegrees = 89.9;

// The derived quantities (eqs 5, 6, 10) from the sines and cosines of theta_i, theta_s, phi_s:
// what make_scatter_geometry does after its trigonometry (no validation).
ScatterGeometry scatter_geometry_from_trig(double cos_theta_i, double sin_theta_i, double cos_theta_s,
                                           double sin_theta_s, double cos_phi_s, double sin_phi_s);

// geos[k] = make_scatter_geometry(angles[k]) for k < count (the same bits), without the
// validation (callers validate first: evaluate_batch). Both take their sines and cosines from one
// SIMD routine (Google Highway, 3 ulp; within a few 1e-16 of the C library's,
// tests/cpp/test_geometry.cpp), so that every path gives a query the same geometry.
void make_scatter_geometries(const ScatterAngles* angles, std::size_t count, ScatterGeometry* geos);

// tan^2 theta_h from eq. 17; equals eta_r^2 / (cos ti + cos ts)^2 (eq. 19).
double tan2_theta_h(const ScatterGeometry& geo);

// eq. 12: g = (2 pi sigma_s / lambda)^2 (cos ti + cos ts)^2, with sigma_s/lambda dimensionless.
// Inline: the batch paths compute it per query, next to the kernel table's lookup.
inline double roughness_g(double sigma_s_over_lambda, double cos_theta_i, double cos_theta_s) {
  const double k = 2.0 * kPi * sigma_s_over_lambda * (cos_theta_i + cos_theta_s);
  return k * k;
}

}  // namespace libbrdf
