// The MBK series Sigma(g, c) of eq. 11 against an independent long-double brute-force sum, its
// closed-form limits (eqs 14, 15), the automatic regime choice, and the paper's regime thresholds
// (g < 0.025 polished, g > 800 very rough; measured and printed, not asserted).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "libbrdf/geometry.h"
#include "libbrdf/mbk_series.h"
#include "libbrdf/surface.h"
#include "test_support.h"

namespace {

using namespace libbrdf;
using libbrdf_test::brute_force_log_series;
using libbrdf_test::brute_force_series;
using libbrdf_test::deg;

std::vector<double> logspace(double lo, double hi, int count) {
  std::vector<double> out;
  for (int i = 0; i < count; ++i) out.push_back(lo * std::pow(hi / lo, i / double(count - 1)));
  return out;
}

// Values of Sigma below this are subnormal or 0 in double: compared only for being tiny.
constexpr double kUnderflow = 1e-290;

void check_against_brute_force(SeriesMethod method) {
  SeriesOptions options;
  options.method = method;
  std::vector<double> cs{0.0};
  for (double c : logspace(1e-6, 1e4, 31)) cs.push_back(c);
  int compared = 0;
  double worst = 0;
  for (double g : logspace(1e-8, 1e4, 49)) {
    for (double c : cs) {
      const long double log_ref = brute_force_log_series(g, c);
      const double value = mbk_series_sum(g, c, options);
      ASSERT_TRUE(std::isfinite(value) && value >= 0.0) << "g=" << g << " c=" << c << " value " << value;
      if (log_ref < std::log(kUnderflow)) {
        EXPECT_LE(value, 1e-280) << "reference underflows (ln = " << static_cast<double>(log_ref) << ") at g=" << g << " c=" << c;
        continue;
      }
      const double ref = static_cast<double>(std::exp(log_ref));
      const double rel = std::fabs(value - ref) / ref;
      worst = std::max(worst, rel);
      ++compared;
      EXPECT_LE(rel, 1e-10) << "g=" << g << " c=" << c << " series " << value << " brute force " << ref;
    }
  }
  EXPECT_GT(compared, 1000) << "too few non-underflowed points compared";
  std::cout << "[ measured ] max relative error vs long-double brute force: " << worst << " over " << compared
            << " points\n";
  testing::Test::RecordProperty("max_relative_error", std::to_string(worst));
}

TEST(MbkSeries, EveryTermMatchesLongDoubleBruteForceTo1e10) { check_against_brute_force(SeriesMethod::every_term); }

TEST(MbkSeries, StridedMatchesLongDoubleBruteForceTo1e10) { check_against_brute_force(SeriesMethod::strided); }

TEST(MbkSeries, RandomPointsMatchBruteForceBothMethods) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> log_g(std::log(1e-8), std::log(1e4)), log_u(std::log(1e-4), std::log(1e2));
  for (int i = 0; i < 400; ++i) {
    const double g = std::exp(log_g(rng));
    const double c = g * std::exp(log_u(rng));  // c relative to g: the lobe of a rough surface
    const long double log_ref = brute_force_log_series(g, c);
    if (log_ref < std::log(kUnderflow)) continue;
    const double ref = static_cast<double>(std::exp(log_ref));
    for (SeriesMethod method : {SeriesMethod::every_term, SeriesMethod::strided}) {
      SeriesOptions options;
      options.method = method;
      const double value = mbk_series_sum(g, c, options);
      ASSERT_LE(std::fabs(value - ref) / ref, 1e-10) << "g=" << g << " c=" << c << " method " << int(method);
    }
  }
}

TEST(MbkSeries, ReferenceWindowedSumEqualsFullBruteForce) {
  // The scans below use the test's windowed long-double sum; it must equal the full m = 1..M sum.
  for (double g : {1e-6, 0.3, 7.0, 120.0, 3e3}) {
    for (double u : {0.0, 0.2, 1.0, 5.0, 50.0}) {
      const long double full = brute_force_log_series(g, u * g), windowed = libbrdf_test::windowed_log_series(g, u * g);
      EXPECT_NEAR(static_cast<double>(windowed - full), 0.0, 1e-13) << "g=" << g << " c=" << u * g;
    }
  }
}

TEST(MbkSeries, StridedSumsFewerTermsForWideWindows) {
  SeriesOptions every, strided;
  every.method = SeriesMethod::every_term;
  strided.method = SeriesMethod::strided;
  SeriesStats a, b;
  mbk_series_sum(1e4, 10.0, every, &a);
  mbk_series_sum(1e4, 10.0, strided, &b);
  EXPECT_GT(b.stride, 1);
  EXPECT_LT(b.terms_evaluated * 4, a.terms_evaluated) << "strided " << b.terms_evaluated << " vs " << a.terms_evaluated;
}

TEST(MbkSeries, ZeroRoughnessGivesZeroAndNoNaN) {
  EXPECT_EQ(mbk_series_sum(0.0, 0.0), 0.0);
  EXPECT_EQ(mbk_series_sum(0.0, 5.0), 0.0);
  EXPECT_EQ(mbk_series_rough(0.0, 1.0), 0.0);
  EXPECT_EQ(mbk_series_polished(0.0, 1.0), 0.0);
}

// eq. 14: Sigma / (g e^-c) = e^-g (1 + (g/4) e^{c/2} + O(g^2)), so |ratio - 1| / g tends to
// |e^{c/2}/4 - 1| as g -> 0 (near specular, c = O(1)).
TEST(MbkSeries, PolishedFormRatioTendsToOneAsGVanishes) {
  for (double c : {0.0, 1.0, 5.0}) {
    const double slope = std::fabs(std::exp(0.5 * c) / 4.0 - 1.0);
    double previous = 1.0;
    for (double g : {1e-2, 1e-3, 1e-4, 1e-6, 1e-8}) {
      const double ratio = mbk_series_polished(g, c) / static_cast<double>(brute_force_series(g, c));
      const double deviation = std::fabs(ratio - 1.0);
      EXPECT_LT(deviation, previous) << "c=" << c << " g=" << g;
      if (g <= 1e-4) {
        EXPECT_NEAR(deviation / g, slope, 0.01 * slope + 1e-4) << "c=" << c << " g=" << g;
      }
      previous = deviation;
    }
  }
}

// eq. 15: Sigma = E[exp(-c/m)/m], m ~ Poisson(g); the delta method gives
// Sigma / ((1/g) e^{-c/g}) = 1 + (u^2 - 4u + 2) / (2g) + O(1/g^2), u = c/g.
TEST(MbkSeries, RoughFormRelativeErrorIsOrderOneOverG) {
  for (double u : {0.0, 0.5, 1.0, 3.0}) {
    const double coefficient = std::fabs(u * u - 4 * u + 2) / 2;
    for (double g : {1e2, 1e3, 1e4}) {
      const double c = u * g;
      const double ref = static_cast<double>(brute_force_series(g, c));
      const double scaled = g * std::fabs(mbk_series_rough(g, c) / ref - 1.0);
      // g * error -> coefficient with an O(1/g) correction whose size is ~(1+u)^4.
      EXPECT_NEAR(scaled, coefficient, 3.0 * std::pow(1 + u, 4) / g) << "u=" << u << " g=" << g;
    }
  }
}

// Beyond what a brute-force sum can reach (the mode m ~ g passes 2^31 at g ~ 2e9): the strided
// series must still sum, and agree with the very-rough limit to its first-order error
// |u^2 - 4u + 2| / (2g), up to the next order and the double rounding of the Poisson deviance,
// whose absolute error grows like 1e-16 sqrt(g) (~3e-12 at g = 1e9).
TEST(MbkSeries, HugeGBeyond32BitIndicesMatchesRoughLimit) {
  for (double g : {1e9, 5e9}) {
    for (double u : {0.0, 1.0, 5.0}) {
      const double c = u * g;
      SeriesStats stats;
      const double series = mbk_series_sum(g, c, SeriesOptions{}, &stats);
      ASSERT_TRUE(std::isfinite(series) && series > 0.0) << "g=" << g << " u=" << u << " value " << series;
      EXPECT_GT(stats.mode_m, 1LL << 29) << "mode index must be near g";
      EXPECT_GT(stats.stride, 1) << "a window of width ~sqrt(g) is summed with a stride";
      const double relative = std::fabs(series / mbk_series_rough(g, c) - 1.0);
      const double expected = std::fabs(u * u - 4 * u + 2) / (2 * g);
      EXPECT_NEAR(relative, expected, 5.0 * std::pow(1 + u, 4) / (g * g) + 2e-16 * std::sqrt(g))
          << "g=" << g << " u=" << u;
    }
  }
}

// The estimates that drive the regime choice must bound the actual error (against the
// long-double series) wherever they are small enough to matter (< 0.5).
TEST(MbkSeries, RoughErrorEstimateBoundsActualError) {
  double worst = 0;
  for (double g = 50.0; g < 2e4; g *= 1.25) {
    for (double u = 0.0; u < 12.0; u += 0.1) {
      const double estimate = rough_error_estimate(g, u * g);
      if (!(estimate < 0.5)) continue;
      const double ref = static_cast<double>(std::exp(libbrdf_test::windowed_log_series(g, u * g, 45)));
      const double actual = std::fabs(mbk_series_rough(g, u * g) - ref) / ref;
      worst = std::max(worst, actual / estimate);
      ASSERT_LE(actual, estimate) << "g=" << g << " u=" << u << ": actual " << actual << " > estimate " << estimate;
    }
  }
  std::cout << "[ measured ] rough: max actual/estimate " << worst << "\n";
}

TEST(MbkSeries, PolishedErrorEstimateBoundsActualError) {
  double worst = 0;
  for (double g = 1e-10; g < 0.5; g *= 1.5) {
    for (double c = 0.0; c < 60.0; c += 0.25) {
      const double estimate = polished_error_estimate(g, c);
      if (!(estimate < 0.5)) continue;
      const double ref = static_cast<double>(brute_force_series(g, c));
      const double actual = std::fabs(mbk_series_polished(g, c) - ref) / ref;
      worst = std::max(worst, actual / estimate);
      ASSERT_LE(actual, estimate) << "g=" << g << " c=" << c << ": actual " << actual << " > estimate " << estimate;
    }
  }
  std::cout << "[ measured ] polished: max actual/estimate " << worst << "\n";
}

struct RegimeCounts {
  int polished = 0, rough = 0, series = 0, table = 0;
};

// Whenever asf_auto picks a closed form, its actual error against the (brute-force) series is
// below the tolerance. Points: g log-uniform over [1e-8, 1e7] (beyond the physical 1e4, so that the
// rough form is reachable at tolerance 1e-6); c log-uniform over [1e-6, 1e4],
// or u g with u log-uniform over [1e-3, 30] (the lobe of a rough surface), or 0. With the kernel
// table allowed it takes most of its domain (1e-5 <= g <= 1e7), so the closed forms' choice is
// checked with it disallowed.
RegimeCounts check_auto_regime(double tolerance, int samples, double* worst_polished, double* worst_rough, bool allow_table) {
  SeriesOptions options;
  options.allow_kernel_table = allow_table;
  std::mt19937_64 rng(static_cast<unsigned long>(1e6 * tolerance) + 3);
  std::uniform_real_distribution<double> log_g(std::log(1e-8), std::log(1e7)), log_c(std::log(1e-6), std::log(1e4)),
      log_u(std::log(1e-3), std::log(30.0)), unit(0, 1);
  RegimeCounts counts;
  *worst_polished = *worst_rough = 0;
  for (int i = 0; i < samples; ++i) {
    const double g = std::exp(log_g(rng));
    const double pick = unit(rng);
    const double c = pick < 0.45 ? std::exp(log_c(rng)) : pick < 0.9 ? g * std::exp(log_u(rng)) : 0.0;
    AsfRegime regime;
    const double value = asf_auto(AsfArguments{g, c, 1.0}, tolerance, &regime, options);
    const long double log_ref = libbrdf_test::windowed_log_series(g, c, 45);  // dropped tail < 1e-16 relative
    if (log_ref < std::log(kUnderflow)) continue;
    const double ref = static_cast<double>(std::exp(log_ref));
    const double rel = std::fabs(value - ref) / ref;
    if (regime == AsfRegime::polished) {
      ++counts.polished;
      *worst_polished = std::max(*worst_polished, rel);
    } else if (regime == AsfRegime::rough) {
      ++counts.rough;
      *worst_rough = std::max(*worst_rough, rel);
    } else if (regime == AsfRegime::table) {
      ++counts.table;
    } else {
      ++counts.series;
    }
    // Every method the choice makes, the series (truncated at tolerance/10) and the kernel table
    // included, is within the tolerance.
    const char* names[] = {"series", "polished", "rough", "table"};
    EXPECT_LT(rel, tolerance) << names[static_cast<int>(regime)] << " chosen at g=" << g
                              << " c=" << c << " (u=c/g=" << c / g << "): error " << rel << " >= tolerance " << tolerance;
  }
  return counts;
}

// Dense scan of the rough regime's boundary, where the first-order estimate |u^2 - 4u + 2|/(2g)
// vanishes (u = 2 -+ sqrt 2) and only the higher orders protect the choice: a coarse grid in
// u = c/g over [0, 8] plus fine grids within 0.05 of both zeros.
void check_rough_boundary(double tolerance) {
  SeriesOptions no_table;  // the closed form's choice itself (the table would take g <= 1e7)
  no_table.allow_kernel_table = false;
  std::vector<double> us;
  for (double u = 0.0; u < 8.0; u += 0.03) us.push_back(u);
  for (double root : {2.0 - std::sqrt(2.0), 2.0 + std::sqrt(2.0)})
    for (double d = -0.05; d <= 0.05; d += 0.001) us.push_back(root + d);
  int chosen = 0;
  for (double g = 50.0; g < 2e4; g *= 1.15) {
    for (double u : us) {
      AsfRegime regime;
      const double value = asf_auto(AsfArguments{g, u * g, 1.0}, tolerance, &regime, no_table);
      if (regime != AsfRegime::rough) continue;
      ++chosen;
      const double ref = static_cast<double>(std::exp(libbrdf_test::windowed_log_series(g, u * g, 45)));
      ASSERT_LT(std::fabs(value - ref) / ref, tolerance) << "rough chosen at g=" << g << " u=" << u;
    }
  }
  EXPECT_GT(chosen, 0) << "the scan never reached the rough regime";
}

class AutoRegime : public testing::TestWithParam<double> {};

TEST_P(AutoRegime, ChosenClosedFormIsWithinTolerance) {
  const double tolerance = GetParam();
  double worst_polished, worst_rough;
  for (bool allow_table : {false, true}) {
    const RegimeCounts counts = check_auto_regime(tolerance, 2500, &worst_polished, &worst_rough, allow_table);
    std::cout << "[ measured ] tol " << tolerance << (allow_table ? "" : ", no kernel table") << ": polished chosen "
              << counts.polished << "x (max error " << worst_polished << "), rough " << counts.rough << "x (max error "
              << worst_rough << "), table " << counts.table << "x, series " << counts.series << "x\n";
    if (allow_table) {  // the table wherever it is certified and holds (g, c): most of the points
      EXPECT_GT(counts.table, 1500);
    } else {  // the test must exercise both closed forms
      EXPECT_EQ(counts.table, 0);
      EXPECT_GT(counts.polished, 50);
      EXPECT_GT(counts.rough, 20);
    }
  }
}

TEST_P(AutoRegime, RoughChoiceNearEstimateZerosIsWithinTolerance) { check_rough_boundary(GetParam()); }

TEST_P(AutoRegime, PolishedChoiceScanIsWithinTolerance) {
  const double tolerance = GetParam();
  SeriesOptions no_table;  // the closed form's choice itself (the table would take g >= 1e-5)
  no_table.allow_kernel_table = false;
  int chosen = 0;
  for (double g = 1e-9; g < 0.5; g *= 1.15) {
    for (double c = 0.0; c < 60.0; c += 0.05) {
      AsfRegime regime;
      const double value = asf_auto(AsfArguments{g, c, 1.0}, tolerance, &regime, no_table);
      if (regime != AsfRegime::polished) continue;
      ++chosen;
      const double ref = static_cast<double>(brute_force_series(g, c));
      ASSERT_LT(std::fabs(value - ref) / ref, tolerance) << "polished chosen at g=" << g << " c=" << c;
    }
  }
  EXPECT_GT(chosen, 100);
}

TEST(AutoRegimeZero, ToleranceZeroAlwaysSumsTheSeries) {
  for (double g : {1e-8, 1e-3, 1.0, 1e3, 1e4}) {
    AsfRegime regime;
    asf_auto(AsfArguments{g, 0.1 * g, 1.0}, 0.0, &regime);
    EXPECT_EQ(regime, AsfRegime::series) << "g=" << g;
  }
}

INSTANTIATE_TEST_SUITE_P(Tolerances, AutoRegime, testing::Values(1e-6, 1e-4, 1e-2),
                         [](const testing::TestParamInfo<double>& param_info) {
                           return param_info.param == 1e-6 ? std::string("Tol1e6")
                                                           : param_info.param == 1e-4 ? "Tol1e4" : "Tol1e2";
                         });

// asf_auto_batch against the long-double reference and against asf_auto query by query, at the
// default tolerance and the kernel table's. Grid: g log-spaced over [1e-8, 1e7] plus 0; c = 0,
// log-spaced over [1e-6, 1e7], and u g with u in [1e-3, 30] (a rough surface's lobe), the whole
// grid in one shuffled batch (the batch sorts and packs queries of every regime into lanes).
// Method choice: where asf_auto takes a closed form the batch is bit-identical (asf_regime chooses it);
// elsewhere both are the same method, so they agree well inside the tolerance: the table to
// rounding, two series truncated at tolerance/10 to tolerance/5 -- a table value where asf_auto
// sums the series (or the reverse) would differ by up to the table's certified 1e-4.
void check_batch_against_reference(double tolerance) {
  std::vector<double> g_values, c_values;
  std::vector<double> gs = logspace(1e-8, 1e7, 61);
  gs.push_back(0.0);
  for (double g : gs) {
    std::vector<double> cs{0.0};
    for (double c : logspace(1e-6, 1e7, 27)) cs.push_back(c);
    for (double u : logspace(1e-3, 30.0, 9)) cs.push_back(u * g);
    for (double c : cs) g_values.push_back(g), c_values.push_back(c);
  }
  std::vector<std::size_t> order(g_values.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::shuffle(order.begin(), order.end(), std::mt19937_64(5));
  std::vector<double> g(order.size()), c(order.size()), batch(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) g[k] = g_values[order[k]], c[k] = c_values[order[k]];
  const double prefactor = 3.0;
  asf_auto_batch(g.data(), c.data(), g.size(), prefactor, tolerance, SeriesOptions{}, batch.data());
  double worst = 0.0, worst_vs_scalar = 0.0;
  int compared = 0;
  const char* names[] = {"series", "polished", "rough", "table"};
  for (std::size_t k = 0; k < g.size(); ++k) {
    ASSERT_TRUE(std::isfinite(batch[k]) && batch[k] >= 0.0) << "g=" << g[k] << " c=" << c[k] << ": " << batch[k];
    AsfRegime regime;
    const double scalar = asf_auto(AsfArguments{g[k], c[k], prefactor}, tolerance, &regime);
    const double agreement = regime == AsfRegime::series ? tolerance / 5 : regime == AsfRegime::table ? 1e-12 : 0.0;
    const double vs_scalar = scalar > 0.0 ? std::fabs(batch[k] - scalar) / scalar : batch[k];
    worst_vs_scalar = std::max(worst_vs_scalar, vs_scalar);
    EXPECT_LE(vs_scalar, agreement) << names[static_cast<int>(regime)] << " chosen by asf_auto at g=" << g[k] << " c=" << c[k]
                                    << ": batch " << batch[k] << ", asf_auto " << scalar;
    const long double log_ref = libbrdf_test::windowed_log_series(g[k], c[k], 45);
    if (log_ref < std::log(kUnderflow)) {
      EXPECT_LE(batch[k], 1e-280) << "reference underflows at g=" << g[k] << " c=" << c[k];
      continue;
    }
    const double ref = prefactor * static_cast<double>(std::exp(log_ref));
    const double rel = std::fabs(batch[k] - ref) / ref;
    worst = std::max(worst, rel);
    ++compared;
    EXPECT_LT(rel, tolerance) << names[static_cast<int>(regime)] << " at g=" << g[k] << " c=" << c[k] << ": batch "
                              << batch[k] << ", reference " << ref;
  }
  EXPECT_GT(compared, 1500);
  std::cout << "[ measured ] asf_auto_batch tol " << tolerance << ": max relative error " << worst << " over " << compared
            << " points; max difference from asf_auto " << worst_vs_scalar << "\n";
}

TEST(AsfAutoBatch, WithinToleranceAndSameMethodAsScalar_1e6) { check_batch_against_reference(1e-6); }
TEST(AsfAutoBatch, WithinToleranceAndSameMethodAsScalar_1e4) { check_batch_against_reference(1e-4); }

// A value depends on its own query only (every lane computes alone): the same bits in a batch, in
// the reversed batch and alone (count 1), so that a scalar call and an array call agree (batch.h).
TEST(AsfAutoBatch, ValueDependsOnItsOwnQueryOnly) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<double> g, c;
  for (int k = 0; k < 3000; ++k) {
    g.push_back(std::exp(std::log(1e-8) + unit(rng) * std::log(1e15)));
    c.push_back(unit(rng) < 0.1 ? 0.0 : g.back() * std::exp(std::log(1e-3) + unit(rng) * std::log(1e5)));
  }
  for (double tolerance : {1e-6, 1e-4}) {
    std::vector<double> forward(g.size()), backward(g.size());
    asf_auto_batch(g.data(), c.data(), g.size(), 1.0, tolerance, SeriesOptions{}, forward.data());
    std::vector<double> rg(g.rbegin(), g.rend()), rc(c.rbegin(), c.rend());
    asf_auto_batch(rg.data(), rc.data(), g.size(), 1.0, tolerance, SeriesOptions{}, backward.data());
    for (std::size_t k = 0; k < g.size(); ++k) {
      double alone = 0.0;
      asf_auto_batch(&g[k], &c[k], 1, 1.0, tolerance, SeriesOptions{}, &alone);
      ASSERT_EQ(forward[k], alone) << "tol " << tolerance << " g=" << g[k] << " c=" << c[k];
      ASSERT_EQ(forward[k], backward[g.size() - 1 - k]) << "tol " << tolerance << " g=" << g[k] << " c=" << c[k];
    }
  }
}

// The reference methods and tolerance 0 go through asf_auto query by query: bit-identical.
TEST(AsfAutoBatch, ReferenceMethodsAndToleranceZeroAreAsfAuto) {
  const double g[] = {1e-3, 0.7, 5.0, 80.0, 2e4}, c[] = {0.5, 3.0, 40.0, 100.0, 1e3};
  double out[5];
  for (SeriesMethod method : {SeriesMethod::every_term, SeriesMethod::strided, SeriesMethod::simd}) {
    SeriesOptions options;
    options.method = method;
    for (double tolerance : {0.0, 1e-6}) {
      asf_auto_batch(g, c, 5, 2.0, tolerance, options, out);
      for (int k = 0; k < 5; ++k) {
        const double scalar = asf_auto(AsfArguments{g[k], c[k], 2.0}, tolerance, nullptr, options);
        if (method != SeriesMethod::simd || tolerance == 0.0) EXPECT_EQ(out[k], scalar) << "g=" << g[k];
        else EXPECT_NEAR(out[k], scalar, 2e-7 * scalar) << "g=" << g[k];
      }
    }
  }
}

// The paper (after Krywonos) calls a surface polished for g < 0.025 and very rough for g > 800,
// "less than 1% error ... when theta_i <= 70 deg". Measured here over the lobe (ASF values above
// 1e-3 of the peak at each theta_i), at points that satisfy the g condition themselves.
struct ThresholdError {
  double max_relative = 0;   // max |form - series| / series over the lobe
  double max_of_peak = 0;    // max |form - series| / peak
  int points = 0;
};

ThresholdError measure_threshold(const Surface& surface, bool polished) {
  SeriesOptions series;
  series.method = SeriesMethod::strided;
  ThresholdError out;
  for (double ti_deg = 0; ti_deg <= 70.0; ti_deg += 5.0) {
    struct Point {
      double value, form, g;
    };
    std::vector<Point> points;
    double peak = 0;
    for (double ts_deg = 0; ts_deg < 89.9; ts_deg += 0.5) {
      for (double phi_deg = 0; phi_deg <= 180.0; phi_deg += 2.0) {
        const ScatterGeometry geo = make_scatter_geometry({deg(ti_deg), deg(ts_deg), deg(phi_deg)});
        const AsfArguments a = asf_arguments(surface, geo);
        const double value = mbk_series_sum(a.g, a.c, series);
        const double form = polished ? mbk_series_polished(a.g, a.c) : mbk_series_rough(a.g, a.c);
        points.push_back({value, form, a.g});
        peak = std::max(peak, value);
      }
    }
    for (const Point& p : points) {
      if (p.value < 1e-3 * peak) continue;
      if (polished ? !(p.g < 0.025) : !(p.g > 800)) continue;
      ++out.points;
      out.max_relative = std::max(out.max_relative, std::fabs(p.form - p.value) / p.value);
      out.max_of_peak = std::max(out.max_of_peak, std::fabs(p.form - p.value) / peak);
    }
  }
  return out;
}

TEST(PaperThresholds, MeasurePolishedFormErrorBelowG0_025) {
  // sigma/lambda with g(0, 0) = (4 pi sigma/lambda)^2 = 0.025: every point has g <= 0.025.
  const double sigma = std::sqrt(0.025) / (4 * kPi) * 0.999;
  for (double lc : {1.0, 3.0, 10.0}) {
    const ThresholdError e = measure_threshold(Surface{sigma, lc, 1.0}, true);
    std::cout << "[ measured ] polished (eq. 14) vs series, g < 0.025, ti <= 70, l_c/lambda = " << lc
              << ": max relative error over the lobe " << e.max_relative << ", max error / peak " << e.max_of_peak
              << " (" << e.points << " points)\n";
    RecordProperty("polished_lc" + std::to_string(int(lc)) + "_max_rel", std::to_string(e.max_relative));
    RecordProperty("polished_lc" + std::to_string(int(lc)) + "_max_of_peak", std::to_string(e.max_of_peak));
    EXPECT_GT(e.points, 100);
  }
}

TEST(PaperThresholds, MeasureRoughFormErrorAboveG800) {
  for (const Surface& surface : {Surface{3.0, 30.0, 1.0}, Surface{10.0, 100.0, 1.0}, Surface{10.0, 40.0, 1.0}}) {
    const ThresholdError e = measure_threshold(surface, false);
    std::cout << "[ measured ] rough (eq. 15) vs series, g > 800, ti <= 70, sigma/lambda = " << surface.sigma_s_um
              << ", l_c/lambda = " << surface.lc_um << ": max relative error over the lobe " << e.max_relative
              << ", max error / peak " << e.max_of_peak << " (" << e.points << " points)\n";
    RecordProperty("rough_s" + std::to_string(int(surface.sigma_s_um)) + "_lc" + std::to_string(int(surface.lc_um)) + "_max_rel",
                   std::to_string(e.max_relative));
    EXPECT_GT(e.points, 100);
  }
}

}  // namespace
