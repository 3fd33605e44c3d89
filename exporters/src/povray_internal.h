#pragma once
// Pieces shared by the POV-Ray exporter's sources (not installed): vector helpers, the exact
// radiance of a slice, the feasible interval of a table row and normals around H.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "exporters/povray.h"
#include "libbrdf/error.h"

namespace libbrdf::povray::detail {

using Vec3 = std::array<double, 3>;

inline double dot(const Vec3& p, const Vec3& q) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; }

inline Vec3 unit(const Direction& d, const char* parameter) {
  const Vec3 v{d.x, d.y, d.z};
  const double norm = std::sqrt(dot(v, v));
  if (!std::isfinite(norm) || norm < 1e-12)
    throw InvalidArgument(parameter, "must be a finite non-zero vector X,Y,Z");
  return {v[0] / norm, v[1] / norm, v[2] / norm};
}

// Interval of u = N.L reachable by a lit (u >= 0), visible (N.V >= 0), real unit normal with N.H = a.
// N = a H + b D + e E (D = (L - V)/|L - V|, E completing the frame) gives u = cd a + sd b with
// b^2 <= 1 - a^2 (the "fold", where N lies in the plane of L and V), and N.V = cd a - sd b.
struct FeasibleInterval {
  double lo, hi;
  bool terminator;  // lo = 0 is reached: the row ends in the cut to black at N.L = 0
  bool horizon;     // hi = 2 cd a is reached: N.V = 0 (silhouette), where f may diverge
};

inline FeasibleInterval feasible_u(const SliceGeometry& g, double a) {
  const double reach = g.sin_theta_d * std::sqrt(std::max(0.0, 1.0 - a * a));
  const double fold_lo = g.cos_theta_d * a - reach, fold_hi = g.cos_theta_d * a + reach;
  const double horizon_u = 2.0 * g.cos_theta_d * a;
  FeasibleInterval f{std::max(0.0, fold_lo), std::min(fold_hi, horizon_u), fold_lo <= 0.0, fold_hi >= horizon_u};
  if (f.hi < f.lo) f.hi = f.lo;
  return f;
}

// Exact radiance per unit irradiance for every channel. Returns false outside lit, visible normals
// (u or N.V below kMinCosine: the models reject theta = 90 deg, which acos reaches below ~1e-16);
// the terminator u = 0 itself is handled by the callers (R = 0 there).
inline constexpr double kMinCosine = 1e-9;

class SliceRadiance {
 public:
  SliceRadiance(const SliceGeometry& geometry, const std::vector<Model>& models) : g_(geometry), models_(models) {}

  bool evaluate(double a, double u, double* out) const {
    const double v = 2.0 * g_.cos_theta_d * a - u;
    if (!(u > kMinCosine) || !(v > kMinCosine)) return false;
    const ScatterAngles angles = angles_at(g_, a, u);
    for (std::size_t k = 0; k < models_.size(); ++k) out[k] = models_[k].evaluate(angles) * std::min(u, 1.0);
    return true;
  }
  // Inside the domain where table errors are stated (lut.h): both polar angles <= 85 deg. Within a
  // few degrees of the horizon N.V = 0 (silhouette pixels) a linear interpolant of the values that
  // fall to 0 there has O(1) relative error at any resolution.
  bool in_error_domain(double a, double u) const {
    const double v = 2.0 * g_.cos_theta_d * a - u;
    return u >= domain_cosine_ && v >= domain_cosine_;
  }
  int channels() const { return static_cast<int>(models_.size()); }
  const SliceGeometry& geometry() const { return g_; }

 private:
  const SliceGeometry& g_;
  const std::vector<Model>& models_;
  double domain_cosine_ = std::cos(degrees_to_radians(kErrorThetaLimitDeg));
};

// A normal given by its angle alpha from H and azimuth psi around H (psi = 0 towards L).
struct NormalCosines {
  double a, u;
};
inline NormalCosines normal_at(const SliceGeometry& g, double alpha, double psi) {
  const double b = std::sin(alpha) * std::cos(psi);
  return {std::cos(alpha), g.cos_theta_d * std::cos(alpha) + g.sin_theta_d * b};
}

}  // namespace libbrdf::povray::detail
