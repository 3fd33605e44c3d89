// The kernel layout's tabulated angular factor P~ (lut.h; lut.cpp: kernel_span): Catmull-Rom
// (cubic, interpolating) on each axis, 4 x 4 x 4 nodes, end nodes repeated beyond the table's
// edges, for a span of queries (Google Highway, run-time dispatch). Trilinear left 0.12-0.16% max
// relative error on 54^3 nodes (intermediate/rough mbk, theta <= 85 deg); the cubic's error falls
// as h^3-h^4.
//
// Two passes over chunks of kChunk queries:
//  1. one query per double lane: each axis's position, its four weights and its four (clamped)
//     nodes. Along phi_d, the stencil is moved inside the table and a clamped tap's weight added
//     to the node it repeats, so that its four taps are four adjacent floats of a row wherever the
//     table has >= 4 phi_d nodes (fewer: the row's nodes, then zero weights, from a padded copy);
//  2. per query, each of the 16 (theta_h, theta_d) rows is loaded -- planar: four floats per
//     channel (phi_d in lanes); channel-interleaved (LutSampler): the row's four taps of every
//     channel as one run, one vector of 16 floats for RGB on AVX-512 -- and summed along theta_d
//     in each theta_h row, then along theta_h (short chains of multiply-adds, single precision:
//     the table's own floats), then along phi_d by the same scalar sum in both layouts (the same
//     values to the bit).
// Before (stop 26): the weights and row offsets query by query in scalar code, a dispatched call
// per query for pass 2, and a scalar loop where the phi_d stencil reached past an end. 3-channel
// lookups, 1e6 streaming geometries, one CPU (bench/bench_lookup, three alternated runs): 99-108
// -> 58-61 ns through LutSampler, 66-79 ns planar.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "kernel_angular_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "lerp_simd-inl.h"  // SplitIndex, VectorItems
#include "lut_internal.h"

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

constexpr std::size_t kChunk = 64;  // queries whose weights and offsets pass 1 keeps on the stack

// One axis of the stencil at positions x (in nodes) of a table with `nodes` (>= 2) nodes: the cell
// i and offset t of SplitIndex (x clamped to [0, nodes - 1], i <= nodes - 2); Catmull-Rom weights
// of nodes i - 1 .. i + 2, whose indices are returned clamped to the table (end nodes repeated).
template <class D, class V = hn::Vec<D>>
HWY_INLINE void CubicStencil(D d, V x, int nodes, V* weight, V* node) {
  const V half = hn::Set(d, 0.5), last = hn::Set(d, nodes - 1.0);
  V i, t;
  SplitIndex(d, x, nodes, &i, &t);
  const V t2 = hn::Mul(t, t), t3 = hn::Mul(t2, t);
  // 0.5 (-t^3 + 2t^2 - t), 0.5 (3t^3 - 5t^2 + 2), 0.5 (-3t^3 + 4t^2 + t), 0.5 (t^3 - t^2)
  weight[0] = hn::Mul(half, hn::Sub(hn::MulAdd(hn::Set(d, 2.0), t2, hn::Neg(t3)), t));
  weight[1] = hn::Mul(half, hn::MulAdd(hn::Set(d, 3.0), t3, hn::NegMulAdd(hn::Set(d, 5.0), t2, hn::Set(d, 2.0))));
  weight[2] = hn::Mul(half, hn::Add(hn::MulAdd(hn::Set(d, -3.0), t3, hn::Mul(hn::Set(d, 4.0), t2)), t));
  weight[3] = hn::Mul(half, hn::Sub(t3, t2));
  for (int m = 0; m < 4; ++m) node[m] = hn::Min(hn::Max(hn::Add(i, hn::Set(d, m - 1.0)), hn::Zero(d)), last);
}

// Pass 1's results for the queries of a chunk: the offsets (in floats) of the theta_h and theta_d
// nodes (the first phi_d tap's in the theta_h ones), and every axis's weights, float as the sums.
struct ChunkStencils {
  alignas(64) std::int64_t offset_h[4][kChunk], offset_d[4][kChunk];
  alignas(64) float weight_h[4][kChunk], weight_d[4][kChunk], weight_phi[4][kChunk];
};

// Pass 2 for the `count` queries of a chunk: out[k channel_count + c]. A row's four phi_d taps of
// every channel it holds (one, planar; all, interleaved) are summed in the lanes of `df`, `parts`
// vectors per row; then along phi_d, the same scalar sum for both layouts (bit-identical values).
// kShortRows: a table of n2 < 4 phi_d nodes, whose rows are read through a zero-padded copy.
template <bool kShortRows, class DF>
HWY_INLINE void SumRows(DF df, const KernelAngularView& table, const ChunkStencils& at, std::size_t count, int first_channel,
                        int channel_count, double* out) {
  using VF = hn::Vec<DF>;
  const std::size_t node_floats = static_cast<std::size_t>(table.node_floats), row_floats = 4 * node_floats;
  const std::size_t step = hn::Lanes(df), parts = (row_floats + step - 1) / step;
  const int runs = node_floats == 1 ? channel_count : 1;  // sets of rows: one per channel, or one for all
  const std::size_t short_row_floats = static_cast<std::size_t>(table.nodes[2]) * node_floats;
  constexpr std::size_t kMaxRowFloats = 4 * kInterleavedNodeFloats + HWY_MAX_BYTES / sizeof(float);
  const float* const first = table.values + static_cast<std::size_t>(first_channel) * table.channel_stride;
  for (std::size_t k = 0; k < count; ++k) {
    VF w_h[4], w_d[4];
    const float* row[4][4];  // row (a0, a1) of the first channel
    for (int a = 0; a < 4; ++a) w_h[a] = hn::Set(df, at.weight_h[a][k]), w_d[a] = hn::Set(df, at.weight_d[a][k]);
    for (int a0 = 0; a0 < 4; ++a0)
      for (int a1 = 0; a1 < 4; ++a1) row[a0][a1] = first + at.offset_h[a0][k] + at.offset_d[a1][k];
    double* const values = out + k * static_cast<std::size_t>(channel_count);
    for (int run = 0; run < runs; ++run) {
      const std::size_t channel = static_cast<std::size_t>(run) * table.channel_stride;
      alignas(64) float taps[kMaxRowFloats];  // tap m of channel c at m node_floats + c
      for (std::size_t part = 0; part < parts; ++part) {
        auto load = [&](int a0, int a1) {
          const float* row_start = row[a0][a1] + channel;
          if constexpr (!kShortRows) {
            return hn::LoadU(df, row_start + part * step);
          } else {
            alignas(64) float padded[kMaxRowFloats] = {};  // the row's nodes, then zeros (zero weights)
            std::copy(row_start, row_start + short_row_floats, padded);
            return hn::Load(df, padded + part * step);
          }
        };
        VF along_d[4];  // along theta_d in each theta_h row
        for (int a0 = 0; a0 < 4; ++a0)
          along_d[a0] = hn::MulAdd(w_d[3], load(a0, 3), hn::MulAdd(w_d[2], load(a0, 2), hn::MulAdd(w_d[1], load(a0, 1), hn::Mul(w_d[0], load(a0, 0)))));
        const VF along_h = hn::MulAdd(w_h[3], along_d[3], hn::MulAdd(w_h[2], along_d[2], hn::MulAdd(w_h[1], along_d[1], hn::Mul(w_h[0], along_d[0]))));
        hn::Store(along_h, df, taps + part * step);
      }
      for (std::size_t c = 0; c < node_floats; ++c) {  // along phi_d
        float sum = at.weight_phi[0][k] * taps[c];
        for (std::size_t m = 1; m < 4; ++m) sum += at.weight_phi[m][k] * taps[m * node_floats + c];
        values[run + c] = sum;
      }
    }
  }
}

void KernelAngularSpan(const KernelAngularView& table, const TableAngles* angles, std::size_t count, int first_channel, int channel_count,
                       double* out) {
  const hn::ScalableTag<double> d;
  const hn::Rebind<float, decltype(d)> df_half;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
  const std::size_t n = hn::Lanes(d);
  static_assert(kChunk % kMaxLanes == 0, "whole vectors per chunk");
  const int n1 = table.nodes[1], n2 = table.nodes[2];
  // Offsets in floats: node (i0, i1, i2) of a channel at node_floats ((i0 n1 + i1) n2 + i2).
  const V floats = hn::Set(d, double(table.node_floats));
  const V row0 = hn::Set(d, double(n1) * n2), row1 = hn::Mul(hn::Set(d, double(n2)), floats);
  const bool short_rows = n2 < 4;  // fewer phi_d nodes than taps: rows through a padded copy
  ChunkStencils at;
  TableAngles padded[kMaxLanes];  // a span's last, partial vector of queries
  for (std::size_t begin = 0; begin < count; begin += kChunk) {
    const std::size_t chunk = std::min(kChunk, count - begin);
    for (std::size_t k = 0; k < chunk; k += n) {
      V angle[4];  // theta_h, theta_d, phi_d (and theta_i) of the vector's queries
      static_assert(sizeof(TableAngles) == 4 * sizeof(double), "TableAngles: four doubles");
      const TableAngles* queries = VectorItems(d, angles, begin + k, begin + chunk, padded);
      hn::LoadInterleaved4(d, &queries->theta_h, angle[0], angle[1], angle[2], angle[3]);
      V weight[3][4], node[3][4];
      for (int axis = 0; axis < 3; ++axis)
        CubicStencil(d, hn::Mul(angle[axis], hn::Set(d, table.nodes_per_radian[axis])), table.nodes[axis], weight[axis], node[axis]);
      // phi_d: the stencil's first tap s = clamp(i - 1, 0, max(n2 - 4, 0)); each tap's weight goes
      // to the node it reads (a clamped tap to the end node it repeats), so that the four taps read
      // s .. s + 3, in the row.
      const V start = hn::Min(hn::Max(hn::Add(node[2][1], hn::Set(d, -1.0)), hn::Zero(d)), hn::Set(d, std::max(n2 - 4, 0)));
      V folded[4];
      for (int j = 0; j < 4; ++j) {
        const V tap_node = hn::Add(start, hn::Set(d, double(j)));
        folded[j] = hn::Zero(d);
        for (int m = 0; m < 4; ++m) folded[j] = hn::Add(folded[j], hn::IfThenElseZero(hn::Eq(node[2][m], tap_node), weight[2][m]));
      }
      // Whole vectors (kChunk is a multiple of the lanes): lanes past the chunk's end are not read.
      auto store_float = [&](V v, float* to) { hn::StoreU(hn::DemoteTo(df_half, v), df_half, to + k); };
      auto store_offset = [&](V v, std::int64_t* to) { hn::StoreU(hn::ConvertTo(di, v), di, to + k); };
      for (int m = 0; m < 4; ++m) {
        store_offset(hn::Mul(hn::MulAdd(node[0][m], row0, start), floats), at.offset_h[m]);
        store_offset(hn::Mul(node[1][m], row1), at.offset_d[m]);
        store_float(weight[0][m], at.weight_h[m]);
        store_float(weight[1][m], at.weight_d[m]);
        store_float(folded[m], at.weight_phi[m]);
      }
    }
    double* const chunk_out = out + begin * channel_count;
    if (table.node_floats == 1) {  // planar: the four taps of one channel per vector
      const hn::CappedTag<float, 4> df;
      if (short_rows) SumRows<true>(df, table, at, chunk, first_channel, channel_count, chunk_out);
      else SumRows<false>(df, table, at, chunk, first_channel, channel_count, chunk_out);
    } else {  // interleaved: every channel's taps in a row's vectors
      const hn::ScalableTag<float> df;
      if (short_rows) SumRows<true>(df, table, at, chunk, first_channel, channel_count, chunk_out);
      else SumRows<false>(df, table, at, chunk, first_channel, channel_count, chunk_out);
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf::detail {
HWY_EXPORT(KernelAngularSpan);
void kernel_angular_span(const KernelAngularView& table, const TableAngles* angles, std::size_t count, int first_channel,
                         int channel_count, double* out) {
  HWY_DYNAMIC_DISPATCH(KernelAngularSpan)(table, angles, count, first_channel, channel_count, out);
}
}  // namespace libbrdf::detail
#endif
