// Table coordinates of a span of geometries in SIMD (Google Highway, run-time dispatch): the
// half/difference angles of half_difference_angles() (lut.cpp, MERL's half-vector frame) and
// theta_i, from the dot products of ScatterGeometry with one vector arctangent per angle and no
// branch per query (lut_internal.h: detail::table_angles). The records are read a vector at a
// time by transposition (geometry_records-inl.h) and the four angles stored interleaved: no
// structure-of-arrays copy in or out (3-channel 48^3 lookups, CPU time in one run: 23.7 -> 22.7-23.0 ns).
//
// Every angle lies in [0, pi] and is atan2(y, x) with y >= 0, written without atan2 as
//   a = atan(min(y, |x|) / max(y, |x|))          in [0, pi/4]
//   a -> pi/2 - a  where y > |x|,   a -> pi - a  where x < 0,
// so that the arctangent (Highway's polynomial of hn::Atan, hwy/contrib/math, 2 ulp) only sees
// arguments in [0, 1].
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "table_angles_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <cfloat>
#include <limits>

#include "geometry_records-inl.h"  // LoadRecords
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
  // hn::Atan's own polynomial on [0, 1] (hwy::impl, Debian's Highway 1.0.3): hn::Atan divides 1 by
  // its argument or by 1 in every lane to fold |x| > 1, a division that an argument already in
  // [0, 1] does not need; there the two give the same bits (3-channel lookups 37.5 -> 35.6 ns).
  const V a = hn::impl::AtanImpl<double>().AtanPoly(d, hn::Div(hn::Min(y, ax), big));
  const V folded = hn::IfThenElse(hn::Gt(y, ax), hn::Sub(hn::Set(d, 0.5 * kPi), a), a);
  return hn::IfThenElse(hn::Lt(x, hn::Zero(d)), hn::Sub(hn::Set(d, kPi), folded), folded);
}

// The table coordinates of one vector of geometries (records read by transposition), stored
// interleaved into `lanes` TableAngles.
template <class D>
HWY_INLINE void TableAnglesOfVector(D d, const ScatterGeometry* geos, TableAngles* out) {
  using V = hn::Vec<D>;
  V trig[6];
  LoadRecords(d, geos, 6, trig);
  const V ci = trig[kCosI], si = trig[kSinI], cs = trig[kCosS], ss = trig[kSinS];
  // Half vector along i + s, i = (sin ti, 0, cos ti), s = (sin ts cos phi_s, sin ts sin phi_s, cos ts).
  const V hx = hn::MulAdd(ss, trig[kCosPhi], si);
  const V hy = hn::Mul(ss, trig[kSinPhi]);
  const V hz = hn::Add(ci, cs);
  const V h_xy = hn::Sqrt(hn::MulAdd(hx, hx, hn::Mul(hy, hy)));
  const V inv_norm = hn::Div(hn::Set(d, 1.0), hn::Sqrt(hn::MulAdd(h_xy, h_xy, hn::Mul(hz, hz))));
  // phi_h is undefined at theta_h = 0; (cos, sin) = (1, 0) there, as in lut.cpp.
  const auto has_azimuth = hn::Gt(h_xy, hn::Zero(d));
  const V inv_xy = hn::IfThenElseZero(has_azimuth, hn::Div(hn::Set(d, 1.0), hn::Max(h_xy, hn::Set(d, DBL_MIN))));
  const V cos_phi_h = hn::IfThenElse(has_azimuth, hn::Mul(hx, inv_xy), hn::Set(d, 1.0));
  const V sin_phi_h = hn::Mul(hy, inv_xy);
  const V cos_h = hn::Mul(hz, inv_norm), sin_h = hn::Mul(h_xy, inv_norm);
  // d = R_y(-theta_h) R_z(-phi_h) i: the incident direction in the half-vector frame.
  const V tx = hn::Mul(si, cos_phi_h), ty = hn::Neg(hn::Mul(si, sin_phi_h));
  const V dx = hn::MulSub(tx, cos_h, hn::Mul(ci, sin_h));
  const V dz = hn::MulAdd(tx, sin_h, hn::Mul(ci, cos_h));
  const V d_xy = hn::Sqrt(hn::MulAdd(dx, dx, hn::Mul(ty, ty)));
  static_assert(sizeof(TableAngles) == 4 * sizeof(double), "TableAngles: four doubles");
  hn::StoreInterleaved4(UpperHalfAngle(d, h_xy, hz), UpperHalfAngle(d, d_xy, dz),
                        UpperHalfAngle(d, hn::Abs(ty), dx),  // phi_d folded by the mirror symmetry
                        UpperHalfAngle(d, si, ci), d, reinterpret_cast<double*>(out));
}

// theta_i alone (the same arithmetic as TableAnglesOfVector's); the other three angles NaN.
template <class D>
HWY_INLINE void ThetaIOfVector(D d, const ScatterGeometry* geos, TableAngles* out) {
  alignas(64) double theta_i[HWY_MAX_BYTES / sizeof(double)];
  hn::Store(UpperHalfAngle(d, Field(d, geos, kSinI), Field(d, geos, kCosI)), d, theta_i);
  constexpr double kUnread = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t j = 0; j < hn::Lanes(d); ++j) out[j] = TableAngles{kUnread, kUnread, kUnread, theta_i[j]};
}

// of_vector(d, geos, out) over the span: whole vectors, then the remainder through a padded copy
// (padding repeats the last geometry).
template <class OfVector>
void ForEachVector(const ScatterGeometry* geos, std::size_t count, TableAngles* out, const OfVector& of_vector) {
  const hn::ScalableTag<double> d;
  const std::size_t lanes = hn::Lanes(d);
  std::size_t k = 0;
  for (; k + lanes <= count; k += lanes) of_vector(d, geos + k, out + k);
  if (k < count) {
    constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
    ScatterGeometry pad[kMaxLanes];
    TableAngles angles[kMaxLanes];
    for (std::size_t j = 0; j < lanes; ++j) pad[j] = geos[std::min(k + j, count - 1)];
    of_vector(d, pad, angles);
    std::copy(angles, angles + (count - k), out + k);
  }
}

void TableAnglesSpan(const ScatterGeometry* geos, std::size_t count, TableAngles* out) {
  ForEachVector(geos, count, out, [](auto d, const ScatterGeometry* g, TableAngles* o) { TableAnglesOfVector(d, g, o); });
}

void ThetaISpan(const ScatterGeometry* geos, std::size_t count, TableAngles* out) {
  ForEachVector(geos, count, out, [](auto d, const ScatterGeometry* g, TableAngles* o) { ThetaIOfVector(d, g, o); });
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf::detail {
HWY_EXPORT(TableAnglesSpan);
HWY_EXPORT(ThetaISpan);
void table_angles(const ScatterGeometry* geos, std::size_t count, TableAngles* out) {
  if (count > 0) HWY_DYNAMIC_DISPATCH(TableAnglesSpan)(geos, count, out);
}
void table_theta_i(const ScatterGeometry* geos, std::size_t count, TableAngles* out) {
  if (count > 0) HWY_DYNAMIC_DISPATCH(ThetaISpan)(geos, count, out);
}
}  // namespace libbrdf::detail
#endif
