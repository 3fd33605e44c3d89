// Internal, per SIMD target (Google Highway's -inl.h pattern: re-included once per target by
// foreach_target.h): the square transposition of MaxLanes(d) vectors, shared by the kernel table's
// lookups (asf_batch.cpp: each lane's cell row into columns) and the geometry spans
// (angular_simd.cpp: fields into records).
#if defined(LIBBRDF_SIMD_TRANSPOSE_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef LIBBRDF_SIMD_TRANSPOSE_INL_H_
#undef LIBBRDF_SIMD_TRANSPOSE_INL_H_
#else
#define LIBBRDF_SIMD_TRANSPOSE_INL_H_
#endif

#include <cstddef>

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Transposes the n x n block v[0 .. n) of n = MaxLanes(d) <= 8 lanes: lane r of v[q] goes to lane q
// of v[r]. Block operations only (no per-lane table lookup): log2(n) rounds of n shuffles.
template <class D>
HWY_INLINE void TransposeSquare(D d, hn::Vec<D>* v) {
#if HWY_TARGET == HWY_SCALAR  // one lane: nothing to move (and no block operations)
  (void)d, (void)v;
#else
  constexpr std::size_t n = hn::MaxLanes(d);
  using V = hn::Vec<D>;
  // Within 128-bit blocks: t[2m] holds the even columns of rows 2m, 2m + 1 (one block per
  // column), t[2m + 1] the odd ones.
  V t[n];
  for (std::size_t m = 0; 2 * m < n; ++m) {
    t[2 * m] = hn::InterleaveLower(d, v[2 * m], v[2 * m + 1]);
    t[2 * m + 1] = hn::InterleaveUpper(d, v[2 * m], v[2 * m + 1]);
  }
  if constexpr (n == 2) {
    v[0] = t[0], v[1] = t[1];
  } else if constexpr (n == 4) {
    v[0] = hn::ConcatLowerLower(d, t[2], t[0]), v[1] = hn::ConcatLowerLower(d, t[3], t[1]);
    v[2] = hn::ConcatUpperUpper(d, t[2], t[0]), v[3] = hn::ConcatUpperUpper(d, t[3], t[1]);
  } else {
    static_assert(n == 8, "at most 8 lanes of doubles (512-bit vectors)");
    // Blocks across row pairs: u[4h + r] holds columns r and r + 4 of rows 4h .. 4h + 3.
    V u[8];
    for (std::size_t h = 0; h < 2; ++h)
      for (std::size_t p = 0; p < 2; ++p) {
        const V lo = t[4 * h + p], hi = t[4 * h + 2 + p];
        u[4 * h + p] = hn::OddEvenBlocks(hn::SwapAdjacentBlocks(hi), lo);
        u[4 * h + 2 + p] = hn::OddEvenBlocks(hi, hn::SwapAdjacentBlocks(lo));
      }
    for (std::size_t r = 0; r < 4; ++r)
      v[r] = hn::ConcatLowerLower(d, u[4 + r], u[r]), v[r + 4] = hn::ConcatUpperUpper(d, u[4 + r], u[r]);
  }
#endif
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#endif  // LIBBRDF_SIMD_TRANSPOSE_INL_H_
