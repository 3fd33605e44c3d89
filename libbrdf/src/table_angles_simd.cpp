// Table coordinates of a span of geometries in SIMD (Google Highway, run-time dispatch): the
// half/difference angles of half_difference_angles() (lut.cpp, MERL's half-vector frame) and
// theta_i, from the dot products of ScatterGeometry with one vector arctangent per angle
// (UpperHalfAngle: upper_half_angle-inl.h) and no branch per query (lut_internal.h:
// detail::table_angles). The records are read a vector at a time by transposition
// (geometry_records-inl.h) and the four angles stored interleaved: no structure-of-arrays copy in
// or out (3-channel 48^3 lookups, CPU time in one run: 23.7 -> 22.7-23.0 ns).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "table_angles_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <cfloat>

#include "geometry_records-inl.h"  // LoadRecords
#include "lut_internal.h"
#include "upper_half_angle-inl.h"  // UpperHalfAngle

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Whether every lane of every vector given is finite.
template <class D, class V>
HWY_INLINE bool AllFinite(D d, const V* v, std::size_t count) {
  auto finite = hn::IsFinite(v[0]);
  for (std::size_t f = 1; f < count; ++f) finite = hn::And(finite, hn::IsFinite(v[f]));
  return hn::AllTrue(d, finite);
}

// The table coordinates of one vector of geometries (records read by transposition), stored
// interleaved into `lanes` TableAngles. False (nothing stored) if a sine or cosine it reads is not
// finite: NaN would otherwise be washed into some node by the comparisons (a finite value, wrong).
template <class D>
HWY_INLINE bool TableAnglesOfVector(D d, const ScatterGeometry* geos, TableAngles* out) {
  using V = hn::Vec<D>;
  V trig[6];
  LoadRecords(d, geos, 6, trig);
  if (!AllFinite(d, trig, 6)) return false;
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
  return true;
}

// of_vector(d, geos, out) over the span: whole vectors, then the remainder through a padded copy
// (padding repeats the last geometry). Stops at the first vector of_vector refuses and returns
// the index of its first geometry with a non-finite field; count if none.
template <class OfVector>
std::size_t ForEachVector(const ScatterGeometry* geos, std::size_t count, TableAngles* out, const OfVector& of_vector) {
  const hn::ScalableTag<double> d;
  const std::size_t lanes = hn::Lanes(d);
  auto first_refused = [&](std::size_t k) {
    for (std::size_t j = k; j < std::min(k + lanes, count); ++j)
      if (!geometry_finite(geos[j])) return j;
    return count;  // not reached: a refused vector has such a geometry
  };
  std::size_t k = 0;
  for (; k + lanes <= count; k += lanes)
    if (!of_vector(d, geos + k, out + k)) return first_refused(k);
  if (k < count) {
    constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
    ScatterGeometry pad[kMaxLanes];
    TableAngles angles[kMaxLanes];
    for (std::size_t j = 0; j < lanes; ++j) pad[j] = geos[std::min(k + j, count - 1)];
    if (!of_vector(d, pad, angles)) return first_refused(k);
    std::copy(angles, angles + (count - k), out + k);
  }
  return count;
}

// The index of the first geometry with a non-finite field, or count: the records read as one
// array of doubles, a vector at a time (a std::isfinite per field and query cost ~3 ns of a
// 3-channel kernel lookup's ~33, a scalar test of the exponent bits ~5).
std::size_t FirstNonFiniteSpan(const ScatterGeometry* geos, std::size_t count) {
  static_assert(sizeof(ScatterGeometry) == 10 * sizeof(double), "ScatterGeometry: ten doubles");
  const hn::ScalableTag<double> d;
  const std::size_t lanes = hn::Lanes(d), doubles = 10 * count;
  const double* flat = &geos[0].cos_theta_i;
  std::size_t k = 0;
  for (; k + lanes <= doubles; k += lanes)
    if (!hn::AllTrue(d, hn::IsFinite(hn::LoadU(d, flat + k)))) break;
  for (std::size_t j = k / 10; j < count; ++j)  // from the record holding the vector's first double
    if (!geometry_finite(geos[j])) return j;
  return count;
}

std::size_t TableAnglesSpan(const ScatterGeometry* geos, std::size_t count, TableAngles* out) {
  return ForEachVector(geos, count, out, [](auto d, const ScatterGeometry* g, TableAngles* o) { return TableAnglesOfVector(d, g, o); });
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf::detail {
HWY_EXPORT(TableAnglesSpan);
HWY_EXPORT(FirstNonFiniteSpan);
std::size_t first_non_finite(const ScatterGeometry* geos, std::size_t count) {
  return count > 0 ? HWY_DYNAMIC_DISPATCH(FirstNonFiniteSpan)(geos, count) : 0;
}
std::size_t table_angles(const ScatterGeometry* geos, std::size_t count, TableAngles* out) {
  return count > 0 ? HWY_DYNAMIC_DISPATCH(TableAnglesSpan)(geos, count, out) : 0;
}
}  // namespace libbrdf::detail
#endif
