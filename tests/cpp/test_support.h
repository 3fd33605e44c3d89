#pragma once
// Independent reference machinery for the core tests: a long-double brute-force MBK series, the
// test's own Gauss-Legendre rules and an adaptive integrator. Nothing here calls the library, so
// the references do not share code (or bugs) with the functions under test. Also the loop that
// runs a test body on every Highway target (for_each_simd_target).
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <vector>

namespace libbrdf_test {

inline constexpr long double kPiL = 3.141592653589793238462643383279502884L;

// ln of Sigma(g, c) = e^-g sum_{m>=1} g^m / (m! m) exp(-c/m), summed term by term in long double
// (m = 1..M: M is past the largest term and far enough that the rest is < 1e-30 of the sum).
// Returns -inf for g = 0.
inline long double brute_force_log_series(long double g, long double c) {
  if (!(g > 0)) return -INFINITY;
  const long double log_g = std::log(g);
  auto log_term = [&](long double m) { return m * log_g - std::lgamma(m + 1) - std::log(m) - c / m - g; };
  std::vector<long double> logs;
  long double peak = -INFINITY;
  // Past the mode when the term ratio g m / (m+1)^2 * exp(c / (m(m+1))) < 1, i.e. at the latest
  // m ~ max(g, sqrt c); keep going until the terms are 70 e-folds below the largest one.
  const long double past_mode = 2.0L * std::max(g, std::sqrt(c)) + 10.0L;
  for (long m = 1;; ++m) {
    const long double lt = log_term(static_cast<long double>(m));
    logs.push_back(lt);
    peak = std::max(peak, lt);
    if (m > past_mode && lt < peak - 70.0L) break;
  }
  long double sum = 0;
  for (long double lt : logs) sum += std::exp(lt - peak);
  return peak + std::log(sum);
}

inline long double brute_force_series(long double g, long double c) { return std::exp(brute_force_log_series(g, c)); }

// The same sum restricted to the terms within `efolds` e-folds of the largest one (the terms are
// log-concave in m: ln(t_{m+1}/t_m) = ln g + ln m - 2 ln(m+1) + c/(m(m+1)) decreases), found by
// bisection and walked outward term by term. For the many-point scans where 1..M is too slow.
inline long double windowed_log_series(long double g, long double c, long double efolds = 70) {
  if (!(g > 0)) return -INFINITY;
  const long double log_g = std::log(g);
  auto log_term = [&](long m) {
    const long double dm = static_cast<long double>(m);
    return dm * log_g - std::lgamma(dm + 1) - std::log(dm) - c / dm - g;
  };
  auto log_ratio = [&](long m) {
    const long double dm = static_cast<long double>(m);
    return log_g + std::log(dm) - 2 * std::log(dm + 1) + c / (dm * (dm + 1));
  };
  long lo = 1, hi = static_cast<long>(2.0L * std::max(g, std::sqrt(c))) + 10;
  if (log_ratio(1) < 0) {
    hi = 1;
  } else {
    while (hi - lo > 1) {
      const long mid = lo + (hi - lo) / 2;
      (log_ratio(mid) >= 0 ? lo : hi) = mid;
    }
  }
  const long mode = hi;
  const long double peak = log_term(mode);
  long double sum = 1;
  for (long m = mode + 1;; ++m) {
    const long double d = log_term(m) - peak;
    sum += std::exp(d);
    if (d < -efolds) break;
  }
  for (long m = mode - 1; m >= 1; --m) {
    const long double d = log_term(m) - peak;
    sum += std::exp(d);
    if (d < -efolds) break;
  }
  return peak + std::log(sum);
}

// Gauss-Legendre nodes and weights on [-1, 1] by Newton's method on P_n in long double.
struct Rule {
  std::vector<long double> x, w;
};
inline Rule gauss_legendre_rule(int n) {
  Rule r{std::vector<long double>(n), std::vector<long double>(n)};
  for (int i = 0; i < n; ++i) {
    long double x = std::cos(kPiL * (i + 0.75L) / (n + 0.5L)), dp = 1;
    for (int it = 0; it < 60; ++it) {
      long double p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const long double pk = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = pk;
      }
      dp = n * (x * p1 - p0) / (x * x - 1);
      const long double dx = p1 / dp;
      x -= dx;
      if (std::fabs(dx) < 1e-19L) break;
    }
    r.x[i] = x;
    r.w[i] = 2 / ((1 - x * x) * dp * dp);
  }
  return r;
}

// Adaptive quadrature: a panel is accepted when its 10-point Gauss-Legendre value agrees with the
// sum over its two halves to `tolerance` (absolute); otherwise both halves recurse.
class AdaptiveIntegrator {
 public:
  AdaptiveIntegrator() : rule_(gauss_legendre_rule(10)) {}

  // Integral of f over the panels [b0, b1], [b1, b2], ... with a relative tolerance.
  double integrate(const std::function<double(double)>& f, const std::vector<double>& breaks,
                   double relative_tolerance) const {
    std::vector<double> coarse(breaks.size() - 1);
    double scale = 0;
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
      coarse[i] = panel(f, breaks[i], breaks[i + 1]);
      scale += std::fabs(coarse[i]);
    }
    if (scale == 0) return 0;
    const double tol = relative_tolerance * scale / static_cast<double>(coarse.size());
    double total = 0;
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i) total += refine(f, breaks[i], breaks[i + 1], coarse[i], tol, 0);
    return total;
  }

 private:
  double panel(const std::function<double(double)>& f, double a, double b) const {
    const long double half = 0.5L * (b - a), mid = 0.5L * (a + b);
    long double s = 0;
    for (std::size_t k = 0; k < rule_.x.size(); ++k) s += rule_.w[k] * f(static_cast<double>(mid + half * rule_.x[k]));
    return static_cast<double>(s * half);
  }
  double refine(const std::function<double(double)>& f, double a, double b, double whole, double tol, int depth) const {
    const double m = 0.5 * (a + b);
    const double left = panel(f, a, m), right = panel(f, m, b);
    if (std::fabs(left + right - whole) <= tol || depth >= 40) return left + right;
    return refine(f, a, m, left, 0.5 * tol, depth + 1) + refine(f, m, b, right, 0.5 * tol, depth + 1);
  }
  Rule rule_;
};

// Breakpoints on [lo, hi] graded geometrically towards `centre` (inside [lo, hi]) down to `finest`.
inline std::vector<double> graded_breaks(double lo, double hi, double centre, double finest) {
  std::vector<double> left, right;
  for (double d = finest; centre - d > lo; d *= 2) left.push_back(centre - d);
  for (double d = finest; centre + d < hi; d *= 2) right.push_back(centre + d);
  std::vector<double> out{lo};
  for (auto it = left.rbegin(); it != left.rend(); ++it) out.push_back(*it);
  if (centre > lo && centre < hi) out.push_back(centre);
  for (double x : right) out.push_back(x);
  out.push_back(hi);
  return out;
}

inline double relative_difference(double a, double b) {
  if (a == b) return 0.0;
  return std::fabs(a - b) / std::max(std::fabs(a), std::fabs(b));
}

inline constexpr double deg(double degrees) { return degrees * 3.14159265358979323846 / 180.0; }

// body(target) on every Highway target this machine runs and the build generated, with the
// dispatch forced to it (and restored afterwards, also when an assertion leaves body).
template <class Body>
void for_each_simd_target(const Body& body) {
  struct RestoreTargets {
    ~RestoreTargets() { hwy::SetSupportedTargetsForTest(0); }
  } restore;
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
    SCOPED_TRACE(hwy::TargetName(target));
    hwy::SetSupportedTargetsForTest(target);
    body(target);
  }
}

}  // namespace libbrdf_test
