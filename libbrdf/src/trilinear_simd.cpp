// Trilinear lookups of the rusinkiewicz and MERL layouts (lut.h) over a span of queries, one query
// per SIMD lane (Google Highway, run-time dispatch, as series_simd.cpp): each lane locates its
// cell (lut_internal.h: TrilinearView) and fetches the two phi_d-adjacent nodes of each of its
// four cell rows as one 8-byte pair (a gather of pairs per row and channel), then interpolates
// with the scalar formula's operations in its order. 3-channel lookups (`lookup_all_batch`, 48^3
// rusinkiewicz, 10th percentile of 4000-query batches, one CPU): 36.7 -> 24.5 ns per query.
// LutSampler's channel-interleaved copy is read one query at a time instead (TrilinearInterleavedSpan).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "trilinear_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>
#include <hwy/cache_control.h>

#include <algorithm>
#include <cstdint>

#include "lerp_simd-inl.h"  // SplitIndex, Lerp, GatherNodePair, VectorItems
#include "lut_internal.h"

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The cells of one vector of queries: each lane's corner node index (i0 n12 + i1 n2 + i2, exact
// in a double) and its offsets t0, t1, t2 in the cell.
template <class D, class V = hn::Vec<D>>
HWY_INLINE void LocateCells(D d, const TrilinearView& table, const TableAngles* at, V* corner, V* t0, V* t1, V* t2) {
  V theta_h, theta_d, phi_d, theta_i;
  hn::LoadInterleaved4(d, reinterpret_cast<const double*>(at), theta_h, theta_d, phi_d, theta_i);
  V i0, i1, i2;
  SplitIndex(d, hn::Mul(hn::Sqrt(hn::Mul(theta_h, hn::Set(d, 2.0 / kPi))), hn::Set(d, table.scale0)), table.n0, &i0, t0);  // square map
  SplitIndex(d, hn::Mul(theta_d, hn::Set(d, table.scale1)), table.n1, &i1, t1);
  SplitIndex(d, hn::Mul(phi_d, hn::Set(d, table.scale2)), table.n2, &i2, t2);
  *corner = hn::MulAdd(i0, hn::Set(d, double(table.n12)), hn::MulAdd(i1, hn::Set(d, double(table.n2)), i2));  // < 2^53: exact
}

// Channel-interleaved tables (TrilinearView::interleaved, built by LutSampler): a query's four
// cell rows hold every channel of two nodes (24 bytes for RGB), ~5 cache lines for all channels
// where the planar layout reads 4 lines per channel. Lanes are then the channels of one query
// (Lerp in the same operations and order as TrilinearSpan: the same bits), and the cells of the
// next chunk are located in lanes and their rows prefetched before this chunk is interpolated.
// 3-channel lookups, 1e6 streaming queries, 10th percentile of 4000-query batches, one CPU (AMD
// EPYC with AVX-512), against TrilinearSpan in the same run (bench_lookup, three runs): MERL size
// 1.37-1.42x, 90^3 1.02-1.04x, 48^3 0.98-1.00x. Nodes padded to four floats (16 bytes: rows split
// across lines less often): MERL 1.57-1.65x but 90^3 0.88-0.93x (a third more bytes), not kept;
// there, without the prefetches, 90^3 took 49 ns against 35 and MERL 63 against 46.
constexpr std::size_t kInterleavedChunk = 32;

void TrilinearInterleavedSpan(const TrilinearView& table, const TableAngles* angles, std::size_t count, int first_channel,
                              int channel_count, double* values) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  using TI = hn::TFromD<decltype(di)>;
  constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
  const std::size_t n = hn::Lanes(d);
  // A query's channels: up to four lanes (two on 128-bit targets, then two blocks).
  const hn::CappedTag<double, kInterleavedNodeFloats> dc;
  const hn::Rebind<float, decltype(dc)> dcf;
  using VC = hn::Vec<decltype(dc)>;
  const std::size_t block = hn::Lanes(dc);
  const VC one = hn::Set(dc, 1.0);
  const std::size_t stride = static_cast<std::size_t>(table.node_floats);  // floats per node
  // Each cell row's first node relative to the cell's corner, in floats.
  const std::size_t row_floats[4] = {0, stride * table.n2, stride * table.n12, stride * (table.n12 + table.n2)};
  struct Cells {
    alignas(64) TI corner[kInterleavedChunk];
    alignas(64) double t0[kInterleavedChunk], t1[kInterleavedChunk], t2[kInterleavedChunk];
  } cells[2];
  TableAngles padded[kMaxLanes];
  auto locate = [&](std::size_t k0, Cells& at) {
    const std::size_t chunk = std::min(kInterleavedChunk, count - k0);
    for (std::size_t k = 0; k < chunk; k += n) {
      const std::size_t m = std::min(n, chunk - k);
      const TableAngles* a = VectorItems(d, angles, k0 + k, k0 + chunk, padded);
      V corner, t0, t1, t2;
      LocateCells(d, table, a, &corner, &t0, &t1, &t2);
      hn::Store(hn::ConvertTo(di, corner), di, at.corner + k);
      hn::Store(t0, d, at.t0 + k), hn::Store(t1, d, at.t1 + k), hn::Store(t2, d, at.t2 + k);
      for (std::size_t j = 0; j < m; ++j)
        for (std::size_t r = 0; r < 4; ++r) hwy::Prefetch(table.interleaved + stride * static_cast<std::size_t>(at.corner[k + j]) + row_floats[r]);
    }
  };
  auto interpolate = [&](std::size_t k0, const Cells& at) {
    const std::size_t chunk = std::min(kInterleavedChunk, count - k0);
    for (std::size_t j = 0; j < chunk; ++j) {
      const float* corner = table.interleaved + stride * static_cast<std::size_t>(at.corner[j]);
      const VC t0 = hn::Set(dc, at.t0[j]), t1 = hn::Set(dc, at.t1[j]), t2 = hn::Set(dc, at.t2[j]);
      double* out = values + (k0 + j) * static_cast<std::size_t>(channel_count);
      for (std::size_t c0 = 0; c0 < static_cast<std::size_t>(channel_count); c0 += block) {
        VC lerp_phi[4];  // rows as in TrilinearSpan
        for (int r = 0; r < 4; ++r) {
          const float* node = corner + row_floats[r] + first_channel + c0;
          lerp_phi[r] = Lerp(hn::PromoteTo(dc, hn::LoadU(dcf, node)), hn::PromoteTo(dc, hn::LoadU(dcf, node + stride)), t2, one);
        }
        const VC value = Lerp(Lerp(lerp_phi[0], lerp_phi[1], t1, one), Lerp(lerp_phi[2], lerp_phi[3], t1, one), t0, one);
        alignas(32) double lanes[kInterleavedNodeFloats];
        hn::Store(value, dc, lanes);
        const std::size_t stored = std::min(block, static_cast<std::size_t>(channel_count) - c0);
        for (std::size_t c = 0; c < stored; ++c) out[c0 + c] = lanes[c];
      }
    }
  };
  if (count > 0) locate(0, cells[0]);
  for (std::size_t k0 = 0, which = 0; k0 < count; k0 += kInterleavedChunk, which ^= 1) {
    if (k0 + kInterleavedChunk < count) locate(k0 + kInterleavedChunk, cells[which ^ 1]);
    interpolate(k0, cells[which]);
  }
}

// No row prefetches: each gather already has its lanes' loads in flight, and a two-pass version
// that located a chunk of 32 queries ahead and prefetched their 12 lines each was slower (3-channel
// lookups, 10th percentile of 4000-query batches, same run: 48^3 28.6 -> 32.4 ns, 90^3 41.5 -> 46.7,
// MERL 58.1 -> 60.0).
void TrilinearSpan(const TrilinearView& table, const TableAngles* angles, std::size_t count, int first_channel, int channel_count,
                   double* values) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  using TI = hn::TFromD<decltype(di)>;
  constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
  const std::size_t n = hn::Lanes(d);
  const V one = hn::Set(d, 1.0);
  // Each cell row's first node relative to the cell's corner (node (i0, i1, i2)), in bytes.
  const TI row_bytes[4] = {0, TI{4} * table.n2, TI{4} * static_cast<TI>(table.n12), TI{4} * (static_cast<TI>(table.n12) + table.n2)};
  TableAngles padded[kMaxLanes];
  alignas(64) double out[kMaxLanes];
  for (std::size_t k = 0; k < count; k += n) {
    const std::size_t m = std::min(n, count - k);
    const TableAngles* at = VectorItems(d, angles, k, count, padded);
    V corner, t0, t1, t2;
    LocateCells(d, table, at, &corner, &t0, &t1, &t2);
    const auto corner_bytes = hn::ShiftLeft<2>(hn::ConvertTo(di, corner));  // floats -> bytes
    for (int c = 0; c < channel_count; ++c) {
      const float* channel = table.values + static_cast<std::size_t>(first_channel + c) * table.nodes;
      V lerp_phi[4];  // along phi_d in rows (i0, i1), (i0, i1 + 1), (i0 + 1, i1), (i0 + 1, i1 + 1)
      for (int r = 0; r < 4; ++r) {
        V a, b;  // nodes i2 and i2 + 1 of the row
        GatherNodePair(d, channel, hn::Add(corner_bytes, hn::Set(di, row_bytes[r])), &a, &b);
        lerp_phi[r] = Lerp(a, b, t2, one);
      }
      const V value = Lerp(Lerp(lerp_phi[0], lerp_phi[1], t1, one), Lerp(lerp_phi[2], lerp_phi[3], t1, one), t0, one);
      hn::Store(value, d, out);
      for (std::size_t j = 0; j < m; ++j) values[(k + j) * channel_count + c] = out[j];
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf::detail {
HWY_EXPORT(TrilinearSpan);
HWY_EXPORT(TrilinearInterleavedSpan);
void trilinear_span(const TrilinearView& table, const TableAngles* angles, std::size_t count, int first_channel, int channel_count,
                    double* values) {
  if (count == 0) return;
  if (table.interleaved) HWY_DYNAMIC_DISPATCH(TrilinearInterleavedSpan)(table, angles, count, first_channel, channel_count, values);
  else HWY_DYNAMIC_DISPATCH(TrilinearSpan)(table, angles, count, first_channel, channel_count, values);
}
}  // namespace libbrdf::detail
#endif
