// Streaming benchmarks (bench_eval, bench_lookup): each iteration handles the next batch of a large
// query set, timed by the thread's CPU time, with quantiles over the batches. The machine this
// project runs on is shared: a batch's time moves by 1.5-2x with other tenants' load, so the
// benchmarks report the 10th percentile (the least disturbed batches) and the median beside Google
// Benchmark's mean, and with repetitions each counter's least ("_min" rows).
#pragma once

#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "libbrdf/models.h"

namespace bench {

inline double thread_cpu_ns() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e9 * static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec);
}

// The q-quantile (0 <= q <= 1) of v, nearest rank below.
inline double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

// ns per item of each call of run() that handles `items` items, appended to per_item_ns.
template <class Run>
void time_batch(std::size_t items, std::vector<double>& per_item_ns, const Run& run) {
  const double start = thread_cpu_ns();
  run();
  per_item_ns.push_back((thread_cpu_ns() - start) / static_cast<double>(items));
}

// The issue-9 surfaces (l_c = 2 um; the wavelength and index are each benchmark's).
struct IssueSurface {
  const char* name;
  double sigma_s_um;
};
inline constexpr IssueSurface kIssueSurfaces[] = {{"polished", 0.005}, {"intermediate", 0.1}, {"rough", 0.5}};

// A surface's model parameters at one wavelength and index (the defaults otherwise).
inline libbrdf::ModelParameters issue_parameters(const IssueSurface& surface, double wavelength_um, libbrdf::ComplexIndex index) {
  libbrdf::ModelParameters p;
  p.sigma_s_um = surface.sigma_s_um;
  p.lc_um = 2.0;
  p.wavelength_um = wavelength_um;
  p.index = index;
  return p;
}

// A registered streaming benchmark: a fixed number of batches, microseconds, and "min" statistics.
inline benchmark::internal::Benchmark* streaming(benchmark::internal::Benchmark* b, std::int64_t batches) {
  return b->Iterations(batches)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", [](const std::vector<double>& v) {
    return *std::min_element(v.begin(), v.end());
  });
}

// main() of a benchmark program whose benchmarks register_all() registers.
template <class Register>
int run_main(int argc, char** argv, const Register& register_all) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace bench
