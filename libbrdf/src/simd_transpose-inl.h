// Internal, per SIMD target (Google Highway's -inl.h pattern: re-included once per target by
// foreach_target.h): the square transposition of MaxLanes(d) vectors (TransposeSquare: the geometry
// spans' fields into records and back, angular_simd.cpp) and the table lookups' column loads
// (LoadColumns: each lane's cell row into columns, for the kernel table in asf_batch.cpp and K in
// angular_simd.cpp).
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

// Columns of a table's rows: col[e] for e < kColumns (a multiple of 4, <= 8) gets element e of row
// q = row(q) (a const double*) in lane q, for the MaxLanes(d) lanes. What the table lookups read
// per lane (asf_batch.cpp: a kernel-table cell row of 2 nodes x 4 values; angular_simd.cpp: K's
// cell, 4 values). With 512-bit vectors each register is put together from two lanes' 4-double
// halves (a load and an insert from memory, which need not use the shuffle port) and the halves are
// transposed in two rounds of 4 shuffles and 4 blends per 4 columns: 16 shuffles for 8 columns
// where TransposeSquare takes 24, all on the one port that 512-bit shuffles have. Per query, minus
// g, 1e6 queries, one CPU, best of 3 x 5 runs, same run: asf 7.8 -> 7.6 ns (polished), 7.4 -> 7.1
// (rough); mbk (K's cell too) 15.1 -> 15.0, 14.8 -> 14.0; outputs bit-identical on every target.
// Other widths: n full rows, TransposeSquare.
template <std::size_t kColumns, class D, class RowPointer>
HWY_INLINE void LoadColumns(D d, const RowPointer& row, hn::Vec<D>* col) {
  static_assert(kColumns % 4 == 0 && kColumns <= 8, "4 or 8 columns");
  constexpr std::size_t n = hn::MaxLanes(d);
  using V = hn::Vec<D>;
#if HWY_TARGET != HWY_SCALAR
  if constexpr (n == 8) {
    const hn::Half<D> dh;
    for (std::size_t cb = 0; cb < kColumns; cb += 4) {
      // w[q]: columns cb .. cb + 3 of row q (lower half) and of row q + 4 (upper half).
      V w[4];
      for (std::size_t q = 0; q < 4; ++q) w[q] = hn::Combine(d, hn::LoadU(dh, row(q + 4) + cb), hn::LoadU(dh, row(q) + cb));
      // Per 128-bit block, the pairs of rows (0, 1) and (4, 5), or (2, 3) and (6, 7), side by side:
      // columns cb and cb + 2 (lower*), cb + 1 and cb + 3 (upper*); then blocks of both alternate.
      const V lower01 = hn::InterleaveLower(d, w[0], w[1]), upper01 = hn::InterleaveUpper(d, w[0], w[1]);
      const V lower23 = hn::InterleaveLower(d, w[2], w[3]), upper23 = hn::InterleaveUpper(d, w[2], w[3]);
      col[cb + 0] = hn::OddEvenBlocks(hn::SwapAdjacentBlocks(lower23), lower01);
      col[cb + 1] = hn::OddEvenBlocks(hn::SwapAdjacentBlocks(upper23), upper01);
      col[cb + 2] = hn::OddEvenBlocks(lower23, hn::SwapAdjacentBlocks(lower01));
      col[cb + 3] = hn::OddEvenBlocks(upper23, hn::SwapAdjacentBlocks(upper01));
    }
  } else
#endif
  {  // n <= 4 lanes: whole rows of n columns, kColumns / n of them
    for (std::size_t e0 = 0; e0 < kColumns; e0 += n) {
      V v[n];
      for (std::size_t q = 0; q < n; ++q) v[q] = hn::LoadU(d, row(q) + e0);
      TransposeSquare(d, v);
      for (std::size_t e = 0; e < n; ++e) col[e0 + e] = v[e];
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#endif  // LIBBRDF_SIMD_TRANSPOSE_INL_H_
