// Trilinear lookups of the rusinkiewicz and MERL layouts (lut.h) over a span of queries, one query
// per SIMD lane (Google Highway, run-time dispatch, as series_simd.cpp): each lane locates its
// cell (lut_internal.h: TrilinearView) and fetches the two phi_d-adjacent nodes of each of its
// four cell rows as one 8-byte pair (a gather of pairs per row and channel), then interpolates
// with the scalar formula's operations in its order. 3-channel lookups (`lookup_all_batch`, 48^3
// rusinkiewicz, 10th percentile of 4000-query batches, one CPU): 36.7 -> 24.5 ns per query.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "trilinear_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include <algorithm>
#include <cstdint>

#include "lut_internal.h"

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// split_index (lut.cpp) lane by lane: x clamped to [0, nodes - 1], its cell i <= nodes - 2 and
// the offset t = x - i in it.
template <class D, class V = hn::Vec<D>>
HWY_INLINE void SplitIndex(D d, V x, int nodes, V* i, V* t) {
  x = hn::Min(hn::Max(x, hn::Zero(d)), hn::Set(d, double(nodes - 1)));
  *i = hn::Min(hn::Floor(x), hn::Set(d, double(std::max(nodes - 2, 0))));
  *t = hn::Sub(x, *i);
}

// (1 - t) a + t b, as lut.cpp's lerp: two multiplies and an add, each rounded (this file is compiled
// with -ffp-contract=off, libbrdf/CMakeLists.txt), so that every target gives the scalar formula's
// bits: `brdf eval --lut` on 20k queries, rusinkiewicz and MERL tables, md5-identical to the scalar loop.
template <class V>
HWY_INLINE V Lerp(V a, V b, V t, V one) {
  return hn::Add(hn::Mul(hn::Sub(one, t), a), hn::Mul(t, b));
}

// No row prefetches: each gather already has its lanes' loads in flight, and a two-pass version
// that located a chunk of 32 queries ahead and prefetched their 12 lines each was slower (3-channel
// lookups, 10th percentile of 4000-query batches, same run: 48^3 28.6 -> 32.4 ns, 90^3 41.5 -> 46.7,
// MERL 58.1 -> 60.0).
void TrilinearSpan(const TrilinearView& table, const TableAngles* angles, std::size_t count, int first_channel, int channel_count,
                   double* values) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  const hn::RebindToUnsigned<decltype(d)> du;
  const hn::Rebind<std::uint32_t, decltype(d)> du32;  // as many lanes, 32 bits each
  const hn::Rebind<float, decltype(d)> df;
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
    const TableAngles* at = angles + k;
    if (m < n) {  // the last, partial vector through a padded copy (repeating its last query)
      for (std::size_t j = 0; j < n; ++j) padded[j] = at[std::min(j, m - 1)];
      at = padded;
    }
    V theta_h, theta_d, phi_d, theta_i;
    hn::LoadInterleaved4(d, reinterpret_cast<const double*>(at), theta_h, theta_d, phi_d, theta_i);
    V i0, i1, i2, t0, t1, t2;
    SplitIndex(d, hn::Mul(hn::Sqrt(hn::Mul(theta_h, hn::Set(d, 2.0 / kPi))), hn::Set(d, table.scale0)), table.n0, &i0, &t0);  // square map
    SplitIndex(d, hn::Mul(theta_d, hn::Set(d, table.scale1)), table.n1, &i1, &t1);
    SplitIndex(d, hn::Mul(phi_d, hn::Set(d, table.scale2)), table.n2, &i2, &t2);
    const V corner = hn::MulAdd(i0, hn::Set(d, double(table.n12)), hn::MulAdd(i1, hn::Set(d, double(table.n2)), i2));  // < 2^53: exact
    const auto corner_bytes = hn::ShiftLeft<2>(hn::ConvertTo(di, corner));  // floats -> bytes
    for (int c = 0; c < channel_count; ++c) {
      const float* channel = table.values + static_cast<std::size_t>(first_channel + c) * table.nodes;
      V lerp_phi[4];  // along phi_d in rows (i0, i1), (i0, i1 + 1), (i0 + 1, i1), (i0 + 1, i1 + 1)
      for (int r = 0; r < 4; ++r) {
        // Nodes i2 and i2 + 1 of the row: one 8-byte pair per lane, its low half the first node.
        const auto pair = hn::GatherOffset(du, reinterpret_cast<const std::uint64_t*>(channel),
                                           hn::Add(corner_bytes, hn::Set(di, row_bytes[r])));
        const V a = hn::PromoteTo(d, hn::BitCast(df, hn::TruncateTo(du32, pair)));
        const V b = hn::PromoteTo(d, hn::BitCast(df, hn::TruncateTo(du32, hn::ShiftRight<32>(pair))));
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
void trilinear_span(const TrilinearView& table, const TableAngles* angles, std::size_t count, int first_channel, int channel_count,
                    double* values) {
  if (count > 0) HWY_DYNAMIC_DISPATCH(TrilinearSpan)(table, angles, count, first_channel, channel_count, values);
}
}  // namespace libbrdf::detail
#endif
