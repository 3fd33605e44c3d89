// Speed of baking and of table lookups (issue #3).
//   bake/merl_cold    the MERL-size bake (90 x 90 x 180 nodes x 3 wavelengths 0.65, 0.55, 0.45 um)
//                     of mbk with K, gold, sigma_s = 0.1 um, l_c = 2 um, including the three K
//                     tables (each bake of the process a surface 1e-12 apart, so K is never cached),
//                     wall seconds on this machine (all cores; oneTBB), and the CPU seconds of
//                     all threads (cpu_s_all_threads; wall ~ that / cores on an idle machine).
//                     per_node:1/asf:1 is the landed path (node by node through Model::evaluate,
//                     the scalar strided series for the rows' ASF); per_node:1/asf:2 the same with
//                     the SIMD series; per_node:0/asf:2 each row of nodes one span
//                     through Model::evaluate_many with the SIMD series (the default before the
//                     kernel table was certified at 1e-6); per_node:0/asf:0 the default (spans, the
//                     ASF from the kernel table where certified). The ASF options: asf:0 auto,
//                     asf:1 strided series, asf:2 SIMD series (1 and 2 without the kernel table).
//                     speedup = landed CPU seconds / this one's. All four share the K tables' quadrature and the error sampling (since made faster
//                     too: SIMD-lane ASF), so against the code before issue 9 the ratio is larger.
//   bake/merl_cached  the same bakes with the K tables already cached (the node evaluations and the
//                     error sampling); max_table_diff = largest difference from the landed table,
//                     diff_vs_per_node = the span paths' from per node with the SIMD series,
//                     each relative to max(|value|, 1e-3 x the table's maximum), every node.
//   bake/kernel_cold  the kernel layout (54^3 angular factor x 3 wavelengths, K tables built).
//   ktable/<lambda>   one RenormalizationTable (91 nodes of eq. 13 by quadrature), per wavelength.
//   lookup/...        single-threaded Lut::lookup of a 90^3 rusinkiewicz table and the MERL table,
//   model/...         Model::evaluate (default settings, and the reference: tolerance 0 and
//                     SeriesMethod::every_term), on the same 4096 random geometries.
// Counters beside the speed: max_rel_err / rms_rel_err against the reference series over values
// >= 1e-3 of its maximum; speedup = reference CPU time per evaluation / this one's, the reference
// (model/reference) timed in the same run (its row reads 1); vs_model_evaluate = the same ratio
// against Model::evaluate at its default settings (model/default, also timed in this run).
// Run: build/bench/bench_bake [--benchmark_filter=lookup]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <memory>
#include <vector>

#include "bake_internal.h"
#include "libbrdf/lut.h"
#include "libbrdf/materials.h"
#include "libbrdf/models.h"
#include "libbrdf/renormalization.h"

namespace {

using namespace libbrdf;

ModelParameters gold(double wavelength_um, double sigma_s_um = 0.1) {
  ModelParameters p;
  p.sigma_s_um = sigma_s_um;
  p.lc_um = 2.0;
  p.wavelength_um = wavelength_um;
  p.index = material_index("Au", wavelength_um);
  return p;
}

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// asf: 0 = the default (auto: kernel table where certified), 1 = the landed strided series,
// 2 = the SIMD series (1 and 2 without the kernel table).
BakeRequest merl_request(double sigma_s_um, int asf = 0) {
  BakeRequest r;
  r.model = ModelKind::mbk;
  r.layout = LutLayout::merl;
  for (double w : {0.65, 0.55, 0.45}) {
    r.channels.push_back(gold(w, sigma_s_um));
    r.channels.back().series.method = asf == 1 ? SeriesMethod::strided : SeriesMethod::simd;
    r.channels.back().series.allow_kernel_table = asf == 0;
  }
  r.error_samples = 20000;
  return r;
}

// CPU seconds per bake of the landed path (node by node, strided series): the reference of the
// speedup counters (measured by the first benchmark, bake/merl_cold/per_node:1/asf:1).
struct BakeReference {
  double cold = 0.0, cached = 0.0;
  std::vector<float> cached_values;         // the landed path's table, for max_table_diff
  std::vector<float> per_node_simd_values;  // per node with the SIMD series, for diff_vs_per_node
};
BakeReference& bake_reference() {
  static BakeReference reference;
  return reference;
}

// Args: path (0 = span, Model::evaluate_many per row; 1 = per node, Model::evaluate), asf for
// the rows' ASF (merl_request; the K tables' integrals are the same in all). speedup = the landed
// path's (1/1) CPU seconds / this one's, same run.
detail::BakeNodePath node_path(const benchmark::State& state) {
  return state.range(0) == 0 ? detail::BakeNodePath::span : detail::BakeNodePath::per_node;
}
int asf_variant(const benchmark::State& state) { return static_cast<int>(state.range(1)); }
bool is_landed(const benchmark::State& state) { return state.range(0) == 1 && state.range(1) == 1; }

// A sigma_s never baked before in this process (1e-12 apart): its K tables are built inside the
// timed bake. One counter for every benchmark (a counter per benchmark gave the later ones the
// tables the first had built).
double fresh_sigma_s() {
  static int bakes = 0;
  return 0.1 * (1.0 + 1e-12 * ++bakes);
}

void BM_BakeMerlCold(benchmark::State& state) {
  double error = 0.0;
  const double cpu_start = cpu_seconds();
  for (auto _ : state) {
    const Lut lut = detail::bake(merl_request(fresh_sigma_s(), asf_variant(state)), node_path(state));
    error = lut.error.max_relative;
    benchmark::DoNotOptimize(lut.values.data());
  }
  const double cpu = (cpu_seconds() - cpu_start) / double(state.iterations());
  if (is_landed(state)) bake_reference().cold = cpu;
  state.counters["nodes"] = 90.0 * 90 * 180 * 3;
  state.counters["lut_max_rel_err"] = error;
  state.counters["cpu_s_all_threads"] = cpu;
  if (bake_reference().cold > 0.0) state.counters["speedup"] = bake_reference().cold / cpu;
}
// The landed path first: the others' speedup counters divide by its time.
BENCHMARK(BM_BakeMerlCold)->Name("bake/merl_cold")->Args({1, 1})->Args({1, 2})->Args({0, 2})->Args({0, 0})->ArgNames({"per_node", "asf"})
    ->Unit(benchmark::kSecond)->UseRealTime()->Iterations(3);

// The same bakes with the K tables already cached: the node evaluations (and the error sampling)
// alone. max_table_diff: the largest |value - landed value| / max(|landed value|, 1e-3 x the
// table's maximum) over the whole table (every node, horizon rows included).
// The largest |value - reference| / max(|reference|, 1e-3 x the reference's maximum) over a table.
double max_table_difference(const std::vector<float>& values, const std::vector<float>& reference) {
  if (values.size() != reference.size() || reference.empty()) return -1.0;
  float peak = 0.0f;
  for (float v : reference) peak = std::max(peak, std::abs(v));
  double worst = 0.0;
  for (std::size_t k = 0; k < values.size(); ++k) {
    const double r = reference[k];
    worst = std::max(worst, std::abs(double(values[k]) - r) / std::max(std::abs(r), 1e-3 * double(peak)));
  }
  return worst;
}

void BM_BakeMerlCached(benchmark::State& state) {
  const BakeRequest request = merl_request(0.1, asf_variant(state));
  (void)bake(request);  // builds and caches the K tables
  const double cpu_start = cpu_seconds();
  std::vector<float> values;
  for (auto _ : state) {
    Lut lut = detail::bake(request, node_path(state));
    benchmark::DoNotOptimize(lut.values.data());
    values = std::move(lut.values);
  }
  const double cpu = (cpu_seconds() - cpu_start) / double(state.iterations());
  BakeReference& reference = bake_reference();
  if (is_landed(state)) {
    reference.cached = cpu;
    reference.cached_values = values;
  }
  const bool per_node_simd = state.range(0) == 1 && state.range(1) == 2;
  if (per_node_simd) reference.per_node_simd_values = values;
  state.counters["cpu_s_all_threads"] = cpu;
  if (reference.cached > 0.0) state.counters["speedup"] = reference.cached / cpu;
  state.counters["max_table_diff"] = max_table_difference(values, reference.cached_values);
  // The span path against the per-node path with the same (SIMD) series: what evaluate_many changes.
  if (state.range(0) == 0) state.counters["diff_vs_per_node"] = max_table_difference(values, reference.per_node_simd_values);
}
BENCHMARK(BM_BakeMerlCached)->Name("bake/merl_cached")->Args({1, 1})->Args({1, 2})->Args({0, 2})->Args({0, 0})->ArgNames({"per_node", "asf"})
    ->Unit(benchmark::kSecond)->UseRealTime()->Iterations(3);

// The kernel layout (54^3 x 3 channels of the angular factor, K tables built inside).
void BM_BakeKernelCold(benchmark::State& state) {
  double error = 0.0;
  for (auto _ : state) {
    BakeRequest r = merl_request(fresh_sigma_s());
    r.layout = LutLayout::kernel;
    const Lut lut = bake(r);
    error = lut.error.max_relative;
    benchmark::DoNotOptimize(lut.values.data());
  }
  state.counters["lut_max_rel_err"] = error;
}
BENCHMARK(BM_BakeKernelCold)->Name("bake/kernel_cold")->Unit(benchmark::kSecond)->UseRealTime()->Iterations(3);


void BM_KTable(benchmark::State& state) {
  const double wavelength = double(state.range(0)) / 1000.0;
  const Surface surface{0.1, 2.0, wavelength};
  const double cpu_start = cpu_seconds();
  for (auto _ : state) {
    const RenormalizationTable table(surface, KMode::plane);
    benchmark::DoNotOptimize(table.node_values().data());
  }
  state.counters["cpu_s_all_threads"] = (cpu_seconds() - cpu_start) / double(state.iterations());
}
BENCHMARK(BM_KTable)->Name("ktable/lambda_nm")->Arg(650)->Arg(550)->Arg(450)->Unit(benchmark::kMillisecond)->UseRealTime();

// Shared fixture for the per-evaluation benchmarks: random geometries, reference values and the
// reference's CPU time per evaluation (measured by the first benchmark of the group).
struct Fixture {
  std::vector<ScatterGeometry> geometries;
  std::vector<double> reference;
  double floor = 0.0;
  double reference_seconds_per_eval = 0.0, default_seconds_per_eval = 0.0;
  std::unique_ptr<Model> reference_model, default_model;
  Lut rusinkiewicz, merl;

  static Fixture& get() {
    static Fixture f;
    return f;
  }

 private:
  Fixture() {
    for (const ScatterAngles& a : random_table_geometries(LutLayout::rusinkiewicz, 4096, kErrorThetaLimitDeg, 7))
      geometries.push_back(make_scatter_geometry(a));
    ModelParameters ref = gold(0.55);
    ref.tolerance = 0.0;
    ref.series.method = SeriesMethod::every_term;
    reference_model = std::make_unique<Model>(ModelKind::mbk, ref);
    default_model = std::make_unique<Model>(ModelKind::mbk, gold(0.55));
    double peak = 0.0;
    for (const ScatterGeometry& g : geometries) {
      reference.push_back(reference_model->evaluate(g));
      peak = std::max(peak, reference.back());
    }
    floor = 1e-3 * peak;
    BakeRequest r;
    r.model = ModelKind::mbk;
    r.channels = {gold(0.55)};
    r.resolution = std::array<int, 3>{90, 90, 90};
    rusinkiewicz = bake(r);
    r.layout = LutLayout::merl;
    r.resolution.reset();
    merl = bake(r);
  }
};

enum class Role { reference, model_default, other };

template <class F>
void per_evaluation(benchmark::State& state, F&& f, Role role) {
  Fixture& fx = Fixture::get();
  const double start = cpu_seconds();
  std::size_t evaluations = 0;
  for (auto _ : state) {
    double sum = 0.0;
    for (const ScatterGeometry& g : fx.geometries) sum += f(g);
    benchmark::DoNotOptimize(sum);
    evaluations += fx.geometries.size();
  }
  const double seconds_per_eval = (cpu_seconds() - start) / double(evaluations);
  if (role == Role::reference) fx.reference_seconds_per_eval = seconds_per_eval;
  if (role == Role::model_default) fx.default_seconds_per_eval = seconds_per_eval;
  double worst = 0.0, sum_squares = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < fx.geometries.size(); ++i) {
    if (fx.reference[i] < fx.floor || fx.reference[i] <= 0.0) continue;
    const double e = std::abs(f(fx.geometries[i]) - fx.reference[i]) / fx.reference[i];
    worst = std::max(worst, e);
    sum_squares += e * e;
    ++count;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(evaluations));
  state.counters["max_rel_err"] = worst;
  state.counters["rms_rel_err"] = count ? std::sqrt(sum_squares / count) : 0.0;
  if (fx.reference_seconds_per_eval > 0.0) state.counters["speedup"] = fx.reference_seconds_per_eval / seconds_per_eval;
  if (fx.default_seconds_per_eval > 0.0)
    state.counters["vs_model_evaluate"] = fx.default_seconds_per_eval / seconds_per_eval;
}

void BM_ModelReference(benchmark::State& state) {
  const Model& m = *Fixture::get().reference_model;
  per_evaluation(state, [&m](const ScatterGeometry& g) { return m.evaluate(g); }, Role::reference);
}
void BM_ModelDefault(benchmark::State& state) {
  const Model& m = *Fixture::get().default_model;
  per_evaluation(state, [&m](const ScatterGeometry& g) { return m.evaluate(g); }, Role::model_default);
}
void BM_LookupRusinkiewicz(benchmark::State& state) {
  const Lut& lut = Fixture::get().rusinkiewicz;
  per_evaluation(state, [&lut](const ScatterGeometry& g) { return lut.lookup(0, g); }, Role::other);
}
void BM_LookupMerl(benchmark::State& state) {
  const Lut& lut = Fixture::get().merl;
  per_evaluation(state, [&lut](const ScatterGeometry& g) { return lut.lookup(0, g); }, Role::other);
}
BENCHMARK(BM_ModelReference)->Name("model/reference");
BENCHMARK(BM_ModelDefault)->Name("model/default");
BENCHMARK(BM_LookupRusinkiewicz)->Name("lookup/rusinkiewicz_90^3");
BENCHMARK(BM_LookupMerl)->Name("lookup/merl");

}  // namespace

BENCHMARK_MAIN();
