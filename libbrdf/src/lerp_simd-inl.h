// Internal, per SIMD target (Google Highway's -inl.h pattern: re-included once per target by
// foreach_target.h): linear interpolation in lanes with lut.cpp's scalar operations, its node pairs
// fetched by gathers, for the trilinear lookups (trilinear_simd.cpp) and the kernel layout's K
// (kernel_k_simd.cpp), both compiled with -ffp-contract=off (libbrdf/CMakeLists.txt), so that
// Lerp's two multiplies and add round as the scalar formula's do; and the partial last vector of a
// span, read padded (VectorItems) and stored in part (StoreItems), which asf_batch.cpp uses too.
#if defined(LIBBRDF_LERP_SIMD_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef LIBBRDF_LERP_SIMD_INL_H_
#undef LIBBRDF_LERP_SIMD_INL_H_
#else
#define LIBBRDF_LERP_SIMD_INL_H_
#endif

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include <hwy/highway.h>

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

// (1 - t) a + t b, as lut.cpp's lerp: two multiplies and an add, each rounded (the including file
// is compiled with -ffp-contract=off), so that every target gives the scalar formula's
// bits: `brdf eval --lut` on 20k queries, rusinkiewicz and MERL tables, md5-identical to the scalar loop.
template <class V>
HWY_INLINE V Lerp(V a, V b, V t, V one) {
  return hn::Add(hn::Mul(hn::Sub(one, t), a), hn::Mul(t, b));
}

// The nodes i and i + 1 of a float table as two double vectors (a lane's pair is one 8-byte gather
// at its byte offset 4 i; the low half the first node).
template <class D, class V = hn::Vec<D>>
HWY_INLINE void GatherNodePair(D d, const float* table, hn::Vec<hn::RebindToSigned<D>> byte_offset, V* first, V* second) {
  const hn::RebindToUnsigned<D> du;
  const hn::Rebind<std::uint32_t, D> du32;  // as many lanes, 32 bits each
  const hn::Rebind<float, D> df;
  const auto pair = hn::GatherOffset(du, reinterpret_cast<const std::uint64_t*>(table), byte_offset);
  *first = hn::PromoteTo(d, hn::BitCast(df, hn::TruncateTo(du32, pair)));
  *second = hn::PromoteTo(d, hn::BitCast(df, hn::TruncateTo(du32, hn::ShiftRight<32>(pair))));
}

// The queries of the vector from `first` on: `items` itself, or where fewer than a vector's lanes
// are left, `padded` filled with them and the last one repeated.
template <class D, class T>
HWY_INLINE const T* VectorItems(D d, const T* items, std::size_t first, std::size_t count, T* padded) {
  const std::size_t n = hn::Lanes(d), m = std::min(n, count - first);
  if (m == n) return items + first;
  for (std::size_t j = 0; j < n; ++j) padded[j] = items[first + std::min(j, m - 1)];
  return padded;
}

// Stores the lanes of v that are items [first, count) of `items` (all of them but in a span's last,
// partial vector).
template <class D>
HWY_INLINE void StoreItems(D d, hn::Vec<D> v, hn::TFromD<D>* items, std::size_t first, std::size_t count) {
  const std::size_t n = hn::Lanes(d), m = std::min(n, count - first);
  if (m == n) {
    hn::StoreU(v, d, items + first);
    return;
  }
  alignas(64) hn::TFromD<D> lanes[HWY_MAX_BYTES / sizeof(hn::TFromD<D>)];
  hn::Store(v, d, lanes);
  std::copy(lanes, lanes + m, items + first);
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#endif  // LIBBRDF_LERP_SIMD_INL_H_
