// The kernel layout's K(theta_i) factor (lut.cpp: kernel_span; lut_internal.h: k_positions_span,
// k_factors_span) in SIMD lanes (Google Highway, run-time dispatch). Apart from trilinear_simd.cpp,
// whose lookups then compiled as before (in one file, 3-channel 90^3 lookups had come out ~2%
// slower from a different register allocation).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "kernel_k_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <cstdint>

#include "geometry_records-inl.h"  // Field
#include "lerp_simd-inl.h"         // SplitIndex, Lerp, GatherNodePair, VectorItems, StoreItems
#include "lut_internal.h"
#include "upper_half_angle-inl.h"  // UpperHalfAngle

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Kernel layout (lut.cpp: kernel_span): K(theta_i) by linear interpolation in a table of `nodes`
// floats over theta_i in [0, pi/2], one query per lane, in lut.cpp's linear_position and linear_at
// operations (-ffp-contract=off): the same bits. First each query's position (node index and
// offset, shared by the channels whose K tables have as many nodes), then per channel
// factor[k] = K closed[k] asf[k], the node pair of a lane's cell fetched by one gather as
// TrilinearSpan's rows (trilinear_simd.cpp). theta_i is atan2(sin, cos) of the geometry by the
// table coordinates' UpperHalfAngle (stop 25: no separate pass storing it into table angles, 23.1-23.6
// -> 22.5-23.0 ns, the same bits). KPositionsSpan returns false at a theta_i outside
// [0, pi/2], NaN included, for lut.cpp's scalar path to name it. 3-channel closed-form lookups, 8000 cached geometries, one
// CPU, best of 3000 passes, alternated runs: against the scalar loop (27.2-27.7 ns), 26.4-27.3 ns
// with the positions found in every channel's pass, 25.0-25.2 ns with them shared (26.2-26.8 in
// that run); the values md5-identical (every kernel-layout model, both angular forms, 5000 geometries).
bool KPositionsSpan(int nodes, const ScatterGeometry* geos, std::size_t count, double* node, double* offset) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
  const std::size_t n = hn::Lanes(d);
  const V zero = hn::Zero(d), right_angle = hn::Set(d, 0.5 * kPi), last = hn::Set(d, double(nodes - 1));
  ScatterGeometry padded[kMaxLanes];
  for (std::size_t k = 0; k < count; k += n) {
    const ScatterGeometry* at = VectorItems(d, geos, k, count, padded);
    const V theta_i = UpperHalfAngle(d, Field(d, at, kSinI), Field(d, at, kCosI));
    if (!hn::AllTrue(d, hn::And(hn::Ge(theta_i, zero), hn::Le(theta_i, right_angle)))) return false;
    V i, t;
    SplitIndex(d, hn::Mul(hn::Div(theta_i, right_angle), last), nodes, &i, &t);
    StoreItems(d, i, node, k, count), StoreItems(d, t, offset, k, count);
  }
  return true;
}

void KFactorsSpan(const float* k_table, const double* node, const double* offset, const double* closed, const double* asf, std::size_t count,
                  double* factor) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
  const std::size_t n = hn::Lanes(d);
  const V one = hn::Set(d, 1.0);
  alignas(64) double pad[4][kMaxLanes];
  for (std::size_t k = 0; k < count; k += n) {
    const double* in[4] = {node, offset, closed, asf};
    for (int a = 0; a < 4; ++a) in[a] = VectorItems(d, in[a], k, count, pad[a]);
    V k_low, k_high;
    GatherNodePair(d, k_table, hn::ShiftLeft<2>(hn::ConvertTo(di, hn::LoadU(d, in[0]))), &k_low, &k_high);  // floats -> bytes
    const V value = hn::Mul(hn::Mul(Lerp(k_low, k_high, hn::LoadU(d, in[1]), one), hn::LoadU(d, in[2])), hn::LoadU(d, in[3]));
    StoreItems(d, value, factor, k, count);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf::detail {
HWY_EXPORT(KPositionsSpan);
HWY_EXPORT(KFactorsSpan);
bool k_positions_span(int nodes, const ScatterGeometry* geos, std::size_t count, double* node, double* offset) {
  return count == 0 || HWY_DYNAMIC_DISPATCH(KPositionsSpan)(nodes, geos, count, node, offset);
}
void k_factors_span(const float* k_table, const double* node, const double* offset, const double* closed, const double* asf, std::size_t count,
                    double* factor) {
  if (count > 0) HWY_DYNAMIC_DISPATCH(KFactorsSpan)(k_table, node, offset, closed, asf, count, factor);
}
}  // namespace libbrdf::detail
#endif
