// Speed and accuracy of the MBK ASF (eq. 11) and the mbk BRDF at g ~ 0.01, 1, 100, 1e4, for
//   reference  every term of the series, no closed form (SeriesMethod::every_term, tolerance 0)
//   strided    the strided series (SeriesMethod::strided, tolerance 0)
//   auto1e-6   automatic regime: a closed form where its estimated error < 1e-6, else strided
//   auto1e-3   the same with 1e-3
//   polished   eq. 14's closed form (mbk-polished for the BRDF: K = 1, e^-g = 1)
//   rough      eq. 15's closed form (mbk-rough)
// Each benchmark evaluates a fixed set of 64 lobe points (theta_i = 30 deg, theta_s and phi_s
// around specular, out to ~e^-7 of the peak) and reports, beside evaluations per second:
//   max_rel_err  max over the points of |value - reference| / reference, reference summed in the
//                same run (every term, relative tolerance 1e-14)
//   speedup      reference CPU time per evaluation / this benchmark's CPU time per evaluation, the
//                reference being the group's first benchmark in the same run (its row reads 1)
// tolerance/...: every ASF model at --tolerance 1e-4 against 1e-6, per query and over a span
// (register_tolerance below).
// Run: build-core/bench/bench_models [--benchmark_filter=asf/g=100]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <time.h>

#include "libbrdf/geometry.h"
#include "libbrdf/lut.h"
#include "libbrdf/materials.h"
#include "libbrdf/mbk_series.h"
#include "libbrdf/models.h"

namespace {

using namespace libbrdf;

struct Scenario {
  std::string label;  // "g=100"
  double g_target;
  Surface surface;
  std::vector<ScatterGeometry> points;
};

// sigma/lambda with g(30 deg, 30 deg) = g_target; l_c/lambda so that the lobe (the e^-7 contour of
// its widest Gaussian term, exp(-pi^2 L^2 eta^2 / max(1, g)) = e^-7) has a radius of ~0.2 in
// direction cosines, inside the hemisphere. The 64 points fill that half-disk (8 radii x 8 azimuths
// from in-plane forward to in-plane backward of specular).
Scenario make_scenario(const std::string& label, double g_target) {
  const double lambda = 0.5, ti = degrees_to_radians(30.0);
  const double sigma_over_lambda = std::sqrt(g_target) / (2 * kPi * 2 * std::cos(ti));
  const double radius = 0.2;
  const double lc_over_lambda = std::sqrt(7.0 * std::max(1.0, g_target)) / (kPi * radius);
  Scenario s{label, g_target, Surface{sigma_over_lambda * lambda, lc_over_lambda * lambda, lambda}, {}};
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      const double r = radius * i / 7.0, psi = kPi * j / 7.0;
      const double alpha = r * std::sin(psi), beta = std::sin(ti) + r * std::cos(psi);  // scattered direction cosines
      const double ts = std::asin(std::sqrt(alpha * alpha + beta * beta));
      const double phi = kPi - std::atan2(alpha, beta);
      s.points.push_back(make_scatter_geometry({ti, ts, phi}));
    }
  }
  return s;
}

std::vector<Scenario> scenarios() {
  return {make_scenario("g=0.01", 0.01), make_scenario("g=1", 1.0), make_scenario("g=100", 100.0),
          make_scenario("g=1e4", 1e4)};
}

enum class Variant { reference, strided, auto_1e6, auto_1e3, polished, rough };
const std::vector<std::pair<Variant, const char*>> kVariants{
    {Variant::reference, "reference"}, {Variant::strided, "strided"}, {Variant::auto_1e6, "auto1e-6"},
    {Variant::auto_1e3, "auto1e-3"},   {Variant::polished, "polished"}, {Variant::rough, "rough"}};

SeriesOptions series(SeriesMethod method) {
  SeriesOptions o;
  o.relative_tolerance = 1e-14;
  o.method = method;
  return o;
}

// The ASF (K = 1) by one variant.
double asf_by(Variant v, const Surface& surface, const ScatterGeometry& geo) {
  switch (v) {
    case Variant::reference: return asf(surface, geo, series(SeriesMethod::every_term));
    case Variant::strided: return asf(surface, geo, series(SeriesMethod::strided));
    case Variant::auto_1e6: return asf_auto(asf_arguments(surface, geo), 1e-6, nullptr, series(SeriesMethod::strided));
    case Variant::auto_1e3: return asf_auto(asf_arguments(surface, geo), 1e-3, nullptr, series(SeriesMethod::strided));
    case Variant::polished: {
      const AsfArguments a = asf_arguments(surface, geo);
      return a.prefactor * mbk_series_polished(a.g, a.c);
    }
    case Variant::rough: {
      const AsfArguments a = asf_arguments(surface, geo);
      return a.prefactor * mbk_series_rough(a.g, a.c);
    }
  }
  return 0.0;
}

// The mbk BRDF by one variant (Model objects: K table and permittivity built once).
std::shared_ptr<const Model> mbk_model(Variant v, const Surface& surface) {
  ModelParameters p;
  p.sigma_s_um = surface.sigma_s_um;
  p.lc_um = surface.lc_um;
  p.wavelength_um = surface.wavelength_um;
  p.index = ComplexIndex{1.5, 0.0};
  p.tolerance = 0.0;
  p.series = series(SeriesMethod::strided);
  ModelKind kind = ModelKind::mbk;
  switch (v) {
    case Variant::reference: p.series = series(SeriesMethod::every_term); break;
    case Variant::strided: break;
    case Variant::auto_1e6: p.tolerance = 1e-6; break;
    case Variant::auto_1e3: p.tolerance = 1e-3; break;
    case Variant::polished: kind = ModelKind::mbk_polished; break;
    case Variant::rough: kind = ModelKind::mbk_rough; break;
  }
  return std::make_shared<const Model>(kind, p);
}

using Evaluator = std::function<double(const ScatterGeometry&)>;

// This thread's CPU time (Google Benchmark's "CPU" column and its rate counters use the same clock,
// which keeps the ratio meaningful on a loaded machine).
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double max_relative_error(const Evaluator& f, const std::vector<double>& reference, const std::vector<ScatterGeometry>& points) {
  double worst = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!(reference[i] > 0.0)) continue;
    worst = std::max(worst, std::fabs(f(points[i]) - reference[i]) / reference[i]);
  }
  return worst;
}

void register_all() {
  static std::vector<Scenario> all = scenarios();
  for (const Scenario& scenario : all) {
    for (const char* function : {"asf", "mbk"}) {
      const bool is_asf = std::string(function) == "asf";
      std::map<Variant, Evaluator> evaluators;
      for (const auto& [variant, name] : kVariants) {
        if (is_asf) {
          const Surface surface = scenario.surface;
          const Variant v = variant;
          evaluators[variant] = [surface, v](const ScatterGeometry& geo) { return asf_by(v, surface, geo); };
        } else {
          std::shared_ptr<const Model> model = mbk_model(variant, scenario.surface);
          evaluators[variant] = [model](const ScatterGeometry& geo) { return model->evaluate(geo); };
        }
      }
      std::vector<double> reference;
      double g_min = 1e300, g_max = 0.0;
      for (const ScatterGeometry& geo : scenario.points) {
        reference.push_back(evaluators[Variant::reference](geo));
        const double g = asf_arguments(scenario.surface, geo).g;
        g_min = std::min(g_min, g);
        g_max = std::max(g_max, g);
      }
      // CPU seconds per evaluation of this group's reference, written by its own benchmark, which
      // is registered (and so runs) first; the other variants of the group read it.
      auto reference_seconds = std::make_shared<double>(0.0);
      for (const auto& [variant, name] : kVariants) {
        const Evaluator f = evaluators[variant];
        const double error = max_relative_error(f, reference, scenario.points);
        const std::vector<ScatterGeometry>* points = &scenario.points;
        const bool is_reference = variant == Variant::reference;
        const std::string label = std::string(function) + "/" + scenario.label + "/" + name;
        benchmark::RegisterBenchmark(label.c_str(), [f, points, error, reference_seconds, is_reference, g_min, g_max](benchmark::State& state) {
          double sink = 0.0;
          const double start = thread_cpu_seconds();
          for (auto _ : state) {
            for (const ScatterGeometry& geo : *points) sink += f(geo);
            benchmark::DoNotOptimize(sink);
          }
          const double evaluations = static_cast<double>(state.iterations()) * static_cast<double>(points->size());
          const double per_evaluation = (thread_cpu_seconds() - start) / evaluations;
          if (is_reference) *reference_seconds = per_evaluation;
          state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(points->size()));
          state.counters["max_rel_err"] = error;
          state.counters["speedup"] = *reference_seconds / per_evaluation;
          state.counters["g_min"] = g_min;
          state.counters["g_max"] = g_max;
        })->Unit(benchmark::kMicrosecond);
      }
    }
  }
}

// tolerance/<model>/<surface>/<path>/<tol>: --tolerance 1e-4 against 1e-6 (issue 9) for every ASF
// model on the three gold surfaces of `brdf bench` (0.55 um; polished sigma_s = 0.01 um, l_c = 2;
// intermediate 0.1, 2; rough 0.5, 5), on its 1500 random table geometries (theta <= 85 deg), one
// thread, through Model::evaluate query by query (path "evaluate") and through
// Model::evaluate_many on the whole set (path "span", what evaluate_batch runs per chunk).
//   vs_1e-6       CPU time per evaluation at 1e-6 / at 1e-4, same model, surface and path
//   span_speedup  evaluate's CPU time per evaluation / the span's, same tolerance
//   max_rel_err   against the same model at tolerance 0 (the series at 1e-14)
void register_tolerance() {
  struct GoldSurface {
    const char* name;
    double sigma_s_um, lc_um;
  };
  static const GoldSurface surfaces[] = {{"polished", 0.01, 2.0}, {"intermediate", 0.1, 2.0}, {"rough", 0.5, 5.0}};
  static std::vector<ScatterGeometry> points;
  if (points.empty())
    for (const ScatterAngles& a : random_table_geometries(LutLayout::rusinkiewicz, 1500, kErrorThetaLimitDeg, 1))
      points.push_back(make_scatter_geometry(a));
  for (ModelKind kind : {ModelKind::asf, ModelKind::mbk, ModelKind::mbk_fg, ModelKind::bk, ModelKind::bk_modified}) {
    for (const GoldSurface& surface : surfaces) {
      ModelParameters p;
      p.sigma_s_um = surface.sigma_s_um;
      p.lc_um = surface.lc_um;
      p.wavelength_um = 0.55;
      p.index = material_index("Au", 0.55);
      ModelParameters exact = p;
      exact.tolerance = 0.0;
      const Model reference_model(kind, exact);
      auto reference = std::make_shared<std::vector<double>>();
      for (const ScatterGeometry& g : points) reference->push_back(reference_model.evaluate(g));
      // Seconds per evaluation: [path][tolerance index], written by the benchmarks in their order.
      auto seconds = std::make_shared<std::array<std::array<double, 2>, 2>>();
      for (int path = 0; path < 2; ++path) {
        for (int t = 0; t < 2; ++t) {
          ModelParameters q = p;
          q.tolerance = t == 0 ? 1e-6 : 1e-4;
          auto model = std::make_shared<const Model>(kind, q);
          const std::string label = "tolerance/" + std::string(model_name(kind)) + "/" + surface.name + "/" +
                                    (path == 0 ? "evaluate" : "span") + (t == 0 ? "/1e-6" : "/1e-4");
          benchmark::RegisterBenchmark(label.c_str(), [model, reference, seconds, path, t](benchmark::State& state) {
            std::vector<double> out(points.size());
            auto run = [&] {
              if (path == 1) {
                model->evaluate_many(points.data(), points.size(), out.data());
              } else {
                for (std::size_t k = 0; k < points.size(); ++k) out[k] = model->evaluate(points[k]);
              }
            };
            const double start = thread_cpu_seconds();
            for (auto _ : state) {
              run();
              benchmark::DoNotOptimize(out.data());
            }
            const double per_evaluation = (thread_cpu_seconds() - start) / (double(state.iterations()) * double(points.size()));
            (*seconds)[path][t] = per_evaluation;
            double worst = 0.0;
            for (std::size_t k = 0; k < points.size(); ++k)
              if ((*reference)[k] > 0.0) worst = std::max(worst, std::fabs(out[k] - (*reference)[k]) / (*reference)[k]);
            state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(points.size()));
            state.counters["max_rel_err"] = worst;
            if (t == 1 && (*seconds)[path][0] > 0.0) state.counters["vs_1e-6"] = (*seconds)[path][0] / per_evaluation;
            if (path == 1 && (*seconds)[0][t] > 0.0) state.counters["span_speedup"] = (*seconds)[0][t] / per_evaluation;
          })->Unit(benchmark::kMicrosecond);
        }
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  register_all();
  register_tolerance();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
