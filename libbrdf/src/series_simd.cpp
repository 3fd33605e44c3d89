// The MBK series Sigma(g, c) of eq. 11 summed in SIMD blocks: Google Highway with run-time
// dispatch (one binary runs with SSE2/SSSE3/SSE4, AVX2 or AVX-512 as the CPU allows; nothing is
// compiled for the build machine only). Why Highway: Debian 12 ships it (libhwy-dev 1.0.3) with
// vector exp/log/log1p of 1-4 ulp (hwy/contrib/math) and dynamic dispatch built in; xsimd has no
// run-time dispatch of its own and SLEEF has no portable vector types.
//
// Each lane holds one term m of the window (m = m0 + stride * k): its logarithm in C. Loader's
// saddle-point form (as the scalar reference, mbk_series.cpp), then exp relative to the largest
// term. Blocks walk up and down from the mode until the geometric tail bound holds (the terms are
// log-concave in m, so the ratio of the last two lanes bounds every later ratio).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "series_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <cmath>

#include "series_simd.h"
#include "series_terms-inl.h"  // LogTerm

HWY_BEFORE_NAMESPACE();
namespace libbrdf::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

double SumSeriesBlocks(const SeriesPlan& plan, SeriesBlockStats* stats, SeriesMomentSums* moments) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t n = hn::Lanes(d);
  const double lanes = static_cast<double>(n), stride = plan.stride;
  const V g = hn::Set(d, plan.g), ln_g = hn::Set(d, std::log(plan.g)), c = hn::Set(d, plan.c);
  const V offsets = hn::Mul(hn::Iota(d, 0.0), hn::Set(d, stride));
  const V one = hn::Set(d, 1.0);
  // Terms are summed relative to exp(reference), the largest log-term met so far; a block with a
  // larger one rescales the sum (so an inexact mode guess costs blocks, never overflow).
  double reference = -HUGE_VAL, sum = 0.0;
  long long blocks = 0;
  const double tol = plan.relative_tolerance;
  alignas(64) double t[HWY_MAX_BYTES / sizeof(double)];
  // One block: lanes m = base + stride * k (k = 0..n-1, or k = 0..-(n-1) going down), m >= 1 kept.
  // Returns the last two lanes' terms (in walking order) for the tail bound.
  auto block = [&](double base, int direction, double* last, double* previous) {
    const V m_raw = hn::Add(hn::Set(d, base), direction > 0 ? offsets : hn::Neg(offsets));
    const auto valid = hn::Ge(m_raw, one);
    const V log_terms = LogTerm(d, hn::Max(m_raw, one), g, ln_g, c);
    const double block_max = hn::GetLane(hn::MaxOfLanes(d, hn::IfThenElse(valid, log_terms, hn::Set(d, -HUGE_VAL))));
    if (block_max > reference) {
      const double rescale = sum > 0.0 ? std::exp(reference - block_max) : 0.0;
      sum *= rescale;
      if (moments) {
        moments->b *= rescale;
        moments->c *= rescale;
        moments->d *= rescale;
        moments->e *= rescale;
      }
      reference = block_max;
    }
    const V terms = hn::IfThenElseZero(valid, hn::Exp(d, hn::Sub(log_terms, hn::Set(d, reference))));
    sum += hn::GetLane(hn::SumOfLanes(d, terms));
    if (moments) {  // sums of t_m (m - g), t_m / m, t_m (m - g) / m, t_m / m^2 (poisson.h)
      const V m = hn::Max(m_raw, one);
      const V shifted = hn::Mul(terms, hn::Sub(m, g)), inv = hn::Div(one, m);
      moments->b += hn::GetLane(hn::SumOfLanes(d, shifted));
      moments->c += hn::GetLane(hn::SumOfLanes(d, hn::Mul(terms, inv)));
      moments->d += hn::GetLane(hn::SumOfLanes(d, hn::Mul(shifted, inv)));
      moments->e += hn::GetLane(hn::SumOfLanes(d, hn::Mul(hn::Mul(terms, inv), inv)));
    }
    ++blocks;
    hn::Store(terms, d, t);
    *last = t[n - 1];
    *previous = n >= 2 ? t[n - 2] : *previous;  // one-lane targets: the previous block's last term
  };
  // Stop walking when the remaining tail is below 0.45 tol (each direction; the stride's aliasing
  // takes at most tol/10, so the total stays below tol). Bounded: terms are log-concave in m away from the
  // first two, so past the largest term each ratio of consecutive (strided) terms bounds the next.
  auto tail_done = [&](double last, double previous) {
    if (last == 0.0) return true;
    const double ratio = last / previous;
    return ratio < 1.0 && last * ratio / (1.0 - ratio) <= 0.45 * tol * sum;
  };
  // The first block is centred on the mode guess (clipped at m = 1), then walks up and down.
  const double first = std::max(1.0, plan.mode - std::floor(0.5 * lanes) * stride);
  double last = 0.0, previous = 0.0;
  block(first, +1, &last, &previous);
  for (double base = first + lanes * stride; !tail_done(last, previous); base += lanes * stride) block(base, +1, &last, &previous);
  // Downward from below the first block, checking after each block.
  double down_last = 0.0, down_previous = 0.0;
  if (first > 1.0) {
    for (double base = first - stride; base >= 1.0; base -= lanes * stride) {
      block(base, -1, &down_last, &down_previous);
      if (!(base - stride * (lanes - 1.0) >= 1.0)) break;  // reached m = 1
      if (tail_done(down_last, down_previous)) break;
    }
  }
  if (stats) stats->blocks = blocks;
  if (moments) {
    moments->log_scale = reference + std::log(stride);
    moments->a = sum;
  }
  if (!(sum > 0.0)) return 0.0;
  const double log_value = reference + std::log(sum * stride);
  return log_value < -745.0 ? 0.0 : std::exp(log_value);
}

std::size_t SeriesLanes() { return hn::Lanes(hn::ScalableTag<double>()); }
const char* SeriesTargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace libbrdf::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace libbrdf::detail {
HWY_EXPORT(SumSeriesBlocks);

double sum_series_blocks(const SeriesPlan& plan, SeriesBlockStats* stats, SeriesMomentSums* moments) {
  return HWY_DYNAMIC_DISPATCH(SumSeriesBlocks)(plan, stats, moments);
}

HWY_EXPORT(SeriesLanes);
HWY_EXPORT(SeriesTargetName);
std::size_t series_lanes() { return HWY_DYNAMIC_DISPATCH(SeriesLanes)(); }
const char* series_target_name() { return HWY_DYNAMIC_DISPATCH(SeriesTargetName)(); }
}  // namespace libbrdf::detail
#endif
