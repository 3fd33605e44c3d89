// Internal, per SIMD target (Google Highway's -inl.h pattern: re-included once per target by
// foreach_target.h): atan2(y, x) for y >= 0 in lanes, without atan2 and without a branch per query.
// Shared by the table coordinates (table_angles_simd.cpp) and the kernel layout's K position
// (kernel_k_simd.cpp), so that both give theta_i the same bits.
//
// Every such angle lies in [0, pi] and is written as
//   a = atan(min(y, |x|) / max(y, |x|))          in [0, pi/4]
//   a -> pi/2 - a  where y > |x|,   a -> pi - a  where x < 0,
// so that the arctangent (Highway's polynomial of hn::Atan, hwy/contrib/math, 2 ulp) only sees
// arguments in [0, 1].
#if defined(LIBBRDF_UPPER_HALF_ANGLE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef LIBBRDF_UPPER_HALF_ANGLE_INL_H_
#undef LIBBRDF_UPPER_HALF_ANGLE_INL_H_
#else
#define LIBBRDF_UPPER_HALF_ANGLE_INL_H_
#endif

#include <cfloat>

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include "libbrdf/geometry.h"  // kPi

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

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#endif  // LIBBRDF_UPPER_HALF_ANGLE_INL_H_
