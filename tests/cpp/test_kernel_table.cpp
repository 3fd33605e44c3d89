// The fast paths of the ASF (issue 9): the SIMD series against the independent long-double
// reference (test_support.h), and the universal kernel table Sigma(g, c) against the series over
// its whole domain, at the cells' centres (where bicubic interpolation errs most), and at its nodes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "libbrdf/kernel_table.h"
#include "libbrdf/mbk_series.h"
#include "test_support.h"

namespace libbrdf {
// How ctest and gtest name a tier.
void PrintTo(KernelTable::Tier tier, std::ostream* os) { *os << (tier == KernelTable::Tier::fine ? "fine" : "coarse"); }
}  // namespace libbrdf

namespace {

using namespace libbrdf;

// The SIMD series truncated at `tolerance` is within `tolerance` of the long-double reference for
// g log-uniform over [1e-8, 1e7] (strides active from g ~ 64; beyond 1e7 the long-double
// reference's lgamma(m + 1) ~ 1e8 has absolute errors ~1e-11 of its own) and c = 0, log-uniform over
// [1e-3, 1e7], or u g (the lobe of a rough surface). Below ~1e-12 the reference's own precision at
// g ~ 1e7 (Loader's form in double, ~eps sqrt(g)) sets the floor, so the assertion is max(tolerance, 1e-11).
void check_simd_series(double tolerance, int samples) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  SeriesOptions fast;
  fast.method = SeriesMethod::simd;
  fast.relative_tolerance = tolerance;
  double worst = 0.0;
  int strided = 0;
  for (int k = 0; k < samples; ++k) {
    const double g = std::exp(std::log(1e-8) + unit(rng) * (std::log(1e7) - std::log(1e-8)));
    const double pick = unit(rng);
    const double c = pick < 0.1 ? 0.0 : pick < 0.6 ? std::exp(std::log(1e-3) + unit(rng) * std::log(1e10)) : g * 30.0 * unit(rng);
    const long double log_ref = libbrdf_test::windowed_log_series(g, c, 45);
    if (log_ref < -700.0L) continue;
    const double ref = static_cast<double>(std::exp(log_ref));
    SeriesStats stats;
    const double value = mbk_series_sum(g, c, fast, &stats);
    if (stats.stride > 1) ++strided;
    const double rel = std::abs(value - ref) / ref;
    worst = std::max(worst, rel);
    ASSERT_LE(rel, std::max(tolerance, 1e-11)) << "g=" << g << " c=" << c << " stride " << stats.stride;
  }
  std::cout << "[ measured ] SIMD series at tolerance " << tolerance << ": max relative error " << worst << " ("
            << strided << " strided sums)\n";
  EXPECT_GT(strided, samples / 10) << "the sweep must exercise the strided sum";
}

TEST(FastSeries, WithinToleranceOnSweep_1e6) { check_simd_series(1e-6, 3000); }
TEST(FastSeries, WithinToleranceOnSweep_1e9) { check_simd_series(1e-9, 3000); }
TEST(FastSeries, WithinToleranceOnSweep_1e14) { check_simd_series(1e-14, 2000); }

// Bounded time and the limit for g up to the double range (issue 11: g >= 2^31 hung): beyond
// kSeriesRoughLimitG every method returns eq. 15, whose error there is ~1/g.
TEST(FastSeries, HugeAndInfiniteG) {
  for (double g : {1e12, 1e15, 1e16, 1e100, 1e300}) {
    for (double c : {0.0, 0.3 * g, 3.0 * g}) {
      const double value = mbk_series_sum(g, c);
      ASSERT_TRUE(std::isfinite(value)) << g;
      const double limit = mbk_series_rough(g, c);
      if (limit > 0.0) {
        EXPECT_NEAR(value / limit, 1.0, 2e-10 + rough_error_estimate(g, c)) << "g=" << g << " c=" << c;
      }
    }
  }
  EXPECT_EQ(mbk_series_sum(INFINITY, 1.0), 0.0);
  EXPECT_EQ(mbk_series_sum(1.0, INFINITY), 0.0);
  EXPECT_TRUE(std::isnan(mbk_series_sum(NAN, 1.0)));  // never hidden as a value (callers validate)
}

// The reference the table is checked against: the series, every term, truncated at 1e-16.
SeriesOptions reference_series() {
  SeriesOptions reference;
  reference.method = SeriesMethod::every_term;
  reference.relative_tolerance = 1e-16;
  return reference;
}

// Every test below runs on each tier of the table (kernel_table.h: fine 1e-6, coarse 1e-4).
class KernelTableTier : public ::testing::TestWithParam<KernelTable::Tier> {
 protected:
  const KernelTable& table = KernelTable::instance(GetParam());
};
INSTANTIATE_TEST_SUITE_P(Tiers, KernelTableTier, ::testing::Values(KernelTable::Tier::fine, KernelTable::Tier::coarse),
                         [](const ::testing::TestParamInfo<KernelTable::Tier>& tier) {
                           return std::string(tier.param == KernelTable::Tier::fine ? "fine" : "coarse");
                         });

// The certified error of the kernel table: every cell of the near section (in z every row of
// cells of ~150 evenly spaced) at its centre and at a random point, against the reference series
// (every term, 1e-16). The claim (kernel_table.h) must hold with a margin of 2 (what a cell centre
// misses of its worst point). The far section: the next test.
TEST_P(KernelTableTier, CertifiedErrorHoldsOverTheWholeDomain) {
  std::cout << "[ measured ] kernel table " << table.nx() << " x " << table.nz() << " nodes, " << static_cast<double>(table.bytes()) / 1e6
            << " MB, built in " << table.build_seconds() << " s\n";
  const SeriesOptions reference = reference_series();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  const double x_max = std::log(kKernelGMax);
  double worst = 0.0, worst_g = 0.0, worst_z = 0.0;
  long long compared = 0;
  for (int i = 0; i + 1 < table.nx(); ++i) {
    for (int j = 0; j + 1 < table.nz(); j += table.nz() / 150) {  // fine: every sixth row of cells, 83k cells
      for (int point = 0; point < 2; ++point) {
        const double s = point == 0 ? 0.5 : unit(rng), t = point == 0 ? 0.5 : unit(rng);
        const double x = table.x_min() + (i + s) * table.dx(), z = (j + t) * table.dz();
        if (x > x_max || z > kKernelZNear) continue;
        const double g = std::exp(x), c = (g + 1.0) * z * z;
        if (!table.contains(g, c)) continue;
        const double ref = mbk_series_sum(g, c, reference);
        if (!(ref > 1e-300)) continue;
        const double rel = std::abs(table.sigma(g, c) - ref) / ref;
        ++compared;
        if (rel > worst) {
          worst = rel;
          worst_g = g;
          worst_z = z;
        }
      }
    }
  }
  std::cout << "[ measured ] kernel table max relative error " << worst << " at g=" << worst_g << " z=" << worst_z
            << " over " << compared << " points (certified " << table.certified_error() << ")\n";
  EXPECT_GT(compared, 40000);
  EXPECT_LT(2.0 * worst, table.certified_error());
}

// The far section (kKernelZNear < z <= kKernelZFar, nodes even in ln z): every cell, at its centre
// and at a random point, against the same reference; the same claim with the same margin. Its values
// reach ~e^-745 (polished surfaces with l_c / lambda ~ 10 or more, at g << 1).
TEST_P(KernelTableTier, CertifiedErrorHoldsOverTheFarSection) {
  const SeriesOptions reference = reference_series();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  double worst = 0.0, worst_g = 0.0, worst_z = 0.0;
  long long compared = 0;
  for (int i = 0; i + 1 < table.nx(); ++i) {
    for (int k = 0; k + 1 < table.nw(); ++k) {
      for (int point = 0; point < 2; ++point) {
        const double s = point == 0 ? 0.5 : unit(rng), t = point == 0 ? 0.5 : unit(rng);
        const double x = table.x_min() + (i + s) * table.dx(), z = kKernelZNear * std::exp((k + t) * table.dw());
        if (x > std::log(kKernelGMax) || z > kKernelZFar) continue;
        const double g = std::exp(x), c = (g + 1.0) * z * z;
        const double ref = mbk_series_sum(g, c, reference);
        if (!(ref > 1e-300)) continue;
        const double rel = std::abs(table.sigma(g, c) - ref) / ref;
        ++compared;
        if (rel > worst) worst = rel, worst_g = g, worst_z = z;
      }
    }
  }
  std::cout << "[ measured ] kernel table far section (" << table.nw() << " nodes per row) max relative error " << worst
            << " at g=" << worst_g << " z=" << worst_z << " over " << compared << " points (certified " << table.certified_error() << ")\n";
  EXPECT_GT(compared, 10000);
  EXPECT_LT(2.0 * worst, table.certified_error());
}

// Beyond kKernelZFar the table returns 0: it may, because there ln Sigma < -745 (where exp
// underflows and the series returns 0 as well) for every g of the domain. An independent
// long-double sum (test_support.h) at z = kKernelZFar, every 0.01 in ln g, shows it; Sigma
// decreases with c (every term does), so the rest follows. Every lookup gives exactly 0 there.
TEST_P(KernelTableTier, SigmaVanishesBeyondTheFarSection) {
  long double largest = -INFINITY;
  double at_g = 0.0;
  for (double x = std::log(kKernelGMin); x <= std::log(kKernelGMax); x += 0.01) {
    const double g = std::exp(x);
    const long double log_sigma = libbrdf_test::windowed_log_series(g, (g + 1.0) * kKernelZFar * kKernelZFar);
    if (log_sigma > largest) largest = log_sigma, at_g = g;
  }
  std::cout << "[ measured ] largest ln Sigma at z = kKernelZFar: " << static_cast<double>(largest) << " at g=" << at_g << "\n";
  EXPECT_LT(largest, -745.0L - 10.0L);
  std::vector<double> g, c;
  for (double gg : {kKernelGMin, 0.2, 1.0, 1e3, kKernelGMax})
    for (double zz : {std::nextafter(kKernelZFar, INFINITY), 2.0 * kKernelZFar, 1e200}) g.push_back(gg), c.push_back(zz * zz * (gg + 1.0));
  g.push_back(0.2), c.push_back(INFINITY);
  std::vector<double> many(g.size(), -1.0);
  table.sigma_many(g.data(), c.data(), g.size(), many.data());
  for (std::size_t k = 0; k < g.size(); ++k) {
    EXPECT_EQ(table.sigma(g[k], c[k]), 0.0) << "g=" << g[k] << " c=" << c[k];
    EXPECT_EQ(many[k], 0.0) << "g=" << g[k] << " c=" << c[k];
  }
}

// The spline passes through its nodes: at every node of every 7th row (near and far sections, 150
// nodes a row, both ends included) the lookup is the series itself to rounding, far below the
// certified error, which is reached mid-cell (kernel_table.h). A wrong stencil offset, weight or
// row length would show here at the size of a cell's variation (up to ~|F_v dv| ~ 1 relative).
TEST_P(KernelTableTier, SplinePassesThroughItsNodes) {
  const SeriesOptions reference = reference_series();
  double worst = 0.0, worst_g = 0.0, worst_z = 0.0;
  long long compared = 0;
  for (int i = 0; i < table.nx(); i += 7) {
    const double g = std::exp(table.x_min() + i * table.dx());
    if (!(g <= kKernelGMax)) continue;
    for (const bool far : {false, true}) {
      const int n = far ? table.nw() : table.nz();
      for (int j = 0; j < n; j += std::max(1, n / 150)) {
        const double z = far ? kKernelZNear * std::exp(j * table.dw()) : j * table.dz();
        if (z > (far ? kKernelZFar : kKernelZNear)) continue;
        const double c = (g + 1.0) * z * z;
        const double ref = mbk_series_sum(g, c, reference);
        if (!(ref > 1e-300)) continue;
        const double rel = std::abs(table.sigma(g, c) - ref) / ref;
        ++compared;
        if (rel > worst) worst = rel, worst_g = g, worst_z = z;
      }
    }
  }
  std::cout << "[ measured ] kernel table at its nodes: max relative error " << worst << " at g=" << worst_g << " z=" << worst_z
            << " over " << compared << " nodes\n";
  EXPECT_GT(compared, 5000);
  EXPECT_LT(worst, 1e-3 * table.certified_error());
}

// The table the library embeds (computed at build time by libbrdf_generate_kernel_table) is the
// one its coefficients' computation gives now, bit for bit: the build's output is reproducible and not stale.
TEST_P(KernelTableTier, EmbeddedIsTheComputedTableBitForBit) {
  EXPECT_TRUE(table.embedded());
  EXPECT_LT(table.build_seconds(), 0.01) << "an embedded table costs a process nothing to start";
  const std::vector<double> computed = KernelTable::compute_coefficients(GetParam());
  ASSERT_EQ(computed.size(), table.value_count());
  std::size_t differing = 0, non_finite = 0;
  for (std::size_t k = 0; k < computed.size(); ++k) {
    differing += std::memcmp(&computed[k], table.coefficients() + k, sizeof(double)) != 0;
    non_finite += !std::isfinite(table.coefficients()[k]);
  }
  EXPECT_EQ(differing, 0u) << "of " << computed.size() << " coefficients";
  EXPECT_EQ(non_finite, 0u) << "the spline of ln Sigma has finite coefficients everywhere";
}

TEST_P(KernelTableTier, DomainEdges) {
  EXPECT_FALSE(table.contains(0.5 * kKernelGMin, 0.0));
  EXPECT_FALSE(table.contains(2.0 * kKernelGMax, 0.0));
  EXPECT_FALSE(table.contains(1.0, -1e-300));
  EXPECT_TRUE(table.contains(kKernelGMin, 0.0));
  EXPECT_TRUE(table.contains(1.0, INFINITY));  // beyond kKernelZFar: 0
  // The largest g and z of each section uses a cell of the table, not one beyond it (at
  // z = kKernelZNear itself Sigma ~ e^-900 / g underflows at g = kKernelGMax, so z = 25 there; at
  // kKernelZFar it has underflowed for every g, so z = 150 at g = 0.2, Sigma ~ e^-720).
  for (const auto& [g, z] : {std::pair{kKernelGMax, 25.0}, std::pair{1.0, kKernelZNear}, std::pair{0.2, 150.0}}) {
    const double c = z * z * (g + 1.0);
    EXPECT_NEAR(table.sigma(g, c) / mbk_series_sum(g, c), 1.0, table.certified_error()) << "g=" << g << " z=" << z;
  }
}

// asf_auto at a tolerance at or above a tier's certified error uses the coarsest such table inside
// the domain (its very value), and no table below the fine one's error.
TEST(KernelTable, ChosenOnlyWhereCertified) {
  const KernelTable& fine = KernelTable::instance(KernelTable::Tier::fine);
  const KernelTable& coarse = KernelTable::instance(KernelTable::Tier::coarse);
  EXPECT_EQ(KernelTable::for_tolerance(1e-2), &coarse);
  EXPECT_EQ(KernelTable::for_tolerance(coarse.certified_error()), &coarse);
  EXPECT_EQ(KernelTable::for_tolerance(0.5 * coarse.certified_error()), &fine);
  EXPECT_EQ(KernelTable::for_tolerance(fine.certified_error()), &fine);
  EXPECT_EQ(KernelTable::for_tolerance(0.5 * fine.certified_error()), nullptr);
  AsfRegime regime;
  for (const KernelTable* table : {&fine, &coarse}) {
    EXPECT_EQ(asf_auto(AsfArguments{3.0, 10.0, 1.0}, table->certified_error(), &regime), table->sigma(3.0, 10.0));
    EXPECT_EQ(regime, AsfRegime::table);
  }
  EXPECT_NE(fine.sigma(3.0, 10.0), coarse.sigma(3.0, 10.0));  // two tables, not one
  asf_auto(AsfArguments{3.0, 10.0, 1.0}, 0.5 * kKernelTableCertifiedError, &regime);
  EXPECT_EQ(regime, AsfRegime::series);
  asf_auto(AsfArguments{0.5 * kKernelGMin, 1e3, 1.0}, 1e-2, &regime);
  EXPECT_NE(regime, AsfRegime::table);
}

// The lookup in SIMD lanes (sigma_many) is the same interpolation as sigma: equal to rounding
// (ln Sigma down to ~-900, so ~1e-13 relative after exp) on random in-domain points of both
// sections and beyond, the domain's corners and a count that is not a whole number of vectors, on
// every Highway target.
TEST_P(KernelTableTier, SigmaManyEqualsSigma) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<double> g, c;
  for (double gg : {kKernelGMin, 1.0, kKernelGMax})
    for (double zz : {0.0, 0.5, kKernelZNear, std::nextafter(kKernelZNear, INFINITY), kKernelZFar}) g.push_back(gg), c.push_back(zz * zz * (gg + 1.0));
  while (g.size() < 1003) {  // both sections and beyond
    const double gg = std::exp(std::log(kKernelGMin) + unit(rng) * std::log(kKernelGMax / kKernelGMin));
    const double zz = (g.size() % 2 ? kKernelZNear : 1.1 * kKernelZFar) * unit(rng);
    g.push_back(gg), c.push_back(zz * zz * (gg + 1.0));
  }
  // On every Highway target this machine runs: each transposes the stencil rows its own way
  // (simd_transpose-inl.h: 8, 4 or 2 lanes).
  libbrdf_test::for_each_simd_target([&](std::int64_t) {
    std::vector<double> many(g.size());
    table.sigma_many(g.data(), c.data(), g.size(), many.data());
    for (std::size_t k = 0; k < g.size(); ++k) {
      ASSERT_TRUE(table.contains(g[k], c[k]));
      const double one = table.sigma(g[k], c[k]);
      ASSERT_NEAR(many[k], one, 1e-12 * one) << "g=" << g[k] << " c=" << c[k];
    }
  });
}

// The lane kernel's own domain test is contains(): queries just outside every edge, NaN and Inf
// are handed back (exactly those, in order), the others get scale x sigma; sigma_many gives NaN
// outside.
TEST_P(KernelTableTier, ScaledLookupHandsBackExactlyTheQueriesOutside) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const double z2 = kKernelZFar * kKernelZFar;
  std::vector<double> g, c;
  auto add = [&](double gg, double cc) { g.push_back(gg), c.push_back(cc); };
  for (int k = 0; k < 3; ++k) {  // each edge on either side, amid points inside
    add(kKernelGMin, 1.0), add(std::nextafter(kKernelGMin, 0.0), 1.0);
    add(kKernelGMax, 1.0), add(std::nextafter(kKernelGMax, inf), 1.0);
    add(2.0, 0.0), add(2.0, -1e-300);
    add(0.2, z2 * 1.2), add(0.2, std::nextafter(z2 * 1.2, inf));  // the far section's end: inside, then 0
    add(nan, 1.0), add(1.0, nan), add(inf, 1.0), add(1.0, inf), add(0.3, 20.0);
  }
  const double scale = 3.5;
  std::vector<double> out(g.size(), -1.0), many(g.size());
  std::vector<std::uint32_t> outside(g.size());
  const std::size_t count = table.scaled_sigma_inside(g.data(), c.data(), g.size(), scale, out.data(), outside.data());
  table.sigma_many(g.data(), c.data(), g.size(), many.data());
  std::vector<std::uint32_t> expected;
  for (std::size_t k = 0; k < g.size(); ++k) {
    if (!table.contains(g[k], c[k])) {
      expected.push_back(static_cast<std::uint32_t>(k));
      EXPECT_TRUE(std::isnan(many[k])) << k;
      continue;
    }
    const double one = table.sigma(g[k], c[k]);
    EXPECT_NEAR(out[k], scale * one, 1e-12 * scale * one) << "g=" << g[k] << " c=" << c[k];
    EXPECT_NEAR(many[k], one, 1e-12 * one) << k;
  }
  EXPECT_EQ(expected.size(), 3u * 6u);  // the construction above: 6 of 13 per round outside
  EXPECT_EQ(std::vector<std::uint32_t>(outside.begin(), outside.begin() + static_cast<std::ptrdiff_t>(count)), expected);
}

// A caller's ln g (the kernel layout: 2 ln(g_scale |cos ti + cos ts|), shared by its wavelengths)
// gives the lookup with the table's own logarithm to rounding, hands back the same queries, and
// cannot select a row outside the table at g = kKernelGMin with ln g rounded low.
TEST_P(KernelTableTier, CallersLogarithmGivesTheSameLookups) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> cos_sum(0.02, 2.0), eta(0.0, 4.0), scale_log(std::log(1e-3), std::log(100.0));
  std::vector<double> g, c, ln_g;
  for (int k = 0; k < 4000; ++k) {
    const double ln_scale = scale_log(rng), s = cos_sum(rng);
    const double g_scale = std::exp(ln_scale);
    g.push_back((g_scale * s) * (g_scale * s));
    c.push_back(eta(rng) * 40.0);
    ln_g.push_back(2.0 * (ln_scale + std::log(s)));
  }
  g.push_back(kKernelGMin), c.push_back(3.0), ln_g.push_back(std::nextafter(std::log(kKernelGMin), -1e300) - 1e-12);
  g.push_back(1.0), c.push_back(-1.0), ln_g.push_back(0.0);  // outside: handed back either way
  const std::size_t n = g.size();
  std::vector<double> own(n), shared(n);
  std::vector<std::uint32_t> outside_own(n), outside_shared(n);
  const std::size_t own_count = table.scaled_sigma_inside(g.data(), c.data(), n, 2.0, own.data(), outside_own.data());
  const std::size_t shared_count = table.scaled_sigma_inside(g.data(), c.data(), n, 2.0, shared.data(), outside_shared.data(), ln_g.data());
  std::vector<std::uint32_t> expected;  // g spans 4e-10 .. 4e4: some below and above the table
  for (std::size_t k = 0; k < n; ++k)
    if (!table.contains(g[k], c[k])) expected.push_back(static_cast<std::uint32_t>(k));
  ASSERT_GT(expected.size(), 100u);
  ASSERT_LT(expected.size(), n / 2);
  EXPECT_EQ(std::vector<std::uint32_t>(outside_own.begin(), outside_own.begin() + static_cast<std::ptrdiff_t>(own_count)), expected);
  EXPECT_EQ(std::vector<std::uint32_t>(outside_shared.begin(), outside_shared.begin() + static_cast<std::ptrdiff_t>(shared_count)), expected);
  double worst = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!table.contains(g[k], c[k])) continue;
    ASSERT_TRUE(std::isfinite(shared[k]) && shared[k] >= 0.0) << k;
    if (own[k] > 0.0) worst = std::max(worst, std::abs(shared[k] - own[k]) / own[k]);
  }
  // ln Sigma moves by (d ln Sigma / d ln g) x ln g's rounding, ~1e-14: the slope is the index of
  // the largest term, up to ~100 here (measured 1.0e-12).
  EXPECT_LE(worst, 4e-12);
  EXPECT_NEAR(shared[n - 2], 2.0 * table.sigma(kKernelGMin, 3.0), 1e-9 * shared[n - 2]);
}

}  // namespace
