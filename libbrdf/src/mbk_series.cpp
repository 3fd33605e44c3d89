#include "libbrdf/mbk_series.h"

#include "libbrdf/kernel_table.h"
#include "poisson.h"
#include "series_simd.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace libbrdf {
namespace {

constexpr double kLn2Pi = 1.8378770664093454836;
// exp(x) underflows to 0 below this (smallest subnormal ~ e^-745).
constexpr double kLogUnderflow = -745.0;

// Stirling-series error delta(m) = ln m! - (m ln m - m + ln(2 pi m)/2), m >= 1.
// Exact (from lgamma) below 16, where the asymptotic series is not yet at double precision.
double stirling_error(std::int64_t m) {
  static const std::array<double, 16> table = [] {
    std::array<double, 16> t{};
    for (int k = 1; k < 16; ++k) {
      long double mk = k;
      t[k] = static_cast<double>(std::lgamma(mk + 1.0L) - (mk * std::log(mk) - mk + 0.5L * std::log(2.0L * 3.141592653589793238462643383279502884L * mk)));
    }
    return t;
  }();
  if (m < 16) return table[m];
  const double inv = 1.0 / static_cast<double>(m), inv2 = inv * inv;
  return inv * (1.0 / 12 - inv2 * (1.0 / 360 - inv2 * (1.0 / 1260 - inv2 / 1680)));
}

// g * bd(m/g) with bd(x) = x ln x - x + 1 >= 0, accurate where m ~ g (no cancellation).
double poisson_deviance_half(std::int64_t m, double g) {
  const double dm = static_cast<double>(m);
  const double x = dm / g;
  if (std::abs(x - 1.0) < 0.5) {
    const double y = (dm - g) / g;
    return g * ((1.0 + y) * std::log1p(y) - y);
  }
  return dm * std::log(x) - dm + g;
}

}  // namespace

// ln of the Poisson weight e^-g g^m / m! in the saddle-point form of C. Loader, "Fast and
// accurate computation of binomial probabilities" (2000): full relative precision even for
// g ~ 1e6, where m ln g - ln m! - g loses ~10 digits to cancellation.
double detail::log_poisson_weight(std::int64_t m, double g) {
  return -poisson_deviance_half(m, g) - 0.5 * (kLn2Pi + std::log(static_cast<double>(m))) - stirling_error(m);
}

namespace {

// ln of term m of Sigma(g, c): Poisson weight x (1/m) x Gaussian exp(-c/m).
double log_term(std::int64_t m, double g, double c) {
  const double dm = static_cast<double>(m);
  return detail::log_poisson_weight(m, g) - std::log(dm) - c / dm;
}

// ln(t_{m+1} / t_m) = ln g + ln m - 2 ln(m+1) + c / (m (m+1)); strictly decreasing in m, so the
// terms are log-concave in m and have one largest term.
double log_ratio(std::int64_t m, double ln_g, double c) {
  const double dm = static_cast<double>(m);
  return ln_g + std::log(dm) - 2.0 * std::log(dm + 1.0) + c / (dm * (dm + 1.0));
}

// Index of the largest term: the smallest m >= 1 with log_ratio(m) < 0 (bisection on a
// monotone function). Upper bound: at m = 2 max(g, sqrt c) + 2 the ratio is below -0.4.
// 64-bit: the mode is ~g, and g ~ 1e9 (sigma_s/lambda ~ 2500) must not overflow.
std::int64_t largest_term_index(double g, double c) {
  const double ln_g = std::log(g);
  if (log_ratio(1, ln_g, c) < 0.0) return 1;
  const double bound = 2.0 * std::max(g, std::sqrt(c)) + 2.0;
  std::int64_t lo = 1;  // log_ratio(lo) >= 0
  std::int64_t hi = static_cast<std::int64_t>(std::min(bound, 1.0e15));
  while (hi - lo > 1) {
    const std::int64_t mid = lo + (hi - lo) / 2;
    (log_ratio(mid, ln_g, c) >= 0.0 ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace

namespace {

// The scalar reference walk: from the largest term (exact index) outward, ln of every
// stride-th term by Loader's form, until the geometric bound on the rest of the tail (the ratio of
// consecutive terms only decreases away from the mode) is below tol x the sum. *sum_out: the sum of
// the terms relative to the largest (before the x stride). Returns ln of the largest term (-inf
// when it underflows: *sum_out is 0 then).
// Stride (allow_stride, for wide windows): Poisson summation, stride <= width/2 keeps the aliasing
// error ~exp(-8 pi^2) ~ 1e-34; the window must stay 12 widths clear of m = 1, where the sum is cut off.
double walk_series(double g, double c, double tol, bool allow_stride, double* sum_out, std::int64_t* stride_out,
                   std::int64_t* mode_out, long long* evaluated_out) {
  const std::int64_t mode = largest_term_index(g, c);
  const double log_peak = log_term(mode, g, c);
  *mode_out = mode;
  *stride_out = 1;
  *evaluated_out = 1;
  *sum_out = 0.0;
  // Everything below the peak's underflow margin is 0 in double precision anyway.
  if (log_peak < kLogUnderflow - 40.0) return -std::numeric_limits<double>::infinity();
  std::int64_t stride = 1;
  if (allow_stride && mode > 64) {
    const double ln_g = std::log(g);
    const double curvature = log_ratio(mode - 1, ln_g, c) - log_ratio(mode, ln_g, c);
    const double width = 1.0 / std::sqrt(std::max(curvature, 1e-300));
    if (static_cast<double>(mode) - 12.0 * width > 1.0) stride = std::max<std::int64_t>(1, static_cast<std::int64_t>(width / 2.0));
  }
  *stride_out = stride;
  double sum = 1.0;
  long long evaluated = 1;
  auto walk = [&](std::int64_t step) {
    double previous = 1.0;
    for (std::int64_t m = mode + step; m >= 1; m += step) {
      const double term = std::exp(log_term(m, g, c) - log_peak);
      ++evaluated;
      sum += term;
      const double ratio = term / previous;
      if (ratio < 1.0 && term * ratio / (1.0 - ratio) <= tol * sum) break;
      if (term == 0.0) break;
      previous = term;
    }
  };
  walk(stride);
  walk(-stride);
  *evaluated_out = evaluated;
  *sum_out = sum;
  return log_peak;
}

}  // namespace

namespace {

// A guess of the largest term's index: the stationary point of ln t_m without its O(1/m) terms,
// ln(m/g) = c/m^2. With w = 2 ln(m/g) this is w e^w = 2c/g^2, so m = sqrt(2c / W(2c/g^2)) with
// Lambert's W (m -> g as c -> 0). W by Winitzki's closed form (relative error < 2%; S. Winitzki,
// LNCS 2667, 780, 2003): a guess within a few terms of the mode, no iteration. The summation
// does not rely on the guess being exact (it rescales when it meets a larger term).
double mode_guess(double g, double c) {
  const double ln_g = std::log(g);
  if (ln_g - 2.0 * std::log(2.0) + 0.5 * c < 0.0) return 1.0;  // log_ratio(1) < 0: the first term is largest
  const double q = 2.0 * c / (g * g);
  if (!(q > 1e-8)) return std::max(1.0, std::round(g));  // W(q) ~ q: m ~ g (1 + c/g^2)
  const double l = std::log1p(q);
  const double w = l * (1.0 - std::log1p(l) / (2.0 + l));
  return std::max(1.0, std::round(std::sqrt(2.0 * c / w)));
}

}  // namespace

// Stride: the strided sum d * sum_k t(m0 + k d) differs from the full sum by the aliases of the
// terms' Fourier transform (Poisson summation), ~2 exp(-2 pi^2 (s/d)^2) for a window of standard
// deviation s; d is chosen so that this is below tol/10, and only where the window lies clear
// of m = 1 (the cut-off), sqrt(2 ln(20/tol)) + 1 widths. The measured error of this rule over a (g, c) sweep is asserted by
// tests/cpp/test_series.cpp (FastSeries.*).
// Widths per stride at least: skewed windows alias more than the Gaussian estimate says (the
// sweeps of tests/cpp/test_kernel_table.cpp hold with this floor).
constexpr double kMinWidthPerStride = 2.0;
detail::StrideRule detail::stride_rule(double relative_tolerance) {
  const double log_budget = std::log(20.0 / relative_tolerance);
  return StrideRule{std::max(kMinWidthPerStride, std::sqrt(log_budget / (2.0 * kPi * kPi))), std::sqrt(2.0 * log_budget) + 1.0};
}

namespace {

// The plan of the SIMD summation: window start, stride (detail::stride_rule), truncation tolerance.
detail::SeriesPlan series_plan(double g, double c, double relative_tolerance, bool allow_stride) {
  detail::SeriesPlan plan;
  plan.g = g;
  plan.c = c;
  plan.mode = mode_guess(g, c);
  plan.relative_tolerance = relative_tolerance;
  const double m = plan.mode;
  if (allow_stride && m > detail::kStrideMinMode) {
    // Curvature of ln t_m at the mode: psi'(m+1) - 1/m^2 + 2c/m^3, psi'(m+1) ~ 1/(m + 1/2).
    const double curvature = 1.0 / (m + 0.5) - 1.0 / (m * m) + 2.0 * c / (m * m * m);
    const double width = 1.0 / std::sqrt(curvature);
    const detail::StrideRule rule = detail::stride_rule(relative_tolerance);
    const double stride = std::floor(width / rule.widths_per_stride);
    if (stride >= 2.0 && m - rule.clearance_widths * width > 1.0) plan.stride = stride;
  }
  return plan;
}

}  // namespace

double mbk_series_sum(double g, double c, const SeriesOptions& options, SeriesStats* stats) {
  if (std::isnan(g) || std::isnan(c)) return std::numeric_limits<double>::quiet_NaN();  // never hidden
  if (!(g > 0.0) || c == std::numeric_limits<double>::infinity()) return 0.0;  // sigma_s = 0: no scatter
  // Beyond g = 1e15 the very-rough limit eq. 15 is the series to rough_error_estimate(g, c)
  // (~1e-15 relative): summing ~sqrt(g) terms there would only take time (g = inf gives 0).
  // From g ~ 1e10 the SIMD sum's rounding (~eps sqrt(g), in Loader's deviance) exceeds the limit's
  // own error wherever that is below 1e-9.
  if (g > kSeriesRoughLimitG || (g > 1e10 && rough_error_estimate(g, c) < 1e-9)) {
    if (stats) *stats = SeriesStats{0, 0, 0};
    return mbk_series_rough(g, c);
  }
  if (options.method == SeriesMethod::simd) {
    const detail::SeriesPlan plan = series_plan(g, c, options.relative_tolerance, true);
    detail::SeriesBlockStats block_stats;
    const double value = detail::sum_series_blocks(plan, &block_stats);
    if (stats) *stats = SeriesStats{block_stats.blocks * static_cast<long long>(detail::series_lanes()),
                                    static_cast<long long>(plan.stride), static_cast<long long>(plan.mode)};
    return value;
  }
  long long evaluated = 0;
  std::int64_t stride = 1, mode = 0;
  double sum = 0.0;
  const double log_peak = walk_series(g, c, options.relative_tolerance, options.method == SeriesMethod::strided, &sum,
                                      &stride, &mode, &evaluated);
  if (stats) *stats = SeriesStats{evaluated, stride, mode};
  if (!(sum > 0.0)) return 0.0;
  const double log_value = log_peak + std::log(sum * static_cast<double>(stride));
  return log_value < kLogUnderflow ? 0.0 : std::exp(log_value);
}

detail::SeriesMoments detail::series_moments(double g, double c) {
  // The SIMD blocks at a 1e-16 truncation (stride aliasing below 1e-17): the kernel table's
  // 84k nodes in ~50 ms. Rounding ~eps sqrt(g) (Loader's form in double): < 1e-12 for g <= 1e7.
  const detail::SeriesPlan plan = series_plan(g, c, 1e-16, true);
  detail::SeriesMomentSums sums;
  detail::sum_series_blocks(plan, nullptr, &sums);
  return detail::SeriesMoments{sums.log_scale, sums.a, sums.b, sums.c, sums.d, sums.e};
}

double mbk_series_polished(double g, double c) { return g * std::exp(-c); }

double mbk_series_rough(double g, double c) {
  if (!(g > 0.0) || std::isinf(g)) return 0.0;
  return std::exp(-c / g) / g;
}

double polished_error_estimate(double g, double c) {
  // Relative size of the m = 2 and m = 3 terms against m = 1, plus the dropped e^-g.
  const double second = 0.25 * g * std::exp(0.5 * c);
  const double third = (g * g / 18.0) * std::exp(2.0 * c / 3.0);
  return g + second + third;
}

double rough_error_estimate(double g, double c) {
  if (!(g > 0.0)) return std::numeric_limits<double>::infinity();
  const double u = c / g;
  // Delta method on E[exp(-c/m)/m], m ~ Poisson(g): first-order term, then a bound on the next
  // order (fourth central moment 3g^2 + g), then the e^-g of the m = 0 term the form ignores.
  // The next order's coefficient is 2 (1 + u)^4: at u = 0 the error against the series is exactly
  // 1/g + 1/g^2 + 3/g^3 + ..., so a coefficient of 1 was optimistic there (by 0.13% at g = 50,
  // tests/cpp MbkSeries.RoughErrorEstimateBoundsActualError).
  const double first = std::abs(u * u - 4.0 * u + 2.0) / (2.0 * g);
  const double next = 2.0 * std::pow(1.0 + u, 4) / (g * g);
  return first + next + std::exp(-g) * (1.0 + g);
}

void asf_auto_geometries(const Surface& surface, const ScatterGeometry* geos, std::size_t count, double tolerance,
                         const SeriesOptions& options, double* asf_out) {
  constexpr std::size_t kBlock = 256;
  double g[kBlock], c[kBlock];
  const AsfScales scales = asf_scales(surface);
  for (std::size_t begin = 0; begin < count; begin += kBlock) {
    const std::size_t n = std::min(kBlock, count - begin);
    for (std::size_t k = 0; k < n; ++k) {
      const AsfArguments args = asf_arguments(scales, geos[begin + k]);
      g[k] = args.g;
      c[k] = args.c;
    }
    asf_auto_batch(g, c, n, scales.prefactor, tolerance, options, asf_out + begin);
  }
}

double asf(const Surface& surface, const ScatterGeometry& geo, const SeriesOptions& options) {
  const AsfArguments args = asf_arguments(surface, geo);
  return args.prefactor * mbk_series_sum(args.g, args.c, options);
}

double asf_auto(const AsfArguments& args, double tolerance, AsfRegime* regime, const SeriesOptions& options) {
  SeriesOptions series = options;
  series.relative_tolerance = detail::auto_series_truncation(tolerance, options.relative_tolerance);
  const AsfRegime chosen = asf_regime(args, tolerance, options.allow_kernel_table);
  if (regime) *regime = chosen;
  switch (chosen) {
    case AsfRegime::polished: return args.prefactor * mbk_series_polished(args.g, args.c);
    case AsfRegime::rough: return args.prefactor * mbk_series_rough(args.g, args.c);
    // The coarsest certified table, the prefactor inside its exp (as the lanes: no subnormal Sigma).
    case AsfRegime::table: return KernelTable::for_tolerance(tolerance)->scaled_sigma(args.g, args.c, args.prefactor);
    default: return args.prefactor * mbk_series_sum(args.g, args.c, series);
  }
}

AsfRegime asf_regime(const AsfArguments& args, double tolerance, bool allow_table) {
  // The fastest form whose error bound meets the tolerance: a kernel table (the coarsest whose
  // certified error does, KernelTable::for_tolerance; in lanes it is faster than the scalar closed
  // forms; both tiers have one domain), the closed forms (their leading-order error estimates),
  // else the series.
  const KernelTable* table = allow_table ? KernelTable::for_tolerance(tolerance) : nullptr;  // as asf_auto_batch
  if (table && table->contains(args.g, args.c))
    return AsfRegime::table;
  if (tolerance > 0.0 && args.g > 0.0 && args.g < 0.5 && polished_error_estimate(args.g, args.c) < tolerance)
    return AsfRegime::polished;
  if (tolerance > 0.0 && args.g > 50.0 && rough_error_estimate(args.g, args.c) < tolerance) return AsfRegime::rough;
  return AsfRegime::series;
}

}  // namespace libbrdf
