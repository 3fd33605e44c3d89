// Table coordinates of a span of geometries in SIMD (Google Highway, run-time dispatch): the
// half/difference angles of half_difference_angles() (lut.cpp, MERL's half-vector frame) and
// theta_i, from the dot products of ScatterGeometry with one vector arctangent per angle and no
// branch per query (lut_internal.h: detail::table_angles).
//
// Every angle lies in [0, pi] and is atan2(y, x) with y >= 0, written without atan2 as
//   a = atan(min(y, |x|) / max(y, |x|))          in [0, pi/4]
//   a -> pi/2 - a  where y > |x|,   a -> pi - a  where x < 0,
// so that hn::Atan (hwy/contrib/math, 2 ulp) only sees arguments in [0, 1].
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "table_angles_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <cfloat>

#include "lut_internal.h"

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// atan2(y, x) for y >= 0, branch-free (see the file comment).
template <class D, class V>
HWY_INLINE V UpperHalfAngle(D d, V y, V x) {
  const V ax = hn::Abs(x);
  const V big = hn::Max(hn::Max(y, ax), hn::Set(d, DBL_MIN));  // 0/0 -> 0/DBL_MIN = 0 at the origin
  const V a = hn::Atan(d, hn::Div(hn::Min(y, ax), big));
  const V folded = hn::IfThenElse(hn::Gt(y, ax), hn::Sub(hn::Set(d, 0.5 * kPi), a), a);
  return hn::IfThenElse(hn::Lt(x, hn::Zero(d)), hn::Sub(hn::Set(d, kPi), folded), folded);
}

// Structure-of-arrays inputs of one block (the AoS ScatterGeometry copied once per block).
struct GeometryBlock {
  static constexpr std::size_t kSize = 256;
  alignas(64) double cos_i[kSize], sin_i[kSize], cos_s[kSize], sin_s[kSize], cos_phi[kSize], sin_phi[kSize];
  alignas(64) double theta_h[kSize], theta_d[kSize], phi_d[kSize], theta_i[kSize];
};

void TableAnglesSpan(const ScatterGeometry* geos, std::size_t count, TableAngles* out) {
  const hn::ScalableTag<double> d;
  const std::size_t lanes = hn::Lanes(d);
  GeometryBlock b;
  for (std::size_t begin = 0; begin < count; begin += GeometryBlock::kSize) {
    const std::size_t n = std::min(GeometryBlock::kSize, count - begin);
    const std::size_t padded = (n + lanes - 1) / lanes * lanes;
    for (std::size_t k = 0; k < padded; ++k) {
      // Padding lanes repeat the last geometry: finite, discarded.
      const ScatterGeometry& g = geos[begin + std::min(k, n - 1)];
      b.cos_i[k] = g.cos_theta_i, b.sin_i[k] = g.sin_theta_i, b.cos_s[k] = g.cos_theta_s, b.sin_s[k] = g.sin_theta_s;
      b.cos_phi[k] = g.cos_phi_s, b.sin_phi[k] = g.sin_phi_s;
    }
    for (std::size_t k = 0; k < padded; k += lanes) {
      const auto ci = hn::Load(d, b.cos_i + k), si = hn::Load(d, b.sin_i + k);
      const auto cs = hn::Load(d, b.cos_s + k), ss = hn::Load(d, b.sin_s + k);
      // Half vector along i + s, i = (sin ti, 0, cos ti), s = (sin ts cos phi_s, sin ts sin phi_s, cos ts).
      const auto hx = hn::MulAdd(ss, hn::Load(d, b.cos_phi + k), si);
      const auto hy = hn::Mul(ss, hn::Load(d, b.sin_phi + k));
      const auto hz = hn::Add(ci, cs);
      const auto h_xy = hn::Sqrt(hn::MulAdd(hx, hx, hn::Mul(hy, hy)));
      const auto inv_norm = hn::Div(hn::Set(d, 1.0), hn::Sqrt(hn::MulAdd(h_xy, h_xy, hn::Mul(hz, hz))));
      // phi_h is undefined at theta_h = 0; (cos, sin) = (1, 0) there, as in lut.cpp.
      const auto has_azimuth = hn::Gt(h_xy, hn::Zero(d));
      const auto inv_xy = hn::IfThenElseZero(has_azimuth, hn::Div(hn::Set(d, 1.0), hn::Max(h_xy, hn::Set(d, DBL_MIN))));
      const auto cos_phi_h = hn::IfThenElse(has_azimuth, hn::Mul(hx, inv_xy), hn::Set(d, 1.0));
      const auto sin_phi_h = hn::Mul(hy, inv_xy);
      const auto cos_h = hn::Mul(hz, inv_norm), sin_h = hn::Mul(h_xy, inv_norm);
      // d = R_y(-theta_h) R_z(-phi_h) i: the incident direction in the half-vector frame.
      const auto tx = hn::Mul(si, cos_phi_h), ty = hn::Neg(hn::Mul(si, sin_phi_h));
      const auto dx = hn::MulSub(tx, cos_h, hn::Mul(ci, sin_h));
      const auto dz = hn::MulAdd(tx, sin_h, hn::Mul(ci, cos_h));
      const auto d_xy = hn::Sqrt(hn::MulAdd(dx, dx, hn::Mul(ty, ty)));
      hn::Store(UpperHalfAngle(d, h_xy, hz), d, b.theta_h + k);
      hn::Store(UpperHalfAngle(d, d_xy, dz), d, b.theta_d + k);
      hn::Store(UpperHalfAngle(d, hn::Abs(ty), dx), d, b.phi_d + k);  // phi_d folded by the mirror symmetry
      hn::Store(UpperHalfAngle(d, si, ci), d, b.theta_i + k);
    }
    for (std::size_t k = 0; k < n; ++k) out[begin + k] = {b.theta_h[k], b.theta_d[k], b.phi_d[k], b.theta_i[k]};
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf::detail {
HWY_EXPORT(TableAnglesSpan);
void table_angles(const ScatterGeometry* geos, std::size_t count, TableAngles* out) {
  if (count > 0) HWY_DYNAMIC_DISPATCH(TableAnglesSpan)(geos, count, out);
}
}  // namespace libbrdf::detail
#endif
