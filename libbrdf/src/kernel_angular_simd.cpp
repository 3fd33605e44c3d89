// The kernel layout's tabulated angular factor P~ (lut.h; lut.cpp: kernel_angular_factors) in SIMD
// lanes along phi_d (Google Highway, run-time dispatch): a Catmull-Rom stencil's four phi_d taps
// of a row are four adjacent floats wherever the stencil does not reach past the table's phi_d
// ends, so each of its 16 (theta_h, theta_d) rows is one load, weighted by w0 w1 into two 2-lane
// double accumulators, and the phi_d weights close the sum. The scalar loop did 64 multiply-adds
// per channel, each on a converted float; `perf` put 60% of a 3-channel lookup of a P~ table there.
// 3-channel lookups (bench_lookup, 54^3 P~ table, one CPU, three runs): 133-136 -> 106-110 ns with
// 8000 cached geometries, 142-145 -> 115-117 ns streaming 1e6. (Swapping two taps fails lut_cli:
// tried.)
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "kernel_angular_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <cstddef>

#include "lut_internal.h"

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void CatmullRomRows(const float* values, std::size_t channel_stride, int channel_count, const std::size_t* rows, const double* row_weights,
                    const double* phi_weights, double* out) {
#if HWY_TARGET == HWY_SCALAR  // one lane: the sum written out
  for (int c = 0; c < channel_count; ++c) {
    const float* channel = values + static_cast<std::size_t>(c) * channel_stride;
    double sum = 0.0;
    for (int r = 0; r < 16; ++r)
      for (int m = 0; m < 4; ++m) sum += row_weights[r] * phi_weights[m] * double(channel[rows[r] + m]);
    out[c] = sum;
  }
#else
  const hn::FixedTag<float, 4> df4;  // 128 bits: every vector target has them
  const hn::FixedTag<float, 2> df2;
  const hn::FixedTag<double, 2> dd2;
  for (int c = 0; c < channel_count; ++c) {
    const float* channel = values + static_cast<std::size_t>(c) * channel_stride;
    auto low = hn::Zero(dd2), high = hn::Zero(dd2);  // taps 0, 1 and 2, 3 along phi_d
    for (int r = 0; r < 16; ++r) {
      const auto taps = hn::LoadU(df4, channel + rows[r]);
      const auto weight = hn::Set(dd2, row_weights[r]);
      low = hn::MulAdd(weight, hn::PromoteTo(dd2, hn::LowerHalf(df2, taps)), low);
      high = hn::MulAdd(weight, hn::PromoteTo(dd2, hn::UpperHalf(df2, taps)), high);
    }
    alignas(16) double l[2], h[2];
    hn::Store(low, dd2, l), hn::Store(high, dd2, h);
    out[c] = phi_weights[0] * l[0] + phi_weights[1] * l[1] + phi_weights[2] * h[0] + phi_weights[3] * h[1];
  }
#endif
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf::detail {
HWY_EXPORT(CatmullRomRows);
void catmull_rom_rows(const float* values, std::size_t channel_stride, int channel_count, const std::size_t* rows,
                      const double* row_weights, const double* phi_weights, double* out) {
  HWY_DYNAMIC_DISPATCH(CatmullRomRows)(values, channel_stride, channel_count, rows, row_weights, phi_weights, out);
}
}  // namespace libbrdf::detail
#endif
