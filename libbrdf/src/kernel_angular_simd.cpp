// The kernel layout's tabulated angular factor P~ (lut.h; lut.cpp: kernel_angular_factors) in SIMD
// lanes along phi_d (Google Highway, run-time dispatch): a Catmull-Rom stencil's four phi_d taps
// of a row are four adjacent floats wherever the stencil does not reach past the table's phi_d
// ends, so each of its 16 (theta_h, theta_d) rows is one load of four floats, weighted along
// theta_d and theta_h, and the phi_d weights close the sum. The scalar loop did 64 multiply-adds
// per channel, each on a converted float; `perf` put 60% of a 3-channel lookup of a P~ table there.
// 3-channel lookups (bench_lookup, 54^3 P~ table, one CPU, three runs): 133-136 -> 106-110 ns with
// 8000 cached geometries, 142-145 -> 115-117 ns streaming 1e6. (Swapping two taps fails lut_cli:
// tried.) Stop 25: the sums in single precision, along theta_d in each theta_h row and then along
// theta_h (short chains of multiply-adds), with the axes' weights as given rather than 16 products
// the caller had just stored (their reload stalled on store forwarding): 3-channel lookups, 8000
// cached geometries, best of 300 passes, three alternated runs, 97.7-99.4 -> 91.2-92.9 (single
// precision) -> 86.0-89.5 ns; values within 3.2e-7 of the double sums (gold, 20000 queries).
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

void CatmullRomRows(const float* values, std::size_t channel_stride, int channel_count, const std::size_t* rows, const double* theta_h_weights,
                    const double* theta_d_weights, const double* phi_weights, double* out) {
#if HWY_TARGET == HWY_SCALAR  // one lane: the sum written out
  for (int c = 0; c < channel_count; ++c) {
    const float* channel = values + static_cast<std::size_t>(c) * channel_stride;
    double sum = 0.0;
    for (int r = 0; r < 16; ++r)
      for (int m = 0; m < 4; ++m) sum += theta_h_weights[r / 4] * theta_d_weights[r % 4] * phi_weights[m] * double(channel[rows[r] + m]);
    out[c] = sum;
  }
#else
  const hn::FixedTag<float, 4> df4;  // 128 bits: every vector target has them
  using V = hn::Vec<decltype(df4)>;
  V w_h[4], w_d[4];
  for (int a = 0; a < 4; ++a)
    w_h[a] = hn::Set(df4, static_cast<float>(theta_h_weights[a])), w_d[a] = hn::Set(df4, static_cast<float>(theta_d_weights[a]));
  alignas(16) const float phi[4] = {static_cast<float>(phi_weights[0]), static_cast<float>(phi_weights[1]),
                                    static_cast<float>(phi_weights[2]), static_cast<float>(phi_weights[3])};
  const V w_phi = hn::Load(df4, phi);
  for (int c = 0; c < channel_count; ++c) {
    const float* channel = values + static_cast<std::size_t>(c) * channel_stride;
    // Along theta_d in each of the four theta_h rows (four short chains), then along theta_h.
    V along_d[4];
    for (int a0 = 0; a0 < 4; ++a0) {
      const std::size_t* row = rows + 4 * a0;
      along_d[a0] = hn::MulAdd(w_d[3], hn::LoadU(df4, channel + row[3]),
                               hn::MulAdd(w_d[2], hn::LoadU(df4, channel + row[2]),
                                          hn::MulAdd(w_d[1], hn::LoadU(df4, channel + row[1]), hn::Mul(w_d[0], hn::LoadU(df4, channel + row[0])))));
    }
    const V taps = hn::MulAdd(w_h[3], along_d[3], hn::MulAdd(w_h[2], along_d[2], hn::MulAdd(w_h[1], along_d[1], hn::Mul(w_h[0], along_d[0]))));
    out[c] = hn::GetLane(hn::SumOfLanes(df4, hn::Mul(taps, w_phi)));  // along phi_d
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
                      const double* theta_h_weights, const double* theta_d_weights, const double* phi_weights, double* out) {
  HWY_DYNAMIC_DISPATCH(CatmullRomRows)(values, channel_stride, channel_count, rows, theta_h_weights, theta_d_weights, phi_weights, out);
}
}  // namespace libbrdf::detail
#endif
