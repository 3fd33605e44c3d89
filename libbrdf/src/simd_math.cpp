// Vector arctangent over arrays (Google Highway, run-time dispatch): the one inverse-trigonometric
// function the table lookups need, evaluated for a whole batch of table coordinates at once
// (lut.cpp). hn::Atan: 2 ulp (hwy/contrib/math).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "simd_math.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include "simd_math.h"

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void AtanArray(const double* in, double* out, std::size_t count) {
  const hn::ScalableTag<double> d;
  const std::size_t n = hn::Lanes(d);
  std::size_t k = 0;
  for (; k + n <= count; k += n) hn::StoreU(hn::Atan(d, hn::LoadU(d, in + k)), d, out + k);
  if (k < count) {  // the remainder through a zero-padded vector
    alignas(64) double buffer[HWY_MAX_BYTES / sizeof(double)] = {};
    for (std::size_t j = k; j < count; ++j) buffer[j - k] = in[j];
    hn::Store(hn::Atan(d, hn::Load(d, buffer)), d, buffer);
    for (std::size_t j = k; j < count; ++j) out[j] = buffer[j - k];
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf::detail {
HWY_EXPORT(AtanArray);
void atan_array(const double* in, double* out, std::size_t count) { HWY_DYNAMIC_DISPATCH(AtanArray)(in, out, count); }
}  // namespace libbrdf::detail
#endif
