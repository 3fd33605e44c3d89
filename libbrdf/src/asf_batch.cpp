// asf_auto over a batch of queries (mbk_series.h): the method of each query chosen exactly as
// asf_auto chooses it, then the queries of each method evaluated together, one query per SIMD lane
// (Google Highway, run-time dispatch, as series_simd.cpp):
//  - the series (eq. 11) of each lane from its own largest-term guess, by the exact ratios of
//    consecutive (or every d-th) terms: one exp and one division per term, no lgamma or log per
//    term; the plan, stride rule and geometric tail bound are those of sum_series_blocks;
//  - the kernel table's bicubic spline lookup (kernel_table.h), each lane's stencil rows loaded
//    whole and transposed.
// Queries whose closed-form regime (eqs. 14, 15) is possible, and lanes outside the lane kernel's
// domain, go through asf_auto / mbk_series_sum themselves. Every lane computes alone (lane-wise
// operations from its own plan): a value depends on its own (g, c) only, not on the batch.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "asf_batch.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>
#include <hwy/cache_control.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "asf_lanes.h"
#include "lerp_simd-inl.h"  // VectorItems, StoreItems
#include "libbrdf/kernel_table.h"
#include "libbrdf/mbk_series.h"
#include "series_simd.h"
#include "series_terms-inl.h"  // LogTerm
#include "simd_transpose-inl.h"  // TransposeSquare

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
constexpr std::size_t kSubChunk = 512;   // queries planned, sorted and walked together
constexpr int kMaxLaneTerms = 4096;      // a lane still walking after this many terms is rejected
// Largest exp argument of a ratio: beyond, t_m / t_{m0} could overflow (a guess far below the
// mode), and the vector is walked again lane by lane, or rejected.
constexpr double kMaxLogRatio = 700.0;

// 1.5 * 2^52: x + this rounds x to an integer held in the low bits of the sum's mantissa.
constexpr double kRoundingShifter = 6755399441055744.0;

// e^x = poly(r) 2^k, k = round(x / ln 2), r = x - k ln 2: the range reduction of hn::Exp and the
// degree-11 Taylor polynomial on |r| <= ln 2 / 2 (error 9e-15), with 2^k by exponent-field
// arithmetic (no conversion instructions). Returns poly; *shifted holds k + 1.5 * 2^52, whose low
// bits are k. Valid for |x| <= 1000 (k ln2_hi exact).
template <class D, class V = hn::Vec<D>>
HWY_INLINE V ExpReduced(D d, V x, V* shifted) {
  const V shifter = hn::Set(d, kRoundingShifter);
  *shifted = hn::MulAdd(x, hn::Set(d, 1.4426950408889634074), shifter);
  const V k = hn::Sub(*shifted, shifter);
  // ln 2 in two parts (fdlibm's): k ln2_hi is exact for |k| < 2^20.
  const V r = hn::NegMulAdd(k, hn::Set(d, 1.90821492927058770002e-10), hn::NegMulAdd(k, hn::Set(d, 6.93147180369123816490e-01), x));
  const V r2 = hn::Mul(r, r), r4 = hn::Mul(r2, r2), r8 = hn::Mul(r4, r4);
  auto pair = [&](double a, double b) { return hn::MulAdd(hn::Set(d, b), r, hn::Set(d, a)); };
  // 1 + r + ... + r^11/11! by Estrin's scheme.
  const V p01 = pair(1.0, 1.0), p23 = pair(1.0 / 2, 1.0 / 6), p45 = pair(1.0 / 24, 1.0 / 120), p67 = pair(1.0 / 720, 1.0 / 5040);
  const V p89 = pair(1.0 / 40320, 1.0 / 362880), pab = pair(1.0 / 3628800, 1.0 / 39916800);
  const V low = hn::MulAdd(r4, hn::MulAdd(r2, p67, p45), hn::MulAdd(r2, p23, p01));
  return hn::MulAdd(r8, hn::MulAdd(r2, pab, p89), low);
}

// 2^(e - 1023) for a biased exponent e in [1, 2046], as a double (the exponent field alone).
template <class D, class V = hn::Vec<D>>
HWY_INLINE V Pow2(D d, hn::Vec<hn::RebindToSigned<D>> biased_exponent) {
  return hn::BitCast(d, hn::ShiftLeft<52>(biased_exponent));
}

// e^x to ~1e-14 relative for x <= 709 (x < -708 gives ~e^-708, not 0). Fewer operations than
// hn::Exp's full-range version; every ratio of the walks goes through it.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V ExpRatio(D d, V x) {
  const hn::RebindToSigned<D> di;
  V shifted;
  const V poly = ExpReduced(d, hn::Max(x, hn::Set(d, -708.0)), &shifted);
  return hn::Mul(poly, Pow2(d, hn::Add(hn::BitCast(di, shifted), hn::Set(di, 1023))));
}

// e^x to ~1e-14 relative for x in [-745, 709], subnormal below -708 and 0 below ~-745.1 as the C
// library's exp (x clamped to [-1000, 709]): 2^k as 2^(k - k/2) 2^(k/2), two exponent-field
// powers, the second multiply rounding once into the subnormal range. What the kernel table's
// lookups take (ln Sigma reaches ~-900 there); against hn::Exp, whose 2^k goes through 32-bit
// integer conversions (shuffles, on the port the cell rows' transposition needs). asf per query,
// minus g, 1e6 queries, one CPU, best of 3 x 5 runs, same run: 7.8 -> 7.2 ns (polished), 7.8 ->
// 7.4 (intermediate), 7.0 -> 7.1 (rough), 12.3 -> 11.9 (l_c/lambda = 40, many lanes below -708).
// Against std::exp over [-760, 709] (3.2e7 points): 9e-15 relative, subnormals and 0 included.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V ExpFullRange(D d, V x) {
  const hn::RebindToSigned<D> di;
  V shifted;
  const V poly = ExpReduced(d, hn::Min(hn::Max(x, hn::Set(d, -1000.0)), hn::Set(d, 709.0)), &shifted);
  const auto k = hn::Sub(hn::BitCast(di, shifted), hn::BitCast(di, hn::Set(d, kRoundingShifter)));
  const auto half = hn::ShiftRight<1>(k);  // arithmetic: floor(k / 2)
  const auto bias = hn::Set(di, 1023);
  return hn::Mul(hn::Mul(poly, Pow2(d, hn::Add(hn::Sub(k, half), bias))), Pow2(d, hn::Add(half, bias)));
}

// Queries of one sub-chunk, structure of arrays (room for a whole last vector).
struct LaneList {
  alignas(64) double g[kSubChunk + kMaxLanes], c[kSubChunk + kMaxLanes], ln_g[kSubChunk + kMaxLanes],
      m0[kSubChunk + kMaxLanes], stride[kSubChunk + kMaxLanes], sigma[kSubChunk + kMaxLanes];
  std::uint32_t index[kSubChunk];
};

// The plan of sum_series_blocks (mbk_series.cpp) per lane: the largest-term guess (mode_guess:
// Winitzki's closed form of Lambert's W) and the stride rule. *work: the window's extent in
// strides (the lanes are sorted by it).
template <class D, class V = hn::Vec<D>>
HWY_INLINE void PlanLanes(D d, V g, V c, const StrideRule& rule, V* ln_g_out, V* m0, V* stride, V* work) {
  const V one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
  const V ln_g = hn::Log(d, g);
  // log_ratio(1) = ln g - 2 ln 2 + c/2 < 0: the first term is the largest.
  const auto first = hn::Lt(hn::MulAdd(hn::Set(d, 0.5), c, hn::Sub(ln_g, hn::Set(d, 1.3862943611198906188))), hn::Zero(d));
  *ln_g_out = ln_g;
  *stride = one;
  if (hn::AllTrue(d, first)) {  // common on polished surfaces: nothing more to plan
    *m0 = one;
    *work = one;
    return;
  }
  const V two_c = hn::Mul(two, c);
  const V q = hn::Div(two_c, hn::Mul(g, g));
  const V l = hn::Log1p(d, q);
  const V w = hn::Mul(l, hn::Sub(one, hn::Div(hn::Log1p(d, l), hn::Add(two, l))));
  // q <= 1e-8: W(q) ~ q, m ~ g.
  const V guess = hn::IfThenElse(hn::Gt(q, hn::Set(d, 1e-8)), hn::Round(hn::Sqrt(hn::Div(two_c, w))), hn::Round(g));
  const V m = hn::IfThenElse(first, one, hn::Max(one, guess));
  *m0 = m;
  *work = m;
  const auto above = hn::Gt(m, hn::Set(d, kStrideMinMode));
  if (hn::AllFalse(d, above)) return;  // no lane can be strided
  // Curvature of ln t_m at the mode: 1/(m + 1/2) - 1/m^2 + 2c/m^3; width = its -1/2 power.
  const V inv_m = hn::Div(one, m);
  const V curvature = hn::MulAdd(hn::Mul(two_c, inv_m), hn::Mul(inv_m, inv_m),
                                 hn::Sub(hn::Div(one, hn::Add(m, hn::Set(d, 0.5))), hn::Mul(inv_m, inv_m)));
  const V width = hn::Div(one, hn::Sqrt(curvature));
  const V strided = hn::Floor(hn::Mul(width, hn::Set(d, 1.0 / rule.widths_per_stride)));
  const auto use = hn::And(hn::And(above, hn::Ge(strided, two)), hn::Gt(hn::NegMulAdd(hn::Set(d, rule.clearance_widths), width, m), one));
  *stride = hn::IfThenElse(use, strided, one);
  *work = hn::IfThenElse(use, hn::Div(width, strided), m);
}

// Stops a walk where the geometric bound on its remaining tail, t r / (1 - r) with r the last
// ratio (the terms are log-concave in m: each ratio bounds the later ones), is below budget x sum
// (as sum_series_blocks); r >= 1 never stops it (t > 0), t = 0 always does.
template <class D, class V = hn::Vec<D>>
HWY_INLINE hn::Mask<D> TailDone(D d, V t, V ratio, V sum, V budget) {
  return hn::Or(hn::Eq(t, hn::Zero(d)), hn::Le(hn::Mul(t, ratio), hn::Mul(hn::Mul(budget, sum), hn::Sub(hn::Set(d, 1.0), ratio))));
}

// prod_{j=1..s} (m + j) / g per lane (s = the lane's stride <= max_stride): the ratio of Poisson
// weights e^-g g^m / m! at m and m + s, inverted; each factor is ~1 inside the window.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V InversePoissonRatio(D d, V m, V inv_g, V s, double max_stride) {
  const V one = hn::Set(d, 1.0);
  V product = hn::Mul(hn::Add(m, one), inv_g);
  for (double j = 2.0; j <= max_stride; j += 1.0) {
    const V jv = hn::Set(d, j);
    product = hn::Mul(product, hn::IfThenElse(hn::Le(jv, s), hn::Mul(hn::Add(m, jv), inv_g), one));
  }
  return product;
}

// Sigma of one vector of lanes, each on its own lattice m0 + k s. The terms
// t_m = e^-g g^m / (m! m) e^(-c/m) are walked up and down from m0 by their exact ratios
//   t_{m+s} / t_m = [prod_{j=1..s} g/(m+j)] (m/(m+s)) exp(c s / (m (m+s))),
// relative to t_{m0} = exp(LogTerm(m0)), each direction until TailDone with 0.45 tol, as in
// sum_series_blocks. Every operation is lane by lane, so a lane's value depends on its own (g, c)
// only, never on the queries beside it. *converged: false in lanes that needed more than
// kMaxLaneTerms terms or whose ratio could overflow.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V WalkLanes(D d, V g, V c, V ln_g, V m0, V s, double tol, hn::Mask<D>* converged) {
  const V one = hn::Set(d, 1.0), zero = hn::Zero(d);
  const V inv_g = hn::Div(one, g), cs = hn::Mul(c, s);
  const V budget = hn::Set(d, 0.45 * tol);
  const double max_stride = hn::GetLane(hn::MaxOfLanes(d, s));
  V sum = one, largest_exponent = zero;
  // Upward: t_{m+s}/t_m = m^2 Q exp(c s P Q), P = prod (m+j)/g, Q = 1/(m (m+s) P).
  auto up_ratio = [&](V m) {
    const V p = InversePoissonRatio(d, m, inv_g, s, max_stride);
    const V q = hn::Div(one, hn::Mul(hn::Mul(m, hn::Add(m, s)), p));
    const V exponent = hn::Mul(cs, hn::Mul(p, q));
    largest_exponent = hn::Max(largest_exponent, exponent);
    return hn::Mul(hn::Mul(hn::Mul(m, m), q), ExpRatio(d, exponent));
  };
  // Downward: t_{m-s}/t_m = P' m^2 R exp(-c s R), P' = prod (m-s+j)/g, R = 1/((m-s) m); 0 where
  // m - s < 1 (the lattice ends at m >= 1).
  auto down_ratio = [&](V m) {
    const V below = hn::Sub(m, s);
    const V p = InversePoissonRatio(d, below, inv_g, s, max_stride);
    const V r = hn::Div(one, hn::Mul(below, m));
    const V ratio = hn::Mul(hn::Mul(p, hn::Mul(hn::Mul(m, m), r)), ExpRatio(d, hn::Neg(hn::Mul(cs, r))));
    return hn::IfThenElseZero(hn::Ge(below, one), ratio);
  };
  // From m0 by `step` (+s up, -s down) while `active`: two terms per step, the tail tested after
  // the second (the test's latency -- sum, compare, mask -- paid once per two terms; a lane may sum
  // one term past its stop, a real term). Returns the lanes still unfinished.
  auto walk = [&](auto ratio_at, V step, hn::Mask<D> active) {
    V m = m0, t = one;
    for (int terms = 0; !hn::AllFalse(d, active) && (terms += 2) <= kMaxLaneTerms; m = hn::Add(m, hn::Add(step, step))) {
      const V r0 = ratio_at(m), r1 = ratio_at(hn::Add(m, step));
      const V t0 = hn::IfThenElseZero(active, hn::Mul(t, r0));
      t = hn::Mul(t0, r1);
      sum = hn::Add(sum, hn::Add(t0, t));
      active = hn::AndNot(TailDone(d, t, r1, sum, budget), active);
    }
    return active;
  };
  auto unfinished = walk(up_ratio, s, hn::Eq(one, one));
  const auto active = walk(down_ratio, hn::Neg(s), hn::Ge(hn::Sub(m0, s), one));
  unfinished = hn::Or(hn::Or(unfinished, active), hn::Gt(largest_exponent, hn::Set(d, kMaxLogRatio)));
  *converged = hn::Not(unfinished);
  const V log_value = hn::Add(LogTerm(d, m0, g, ln_g, c), hn::Log(d, hn::Mul(sum, s)));
  // exp underflows below -745 (the scalar sums return 0 there too).
  return hn::IfThenElseZero(hn::Ge(log_value, hn::Set(d, -745.0)), hn::Exp(d, log_value));
}

// Walks entries [begin, end) of a list in whole vectors (lanes past the end repeat its last
// entry); lanes with a non-finite result or no convergence are rejected.
std::size_t WalkRange(LaneList& list, std::size_t begin, std::size_t end, double tol, std::uint32_t* rejected) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t n = hn::Lanes(d);
  std::size_t count = 0;
  alignas(64) double converged[kMaxLanes];
  for (std::size_t k = begin; k < end; k += n) {
    const auto valid = hn::FirstN(d, end - k);
    auto load = [&](const double* array) { return hn::IfThenElse(valid, hn::LoadU(d, array + k), hn::Set(d, array[end - 1])); };
    hn::Mask<decltype(d)> ok;
    const V sigma = WalkLanes(d, load(list.g), load(list.c), load(list.ln_g), load(list.m0), load(list.stride), tol, &ok);
    hn::StoreU(sigma, d, list.sigma + k);
    hn::Store(hn::IfThenElseZero(ok, hn::Set(d, 1.0)), d, converged);
    for (std::size_t lane = k; lane < std::min(k + n, end); ++lane)
      if (converged[lane - k] == 0.0 || !std::isfinite(list.sigma[lane])) rejected[count++] = list.index[lane];
  }
  return count;
}

std::size_t SeriesQueryLanes(const double* g, const double* c, std::size_t count, double tol, double* sigma,
                             std::uint32_t* rejected) {
  const hn::ScalableTag<double> d;
  const std::size_t n = hn::Lanes(d);
  const StrideRule rule = stride_rule(tol);
  std::size_t rejected_count = 0;
  static thread_local LaneList all, sorted;  // ~50 KB each: kept off the stack
  // Sort keys (a vector walks as long as its longest lane): unit-stride lanes by their guess, then
  // strided lanes by their extent in strides, then those too wide for lanes.
  constexpr std::size_t kUnitKeys = 256, kStridedKeys = 64, kKeys = kUnitKeys + kStridedKeys + 1, kMinSorted = 64;
  for (std::size_t begin = 0; begin < count; begin += kSubChunk) {
    const std::size_t size = std::min(kSubChunk, count - begin);
    std::copy(g + begin, g + begin + size, all.g);
    std::copy(c + begin, c + begin + size, all.c);
    for (std::size_t k = size; k % n != 0; ++k) all.g[k] = 1.0, all.c[k] = 0.0;
    alignas(64) double work[kSubChunk + kMaxLanes];
    for (std::size_t k = 0; k < size; k += n) {
      hn::Vec<decltype(d)> ln_g, m0, stride, w;
      PlanLanes(d, hn::Load(d, all.g + k), hn::Load(d, all.c + k), rule, &ln_g, &m0, &stride, &w);
      hn::Store(ln_g, d, all.ln_g + k);
      hn::Store(m0, d, all.m0 + k);
      hn::Store(stride, d, all.stride + k);
      hn::Store(w, d, work + k);
    }
    // Few queries (a scalar caller's batch of one): the three groups unsorted, not 321 buckets.
    const bool fine = size >= kMinSorted;
    const std::size_t buckets = fine ? kKeys : 3, strided_key = fine ? kUnitKeys : 1;
    std::uint16_t key[kSubChunk], start[kKeys + 1];
    std::fill(start, start + buckets + 1, std::uint16_t{0});
    for (std::size_t k = 0; k < size; ++k) {
      const double s = all.stride[k];
      const double fine_key = s == 1.0              ? std::min(all.m0[k], kUnitKeys - 1.0)
                              : s <= kLaneMaxStride ? kUnitKeys + std::min(16.0 * (work[k] - 2.0), kStridedKeys - 1.0)
                                                    : kKeys - 1.0;
      key[k] = static_cast<std::uint16_t>(fine ? fine_key : s == 1.0 ? 0.0 : s <= kLaneMaxStride ? 1.0 : 2.0);
      ++start[key[k] + 1];
    }
    for (std::size_t b = 1; b <= buckets; ++b) start[b] += start[b - 1];
    const std::size_t unit_end = start[strided_key], strided_end = start[buckets - 1];
    for (std::size_t k = 0; k < size; ++k) {
      const std::size_t to = start[key[k]]++;
      sorted.g[to] = all.g[k], sorted.c[to] = all.c[k], sorted.ln_g[to] = all.ln_g[k];
      sorted.m0[to] = all.m0[k], sorted.stride[to] = all.stride[k];
      sorted.index[to] = static_cast<std::uint32_t>(begin + k);
    }
    for (std::size_t k = strided_end; k < size; ++k) rejected[rejected_count++] = sorted.index[k];
    rejected_count += WalkRange(sorted, 0, unit_end, tol, rejected + rejected_count);
    rejected_count += WalkRange(sorted, unit_end, strided_end, tol, rejected + rejected_count);
    for (std::size_t k = 0; k < strided_end; ++k) sigma[sorted.index[k]] = sorted.sigma[k];
  }
  return rejected_count;
}

// The bicubic spline of ln Sigma (KernelTable::sigma) with one query per lane, in two passes over
// chunks of kTableChunk queries: the first finds each query's cell and offsets (s, t), the second
// loads the 4 x 4 stencil and interpolates. Split, a chunk's loads do not wait behind each vector's
// log; each stencil row is 4 contiguous doubles, loaded per lane and transposed (LoadColumns) so
// that col[b] holds column b of every lane (when it landed, one pass of gathers was 2.3-2.6x slower). The
// table's domain test (KernelTable::contains) and the prefactor are lane operations here too, so
// asf_auto_batch hands every query of a chunk to the table first and routes only those handed back
// (when it landed: asf minus g 11.7 -> 11.1 ns polished, 12.0 -> 10.0 intermediate).
// No prefetches. Hermite's paired nodes (41 MB, until stop 28) spread a polished surface's queries
// past L2, and prefetching each cell row while locating paid (17.0 -> 12.2 ns). The spline's band
// of that surface is ~0.9 MB: prefetching the 4 stencil rows (8 lines a query) cost 3.4-4.0 ns a
// query, and locating the next chunk before interpolating this one (for the prefetches' lead) made
// no difference without them (within +-0.5 ns). 1e6 queries, warm, one CPU, same run, the issue's
// three surfaces (stop 29).
constexpr std::size_t kTableChunk = 64;

// The uniform cubic B-spline's weights at offsets t in [0, 1) (KernelTable::log_sigma's
// cubic_bspline_weights, lane by lane).
template <class D, class V = hn::Vec<D>>
HWY_INLINE void CubicBSplineWeights(D d, V t, V* w) {
  const V sixth = hn::Set(d, 1.0 / 6.0), u = hn::Sub(hn::Set(d, 1.0), t), t2 = hn::Mul(t, t), t3 = hn::Mul(t2, t);
  w[0] = hn::Mul(hn::Mul(hn::Mul(u, u), u), sixth);
  w[1] = hn::Mul(hn::MulAdd(hn::Set(d, 3.0), t3, hn::MulAdd(hn::Set(d, -6.0), t2, hn::Set(d, 4.0))), sixth);
  w[2] = hn::Mul(hn::MulAdd(hn::Set(d, -3.0), t3, hn::MulAdd(hn::Set(d, 3.0), hn::Add(t2, t), hn::Set(d, 1.0))), sixth);
  w[3] = hn::Mul(t3, sixth);
}

std::size_t KernelTableLanes(const KernelTableView& table, const double* g, const double* c, const double* ln_g, std::size_t count,
                             double scale, double* sigma, std::uint32_t* outside) {
  const double* const coefficients = table.coefficients;
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  constexpr std::size_t n = hn::MaxLanes(d);
  static_assert(kTableChunk % n == 0, "whole vectors per chunk");
  const V one = hn::Set(d, 1.0);
  const KernelGrid& grid = table.grid;
  const V inv_dx = hn::Set(d, 1.0 / grid.dx), inv_dz = hn::Set(d, 1.0 / grid.dz);
  // scale e^F as e^(F + ln scale) (KernelTable::scaled_sigma): where e^F alone is subnormal (F <
  // -708) but scale e^F is not, no subnormal number is computed, and the value keeps its precision.
  // Arithmetic on subnormals takes microcode assists: asf minus g at sigma_s = 0.005 um, l_c =
  // 20 um, lambda = 0.5 um, whose far lobe lies there, 12.0 -> 11.4 ns (1e-4: 11.1 -> 10.2;
  // `brdf eval --timing`, same run); the surfaces unchanged. The sum's rounding, <= |F|
  // eps ~ 1e-13 relative, is below F's own.
  const V ln_scale = hn::Set(d, std::log(scale));
  const V g_min = hn::Set(d, kKernelGMin), g_max = hn::Set(d, kKernelGMax);
  const V z_near = hn::Set(d, kKernelZNear), z_far = hn::Set(d, kKernelZFar);
  std::size_t outside_count = 0;
  // A stencil row to the next, in each section; the far section's first coefficient.
  const V near_stride = hn::Set(d, double(grid.row_length(false))), far_stride = hn::Set(d, double(grid.row_length(true)));
  const V far_base = hn::Set(d, double(grid.far_section_offset()));
  alignas(64) double gb[kMaxLanes], cb[kMaxLanes], lb[kMaxLanes], out[kMaxLanes];
  struct Cells {
    // Cell offsets (s, t); beyond[k] = 1 beyond kKernelZFar (where the value is 0), else 0.
    alignas(64) double s[kTableChunk], t[kTableChunk], beyond[kTableChunk];
    // Index of each query's first stencil coefficient, and its section's row length.
    alignas(64) hn::TFromD<decltype(di)> first[kTableChunk], stride[kTableChunk];
  } cells;
  auto locate = [&](std::size_t k0, Cells& at) {
    double* const s_chunk = at.s;
    double* const t_chunk = at.t;
    const std::size_t chunk = std::min(kTableChunk, count - k0);
    for (std::size_t k = 0; k < chunk; k += n) {
      const std::size_t m = std::min(n, chunk - k);
      V vg, vc, vl = hn::Zero(d);
      if (m == n) {
        vg = hn::LoadU(d, g + k0 + k), vc = hn::LoadU(d, c + k0 + k);
        if (ln_g) vl = hn::LoadU(d, ln_g + k0 + k);
      } else {  // the last, partial vector through a padded copy (a cell inside the table)
        for (std::size_t j = 0; j < n; ++j) {
          gb[j] = j < m ? g[k0 + k + j] : 1.0, cb[j] = j < m ? c[k0 + k + j] : 0.0;
          lb[j] = j < m && ln_g ? ln_g[k0 + k + j] : 0.0;
        }
        vg = hn::Load(d, gb), vc = hn::Load(d, cb), vl = hn::Load(d, lb);
      }
      // KernelTable::contains lane by lane (NaN fails every comparison); a lane outside looks up a
      // point inside (g = 1, c = 0), so that no load leaves the table, and is handed back.
      const auto inside = hn::And(hn::And(hn::Ge(vg, g_min), hn::Le(vg, g_max)), hn::Ge(vc, hn::Zero(d)));
      if (!hn::AllTrue(d, inside)) {
        hn::Store(hn::IfThenElseZero(inside, one), d, out);
        for (std::size_t j = 0; j < m; ++j)
          if (out[j] == 0.0) outside[outside_count++] = static_cast<std::uint32_t>(k0 + k + j);
        vg = hn::IfThenElse(inside, vg, one), vc = hn::IfThenElseZero(inside, vc), vl = hn::IfThenElseZero(inside, vl);
      }
      // A caller's ln g spares the logarithm (~0.7 ns of a query's ~3.5: the kernel layout's
      // wavelengths share ln(cos ti + cos ts)). The row is clamped to the table at both ends: at
      // g = kKernelGMin a logarithm a few ulp low could otherwise select row -1 (the scalar
      // lookup's truncation toward 0 does not).
      const V ux = hn::Mul(hn::Sub(ln_g ? vl : hn::Log(d, vg), hn::Set(d, grid.x_min)), inv_dx);
      const V z = hn::Sqrt(hn::Div(vc, hn::Add(vg, one)));
      const V fi = hn::Max(hn::Zero(d), hn::Min(hn::Floor(ux), hn::Set(d, grid.nx - 2.0)));
      // The cell (as KernelTable::sigma): near, column z / dz below kKernelZNear; far, column
      // ln(z / kKernelZNear) / dw of the far section (its log only where a lane needs it); beyond
      // kKernelZFar, a near cell whose value is then replaced by 0.
      V uv = hn::Mul(z, inv_dz), fj = hn::Min(hn::Floor(uv), hn::Set(d, grid.nz - 2.0));
      auto far_cell = hn::FirstN(d, 0), beyond = hn::FirstN(d, 0);  // none
      const auto far = hn::Gt(z, z_near);
      if (!hn::AllFalse(d, far)) {
        beyond = hn::Not(hn::Le(z, z_far));  // +Inf too
        const V uw = hn::Mul(hn::Log(d, hn::Mul(hn::Min(z, z_far), hn::Set(d, 1.0 / kKernelZNear))), hn::Set(d, 1.0 / grid.dw));
        far_cell = hn::AndNot(beyond, far);
        uv = hn::IfThenElse(far_cell, uw, hn::IfThenZeroElse(beyond, uv));
        fj = hn::IfThenElse(far_cell, hn::Min(hn::Floor(uw), hn::Set(d, grid.nw - 2.0)), hn::IfThenZeroElse(beyond, fj));
      }
      // The stencil's first coefficient in its section (row i, column j), and its row length (the
      // sections' rows differ).
      const V stride = hn::IfThenElse(far_cell, far_stride, near_stride);
      const V first = hn::MulAdd(fi, stride, hn::IfThenElse(far_cell, hn::Add(far_base, fj), fj));
      hn::Store(hn::Sub(ux, fi), d, s_chunk + k), hn::Store(hn::Sub(uv, fj), d, t_chunk + k);
      hn::Store(hn::IfThenElseZero(beyond, one), d, at.beyond + k);
      hn::Store(hn::ConvertTo(di, first), di, at.first + k), hn::Store(hn::ConvertTo(di, stride), di, at.stride + k);
    }
  };
  auto interpolate = [&](std::size_t k0, const Cells& at) {
    const double* const s_chunk = at.s;
    const double* const t_chunk = at.t;
    const std::size_t chunk = std::min(kTableChunk, count - k0);
    for (std::size_t k = 0; k < chunk; k += n) {
      const V s = hn::Load(d, s_chunk + k), t = hn::Load(d, t_chunk + k);
      V wx[4], wv[4];
      CubicBSplineWeights(d, s, wx);
      CubicBSplineWeights(d, t, wv);
      V f = hn::Zero(d);
      for (std::size_t a = 0; a < 4; ++a) {
        // Stencil row a of each lane: col[b] = coefficient (i + a, j + b).
        V col[4];
        LoadColumns<4>(d, [&](std::size_t q) { return coefficients + at.first[k + q] + a * at.stride[k + q]; }, col);
        const V row = hn::MulAdd(wv[3], col[3], hn::MulAdd(wv[2], col[2], hn::MulAdd(wv[1], col[1], hn::Mul(wv[0], col[0]))));
        f = hn::MulAdd(wx[a], row, f);
      }
      const V value = hn::IfThenZeroElse(hn::Ne(hn::Load(d, at.beyond + k), hn::Zero(d)), ExpFullRange(d, hn::Add(f, ln_scale)));
      StoreItems(d, value, sigma, k0 + k, k0 + chunk);
    }
  };
  for (std::size_t k0 = 0; k0 < count; k0 += kTableChunk) {
    locate(k0, cells);
    interpolate(k0, cells);
  }
  return outside_count;
}

void LogSpan(const double* x, std::size_t count, double* out) {
  const hn::ScalableTag<double> d;
  alignas(64) double padded[kMaxLanes];
  for (std::size_t k = 0; k < count; k += hn::Lanes(d))
    StoreItems(d, hn::Log(d, hn::LoadU(d, VectorItems(d, x, k, count, padded))), out, k, count);
}

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf {
namespace detail {
HWY_EXPORT(SeriesQueryLanes);
HWY_EXPORT(KernelTableLanes);
HWY_EXPORT(LogSpan);

void log_span(const double* x, std::size_t count, double* out) { HWY_DYNAMIC_DISPATCH(LogSpan)(x, count, out); }

std::size_t series_query_lanes(const double* g, const double* c, std::size_t count, double relative_tolerance,
                               double* sigma, std::uint32_t* rejected) {
  return HWY_DYNAMIC_DISPATCH(SeriesQueryLanes)(g, c, count, relative_tolerance, sigma, rejected);
}

std::size_t kernel_table_lanes(const KernelTableView& table, const double* g, const double* c, const double* ln_g, std::size_t count,
                               double scale, double* out, std::uint32_t* outside) {
  return HWY_DYNAMIC_DISPATCH(KernelTableLanes)(table, g, c, ln_g, count, scale, out, outside);
}
}  // namespace detail

void asf_auto_batch(const double* g, const double* c, std::size_t count, double prefactor, double tolerance,
                    const SeriesOptions& options, double* asf_out, const double* ln_g) {
  auto scalar = [&](std::size_t k) { asf_out[k] = asf_auto(AsfArguments{g[k], c[k], prefactor}, tolerance, nullptr, options); };
  if (options.method != SeriesMethod::simd) {  // the reference methods: query by query
    for (std::size_t k = 0; k < count; ++k) scalar(k);
    return;
  }
  // asf_auto's series truncation, and which batch kernels apply.
  SeriesOptions series = options;
  series.relative_tolerance = detail::auto_series_truncation(tolerance, options.relative_tolerance);
  const bool lanes = series.relative_tolerance >= detail::kLaneMinTolerance;
  const KernelTable* table = options.allow_kernel_table ? KernelTable::for_tolerance(tolerance) : nullptr;
  constexpr std::size_t kChunk = 1024;
  alignas(64) double series_g[kChunk], series_c[kChunk], series_sigma[kChunk];
  std::uint32_t others[kChunk], series_index[kChunk], rejected[kChunk];
  for (std::size_t begin = 0; begin < count; begin += kChunk) {
    const std::size_t end = std::min(count, begin + kChunk);
    // asf_auto's order: the table first (at the default tolerance it takes every query of a
    // chunk, commonly), then the closed forms, then the series, for the queries it leaves.
    std::size_t other_count = end - begin;
    if (table) {
      other_count = table->scaled_sigma_inside(g + begin, c + begin, end - begin, prefactor, asf_out + begin, others,
                                               ln_g ? ln_g + begin : nullptr);
    } else {
      for (std::size_t j = 0; j < other_count; ++j) others[j] = static_cast<std::uint32_t>(j);
    }
    std::size_t sums = 0;
    for (std::size_t j = 0; j < other_count; ++j) {
      const std::size_t k = begin + others[j];
      const double gk = g[k], ck = c[k];
      // A closed form is possible only where its error estimate's leading term is below the
      // tolerance (polished >= g; rough >= 2/g^2). There asf_auto's own choice (asf_regime) is
      // asked, and a closed form it takes is evaluated as asf_auto does, bit for bit; the queries
      // it sends to the series join the lanes below. (Each through asf_auto, query by query, a
      // super-polished surface -- sigma_s = 0.3 nm, l_c = 2 um, lambda = 0.5 um: 40% of queries
      // have g < 1e-5 -- cost ~27 ns per query at tolerance 1e-4, most of it in scalar series.)
      const bool closed_form = tolerance > 0.0 && ((gk > 0.0 && gk < 0.5 && gk < tolerance) || (gk > 50.0 && 2.0 / (gk * gk) < tolerance));
      if (closed_form) {
        const AsfRegime regime = asf_regime(AsfArguments{gk, ck, prefactor}, tolerance, options.allow_kernel_table);
        if (regime == AsfRegime::polished) {
          asf_out[k] = prefactor * mbk_series_polished(gk, ck);
          continue;
        }
        if (regime == AsfRegime::rough) {
          asf_out[k] = prefactor * mbk_series_rough(gk, ck);
          continue;
        }
      }
      if (lanes && gk >= detail::kLaneMinG && gk <= detail::kLaneMaxG && ck >= 0.0 && ck <= detail::kLaneMaxC) {
        series_g[sums] = gk, series_c[sums] = ck, series_index[sums++] = static_cast<std::uint32_t>(k);
      } else {
        scalar(k);
      }
    }
    if (sums > 0) {
      const std::size_t left = detail::series_query_lanes(series_g, series_c, sums, series.relative_tolerance, series_sigma, rejected);
      for (std::size_t j = 0; j < left; ++j) series_sigma[rejected[j]] = mbk_series_sum(series_g[rejected[j]], series_c[rejected[j]], series);
      for (std::size_t j = 0; j < sums; ++j) asf_out[series_index[j]] = prefactor * series_sigma[j];
    }
  }
}

}  // namespace libbrdf
#endif
