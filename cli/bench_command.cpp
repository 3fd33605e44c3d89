// `brdf bench [--out DIR] [--quick]`: speed against error of every BRDF model, every fast path of
// the core and baked tables of several layouts and sizes, all measured in one run.
//
// For three gold surfaces at 0.55 um (polished sigma_s = 0.01 um, l_c = 2 um; intermediate 0.1, 2;
// rough 0.5, 5) and one set of random geometries (uniform in (sqrt theta_h, theta_d, phi_d), both
// polar angles <= 85 deg; libbrdf::random_table_geometries), each row gives:
//   evals_per_s    single-threaded evaluations (or table lookups) per second over the set;
//   speed_ratio    evals_per_s / that of the row's reference, timed in the same run;
//   max/rms_rel_error  against the reference: the same model with tolerance 0 and
//                  SeriesMethod::every_term (mbk for the mbk fast paths and mbk-polished/-rough),
//                  over values >= floor = 1e-3 x the reference's largest value on the set.
// Rows of kind fast_path include the ASF alone (series SIMD, kernel table, the landed scalar
// strided series) and the ASF through the batch API (asf_auto_batch, one query per SIMD lane, with
// speed_vs_landed: its rate over the per-query row above it, same run); kind lut3 times 3-channel
// lookups; kind bake the MERL-size bake (all threads).
// Slice tables are checked on their own set (geometries of a sun + orthographic camera scene).
// Writes DIR/bench.csv and DIR/bench.png (tools/plot_bench.py, run with /usr/bin/python3).
#include <spawn.h>
#include <sys/wait.h>
#include <tbb/parallel_for.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "libbrdf/batch.h"
#include "libbrdf/error.h"
#include "libbrdf/kernel_table.h"
#include "libbrdf/lut.h"
#include "libbrdf/materials.h"
#include "libbrdf/mbk_series.h"
#include "libbrdf/models.h"

extern char** environ;

namespace brdf_cli {

namespace {

using libbrdf::KernelAngular;
using libbrdf::LutLayout;
using libbrdf::Model;
using libbrdf::ModelKind;
using libbrdf::ModelParameters;
using libbrdf::ScatterGeometry;

struct BenchOptions {
  std::string out = "out/bench";
  bool quick = false;
};

struct BenchSurface {
  const char* name;
  double sigma_s_um, lc_um;
};
constexpr BenchSurface kSurfaces[] = {{"polished", 0.01, 2.0}, {"intermediate", 0.1, 2.0}, {"rough", 0.5, 5.0}};
// A polished surface with a long correlation length (l_c / lambda = 36): most of its queries have
// z = sqrt(c/(g+1)) > 30, the kernel table's far section (kernel_table.h). The ASF's paths only.
constexpr BenchSurface kLongCorrelationSurface{"polished-lc20", 0.01, 20.0};
constexpr double kWavelengthUm = 0.55;
constexpr double kFloorFraction = 1e-3;
const libbrdf::Direction kSunDirection{0.3, 0.0, 1.0}, kCameraDirection{-0.5, 0.2, 1.0};

struct Row {
  std::string kind, model, surface, variant, layout, shape;
  double nodes = 0, evals_per_s = 0, speed_ratio = 0, max_rel_error = 0, rms_rel_error = 0, floor = 0;
  // tables: bytes of the per-material data (float32 nodes + side tables); kernel-table rows: the
  // universal table's tier (kernel_table.h), which every material shares
  double bytes = 0;
  double speed_vs_landed = 0;  // batch rows: evals_per_s / that of the per-query path it replaces (same run)
  int samples = 0;
};

// A set of geometries with the reference values of each model family on it.
struct QuerySet {
  std::vector<ScatterGeometry> geometries;
};

QuerySet make_queries(LutLayout layout, int count, std::uint64_t seed) {
  QuerySet q;
  for (const libbrdf::ScatterAngles& a :
       libbrdf::random_table_geometries(layout, count, libbrdf::kErrorThetaLimitDeg, seed, kSunDirection, kCameraDirection))
    q.geometries.push_back(libbrdf::make_scatter_geometry(a));
  return q;
}

using Evaluator = std::function<double(const ScatterGeometry&)>;

// Values of f on the set, multi-threaded (not timed).
std::vector<double> values_on(const QuerySet& q, const Evaluator& f) {
  std::vector<double> out(q.geometries.size());
  tbb::parallel_for(std::size_t{0}, out.size(), [&](std::size_t i) { out[i] = f(q.geometries[i]); });
  return out;
}

// A single-thread rate: whole passes (each returns how many evaluations it made) until
// min_seconds of wall time elapsed.
double rate_per_second(const std::function<std::size_t()>& pass, double min_seconds) {
  using clock = std::chrono::steady_clock;
  std::size_t count = 0;
  const auto start = clock::now();
  double elapsed = 0.0;
  do {
    count += pass();
    elapsed = std::chrono::duration<double>(clock::now() - start).count();
  } while (elapsed < min_seconds);
  return double(count) / elapsed;
}

// Single-threaded evaluations per second: whole passes over the set.
double evals_per_second(const QuerySet& q, const Evaluator& f, double min_seconds) {
  volatile double sink = 0.0;
  return rate_per_second(
      [&] {
        double sum = 0.0;
        for (const ScatterGeometry& g : q.geometries) sum += f(g);
        sink = sink + sum;
        return q.geometries.size();
      },
      min_seconds);
}

void fill_errors(Row& row, const std::vector<double>& values, const std::vector<double>& reference) {
  double peak = 0.0;
  for (double r : reference) peak = std::max(peak, r);
  row.floor = kFloorFraction * peak;
  double sum_squares = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!(reference[i] >= row.floor) || reference[i] <= 0.0) continue;
    const double e = std::abs(values[i] - reference[i]) / reference[i];
    row.max_rel_error = std::max(row.max_rel_error, e);
    sum_squares += e * e;
    ++row.samples;
  }
  row.rms_rel_error = row.samples ? std::sqrt(sum_squares / row.samples) : 0.0;
}

ModelParameters gold(const BenchSurface& s) {
  ModelParameters p;
  p.sigma_s_um = s.sigma_s_um;
  p.lc_um = s.lc_um;
  p.wavelength_um = kWavelengthUm;
  p.index = libbrdf::material_index("Au", kWavelengthUm);
  return p;
}

// A bake of mbk gold at the three default wavelengths (0.65, 0.55, 0.45 um).
libbrdf::BakeRequest rgb_gold_request(const BenchSurface& s) {
  libbrdf::BakeRequest request;
  request.model = ModelKind::mbk;
  for (double w : {0.65, 0.55, 0.45}) {
    ModelParameters p = gold(s);
    p.wavelength_um = w;
    p.index = libbrdf::material_index("Au", w);
    request.channels.push_back(p);
  }
  return request;
}

ModelParameters reference_parameters(const BenchSurface& s) {
  ModelParameters p = gold(s);
  p.tolerance = 0.0;
  p.series.method = libbrdf::SeriesMethod::every_term;
  return p;
}

// The reference of a model: itself at tolerance 0 / every_term, mbk for its closed forms.
ModelKind reference_kind(ModelKind kind) {
  return kind == ModelKind::mbk_polished || kind == ModelKind::mbk_rough ? ModelKind::mbk : kind;
}

struct Reference {
  std::unique_ptr<Model> model;
  std::vector<double> values;
  double evals_per_s = 0.0;
};

// What every row is measured against, per surface: the query sets (all geometries; the slice
// scene's) and each model's reference values on them, made once and listed as a reference row.
class References {
 public:
  References(bool quick, std::vector<Row>& rows) : min_seconds_(quick ? 0.04 : 0.25), rows_(rows) {
    const int count = quick ? 1500 : 8000;
    full_ = make_queries(LutLayout::rusinkiewicz, count, 1);
    slice_ = make_queries(LutLayout::slice, count, 2);
  }

  void clear() {
    references_.clear();
    slice_references_.clear();
  }

  Reference& of(ModelKind kind, const BenchSurface& s, bool slice) {
    auto& table = slice ? slice_references_ : references_;
    const ModelKind ref_kind = reference_kind(kind);
    auto it = table.find(ref_kind);
    if (it != table.end()) return it->second;
    Reference& ref = table[ref_kind];
    ref.model = std::make_unique<Model>(ref_kind, reference_parameters(s));
    const QuerySet& q = queries(slice);
    const Model& m = *ref.model;
    ref.values = values_on(q, [&m](const ScatterGeometry& g) { return m.evaluate(g); });
    ref.evals_per_s = evals_per_second(q, [&m](const ScatterGeometry& g) { return m.evaluate(g); }, min_seconds_);
    if (!slice) {
      Row row{"model", std::string(libbrdf::model_name(ref_kind)), s.name, "reference", "", ""};
      row.evals_per_s = ref.evals_per_s;
      row.speed_ratio = 1.0;
      fill_errors(row, ref.values, ref.values);
      rows_.push_back(row);
    }
    return ref;
  }

  const QuerySet& queries(bool slice) const { return slice ? slice_ : full_; }
  double min_seconds() const { return min_seconds_; }

 private:
  double min_seconds_;
  std::vector<Row>& rows_;
  QuerySet full_, slice_;
  std::map<ModelKind, Reference> references_, slice_references_;
};

// Rows of models evaluated query by query (Model::evaluate), and of the ASF's paths.
class ModelRows {
 public:
  ModelRows(References& references, std::vector<Row>& rows) : references_(references), rows_(rows) {}

  void add(const char* kind_text, ModelKind kind, const BenchSurface& s, const ModelParameters& p, const std::string& variant) {
    Reference& ref = references_.of(kind, s, false);
    const Model model(kind, p);
    Row row{kind_text, std::string(libbrdf::model_name(kind)), s.name, variant, "", ""};
    const Evaluator f = [&model](const ScatterGeometry& g) { return model.evaluate(g); };
    const QuerySet& q = references_.queries(false);
    fill_errors(row, values_on(q, f), ref.values);
    row.evals_per_s = evals_per_second(q, f, references_.min_seconds());
    row.speed_ratio = row.evals_per_s / ref.evals_per_s;
    rows_.push_back(row);
  }

  // The ASF alone (eq. 11, K = 1): the series, the kernel table, and the landed method.
  void add_asf_rows(const BenchSurface& s) {
    ModelParameters series_only = gold(s);
    series_only.series.allow_kernel_table = false;
    add("fast_path", ModelKind::asf, s, series_only, "series SIMD tol 1e-6 (--asf-method series)");
    add_asf_batch_row(s, series_only, "batch: series in lanes tol 1e-6");
    ModelParameters coarse = gold(s);  // KernelTable::for_tolerance: the coarse tier (kernel_table.h)
    coarse.tolerance = libbrdf::kKernelTableCoarse.certified_error;
    struct Tier {
      ModelParameters parameters;
      const char *name, *batch_name;
    };
    for (const Tier& tier : {Tier{gold(s), "kernel table tol 1e-6 (default)", "batch: kernel table in lanes tol 1e-6 (default)"},
                             Tier{coarse, "kernel table tol 1e-4 (coarse tier)", "batch: kernel table in lanes tol 1e-4 (coarse tier)"}}) {
      add("fast_path", ModelKind::asf, s, tier.parameters, tier.name);
      add_asf_batch_row(s, tier.parameters, tier.batch_name);
      rows_[rows_.size() - 2].bytes = rows_.back().bytes =
          static_cast<double>(libbrdf::KernelTable::for_tolerance(tier.parameters.tolerance)->bytes());
    }
    ModelParameters asf_landed = reference_parameters(s);
    asf_landed.series.method = libbrdf::SeriesMethod::strided;
    add("fast_path", ModelKind::asf, s, asf_landed, "series strided scalar (landed method; tol 0)");
    ModelParameters asf_simd_exact = reference_parameters(s);
    asf_simd_exact.series.method = libbrdf::SeriesMethod::simd;
    add("fast_path", ModelKind::asf, s, asf_simd_exact, "series SIMD tol 0 (1e-14 truncation)");
  }

 private:
  // The ASF through the batch API (asf_auto_batch: queries in SIMD lanes) over the whole set on
  // one thread, g and c derived from the geometries inside the timing; speed_vs_landed against the
  // row just before it (the same tolerance query by query through Model::evaluate).
  void add_asf_batch_row(const BenchSurface& s, const ModelParameters& parameters, const std::string& variant) {
    Reference& ref = references_.of(ModelKind::asf, s, false);
    const double landed = rows_.back().evals_per_s;
    const libbrdf::Surface surface{s.sigma_s_um, s.lc_um, kWavelengthUm};
    const std::vector<ScatterGeometry>& geometries = references_.queries(false).geometries;
    const std::size_t n = geometries.size();
    std::vector<double> g(n), c(n), values(n);
    const libbrdf::AsfScales scales = libbrdf::asf_scales(surface);  // as asf_auto_geometries: once per surface
    auto run = [&] {
      for (std::size_t k = 0; k < n; ++k) {
        const libbrdf::AsfArguments a = libbrdf::asf_arguments(scales, geometries[k]);
        g[k] = a.g, c[k] = a.c;
      }
      libbrdf::asf_auto_batch(g.data(), c.data(), n, scales.prefactor, parameters.tolerance, parameters.series, values.data());
    };
    run();
    Row row{"fast_path", "asf", s.name, variant, "", ""};
    fill_errors(row, values, ref.values);
    row.evals_per_s = rate_per_second(
        [&] {
          run();
          return n;
        },
        references_.min_seconds());
    row.speed_ratio = row.evals_per_s / ref.evals_per_s;
    row.speed_vs_landed = row.evals_per_s / landed;
    rows_.push_back(row);
  }

  References& references_;
  std::vector<Row>& rows_;
};

double table_bytes(const libbrdf::Lut& lut) {
  double bytes = double(lut.values.size()) * sizeof(float);
  for (const auto& t : lut.specular_reflectance) bytes += double(t.size()) * sizeof(float);
  for (const auto& t : lut.renormalization) bytes += double(t.size()) * sizeof(float);
  return bytes;
}

std::string kernel_variant(LutLayout layout, KernelAngular angular) {
  if (layout != LutLayout::kernel) return "";
  return angular == KernelAngular::table ? " (P~ table)" : " (closed-form P)";
}

// Rows of baked tables: one-channel lookups, three-channel lookups (LutSampler), the MERL-size bake.
class TableRows {
 public:
  TableRows(References& references, std::vector<Row>& rows) : references_(references), rows_(rows) {}

  void add_lookup_row(ModelKind kind, const BenchSurface& s, LutLayout layout, const std::array<int, 3>& shape,
                      KernelAngular angular = KernelAngular::table) {
    const bool slice = layout == LutLayout::slice;
    Reference& ref = references_.of(kind, s, slice);
    libbrdf::BakeRequest request;
    request.model = kind;
    request.channels = {gold(s)};
    request.layout = layout;
    request.resolution = shape;
    request.light = kSunDirection;
    request.view = kCameraDirection;
    request.error_samples = 2000;  // the bench measures against the reference itself
    request.kernel_angular = angular;
    const libbrdf::Lut lut = libbrdf::bake(request);
    const QuerySet& q = references_.queries(slice);
    Row row{"lut", std::string(libbrdf::model_name(kind)), s.name, "table of the default model" + kernel_variant(layout, angular),
            std::string(libbrdf::layout_name(layout)), libbrdf::shape_text(lut.shape, lut.layout)};
    row.nodes = double(lut.nodes_per_channel());
    row.bytes = table_bytes(lut);
    const Evaluator f = [&lut](const ScatterGeometry& g) { return lut.lookup(0, g); };
    fill_errors(row, values_on(q, f), ref.values);
    row.evals_per_s = evals_per_second(q, f, references_.min_seconds());
    row.speed_ratio = row.evals_per_s / ref.evals_per_s;
    rows_.push_back(row);
  }

  // Lookups of all three channels of a 3-wavelength table (0.65, 0.55, 0.45 um) per second; the
  // error columns are channel 1 (0.55 um) against the reference.
  void add_rgb_lookup_row(const BenchSurface& s, LutLayout layout, const std::array<int, 3>& shape,
                          KernelAngular angular = KernelAngular::table) {
    Reference& ref = references_.of(ModelKind::mbk, s, false);
    libbrdf::BakeRequest request = rgb_gold_request(s);
    request.layout = layout;
    request.resolution = shape;
    request.error_samples = 2000;
    request.kernel_angular = angular;
    const libbrdf::LutSampler sampler(libbrdf::bake(request));
    const libbrdf::Lut& lut = sampler.lut();
    Row row{"lut3", "mbk", s.name, "3-channel lookups (LutSampler)" + kernel_variant(layout, angular), std::string(libbrdf::layout_name(layout)),
            libbrdf::shape_text(lut.shape, lut.layout)};
    row.nodes = double(lut.nodes_per_channel());
    row.bytes = table_bytes(lut);
    const Evaluator green = [&sampler](const ScatterGeometry& g) {
      double v[3];
      sampler.lookup_all(&g, 1, v);
      return v[1];
    };
    const std::vector<ScatterGeometry>& geometries = references_.queries(false).geometries;
    fill_errors(row, values_on(references_.queries(false), green), ref.values);
    // Timed through LutSampler (lut.h: channel-interleaved nodes for the trilinear layouts and the P~ table, the
    // values of lookup_all_batch) on one thread, as a renderer would call it for RGB.
    std::vector<double> out(geometries.size() * 3);
    row.evals_per_s = rate_per_second(
        [&] {
          sampler.lookup_all(geometries.data(), geometries.size(), out.data());
          return geometries.size();
        },
        references_.min_seconds());
    row.speed_ratio = row.evals_per_s / ref.evals_per_s;
    rows_.push_back(row);
  }

  // The MERL-size bake (90 x 90 x 180 x 3 wavelengths, mbk with K): nodes x channels per second.
  void add_bake_row(const BenchSurface& s) {
    libbrdf::BakeRequest request = rgb_gold_request(s);
    request.layout = LutLayout::merl;
    request.resolution = libbrdf::kMerlShape;
    request.error_samples = 2000;
    const auto start = std::chrono::steady_clock::now();
    const libbrdf::Lut lut = libbrdf::bake(request);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char text[96];
    std::snprintf(text, sizeof text, "MERL-size bake on all threads: %.2f s", seconds);
    Row row{"bake", "mbk", s.name, text, "merl", libbrdf::shape_text(lut.shape, lut.layout)};
    row.nodes = double(lut.nodes_per_channel());
    row.evals_per_s = row.nodes * lut.channels() / seconds;
    row.max_rel_error = lut.error.max_relative;
    row.rms_rel_error = lut.error.rms_relative;
    row.samples = lut.error.samples;
    rows_.push_back(row);
  }

 private:
  References& references_;
  std::vector<Row>& rows_;
};

// Every BRDF of the registry that is its own reference (not mbk's closed forms), mbk apart: it is
// listed with its fast paths.
std::vector<ModelKind> models_at_defaults() {
  std::vector<ModelKind> kinds;
  for (const libbrdf::ModelTraits& row : libbrdf::kModelRegistry)
    if (row.is_brdf() && row.kind != ModelKind::mbk && reference_kind(row.kind) == row.kind) kinds.push_back(row.kind);
  return kinds;
}

class Bench {
 public:
  explicit Bench(bool quick) : quick_(quick), references_(quick, rows_) {}
  Bench(const Bench&) = delete;
  Bench& operator=(const Bench&) = delete;

  void run_surface(const BenchSurface& s) {
    references_.clear();
    add_model_rows(s);
    add_table_rows(s);
  }

  // A surface for the ASF's paths alone (kLongCorrelationSurface).
  void run_asf_surface(const BenchSurface& s) {
    references_.clear();
    models_.add_asf_rows(s);
  }

  void add_bake_row(const BenchSurface& s) { tables_.add_bake_row(s); }

  const std::vector<Row>& rows() const { return rows_; }

 private:
  // Models: every BRDF at its default settings; mbk's default (auto regime, tolerance 1e-6) with
  // its fast paths, and the ASF's.
  void add_model_rows(const BenchSurface& s) {
    for (ModelKind kind : models_at_defaults()) models_.add("model", kind, s, gold(s), "default");
    models_.add("fast_path", ModelKind::mbk, s, gold(s), "auto regime tol 1e-6 (default: kernel table)");
    ModelParameters series_only = gold(s);
    series_only.series.allow_kernel_table = false;
    models_.add("fast_path", ModelKind::mbk, s, series_only, "series tol 1e-6 (--asf-method series)");
    ModelParameters loose = gold(s);
    loose.tolerance = 1e-4;
    models_.add("fast_path", ModelKind::mbk, s, loose, "auto regime tol 1e-4");
    loose.tolerance = 1e-3;
    models_.add("fast_path", ModelKind::mbk, s, loose, "auto regime tol 1e-3");
    ModelParameters strided = reference_parameters(s);
    strided.series.method = libbrdf::SeriesMethod::strided;
    models_.add("fast_path", ModelKind::mbk, s, strided, "series strided (tol 0)");
    models_.add("fast_path", ModelKind::mbk_polished, s, gold(s), "closed form eq. 14");
    models_.add("fast_path", ModelKind::mbk_rough, s, gold(s), "closed form eq. 15");
    models_.add_asf_rows(s);
    ModelParameters tis = gold(s);
    tis.k_mode = libbrdf::KMode::tis;
    models_.add("fast_path", ModelKind::mbk, s, tis, "k-mode tis (vs plane)");
  }

  // Tables of every BRDF, and several layouts and sizes for mbk.
  void add_table_rows(const BenchSurface& s) {
    const int n = quick_ ? 48 : 90;
    for (const libbrdf::ModelTraits& row : libbrdf::kModelRegistry)
      if (row.is_brdf()) tables_.add_lookup_row(row.kind, s, LutLayout::rusinkiewicz, std::array<int, 3>{n, n, n});
    tables_.add_lookup_row(ModelKind::mbk, s, LutLayout::rusinkiewicz, {24, 24, 24});
    if (!quick_) tables_.add_lookup_row(ModelKind::mbk, s, LutLayout::rusinkiewicz, {160, 160, 160});
    tables_.add_lookup_row(ModelKind::mbk, s, LutLayout::merl, libbrdf::kMerlShape);
    tables_.add_lookup_row(ModelKind::mbk, s, LutLayout::slice, {64, 32, 1});
    tables_.add_lookup_row(ModelKind::mbk, s, LutLayout::slice, {256, 128, 1});
    if (!quick_) tables_.add_lookup_row(ModelKind::mbk, s, LutLayout::slice, {1024, 512, 1});
    // Kernel layout: P~ tabulated (what the Blender atlas holds) and all of P in closed form (2^3).
    tables_.add_lookup_row(ModelKind::mbk, s, LutLayout::kernel, {32, 32, 32}, KernelAngular::table);
    tables_.add_lookup_row(ModelKind::mbk, s, LutLayout::kernel, libbrdf::default_resolution(LutLayout::kernel), KernelAngular::table);
    tables_.add_lookup_row(ModelKind::mbk, s, LutLayout::kernel, {2, 2, 2}, KernelAngular::closed_form);
    tables_.add_lookup_row(ModelKind::bk_modified, s, LutLayout::kernel, {2, 2, 2}, KernelAngular::closed_form);
    tables_.add_lookup_row(ModelKind::mbk_fg, s, LutLayout::kernel, {2, 2, 2}, KernelAngular::closed_form);  // G/S at lookup
    // Three-channel lookups (LutSampler: coordinates once, no acos/atan2 calls), every layout.
    tables_.add_rgb_lookup_row(s, LutLayout::rusinkiewicz, std::array<int, 3>{n, n, n});
    tables_.add_rgb_lookup_row(s, LutLayout::merl, libbrdf::kMerlShape);
    tables_.add_rgb_lookup_row(s, LutLayout::kernel, libbrdf::default_resolution(LutLayout::kernel), KernelAngular::table);
    tables_.add_rgb_lookup_row(s, LutLayout::kernel, {2, 2, 2}, KernelAngular::closed_form);
  }

  bool quick_;
  std::vector<Row> rows_;
  References references_;
  ModelRows models_{references_, rows_};
  TableRows tables_{references_, rows_};
};

void write_csv(const std::vector<Row>& rows, const std::string& path) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << "kind,model,surface,variant,layout,shape,nodes,evals_per_s,speed_ratio,max_rel_error,rms_rel_error,floor,samples,bytes,speed_vs_landed\n";
    char buffer[512];
    for (const Row& r : rows) {
      std::snprintf(buffer, sizeof buffer, "%s,%s,%s,%s,%s,%s,%.0f,%.4g,%.4g,%.3g,%.3g,%.3g,%d,%.0f,%.4g\n", r.kind.c_str(),
                    r.model.c_str(), r.surface.c_str(), r.variant.c_str(), r.layout.c_str(), r.shape.c_str(), r.nodes,
                    r.evals_per_s, r.speed_ratio, r.max_rel_error, r.rms_rel_error, r.floor, r.samples, r.bytes, r.speed_vs_landed);
      out << buffer;
    }
    out.close();
    if (!out) {
      std::filesystem::remove(temporary);
      throw std::runtime_error(path + ": write failed");
    }
  }
  std::filesystem::rename(temporary, path);
}

// LIBBRDF_ROOT's, else the source tree's, else the one `cmake --install` put beside this program
// (PREFIX/bin/brdf -> PREFIX/share/libbrdf/tools/), so that an installed brdf outlives its clone.
std::string plot_script() {
  if (const char* root = std::getenv("LIBBRDF_ROOT")) return std::string(root) + "/tools/plot_bench.py";
#ifdef LIBBRDF_SOURCE_DIR
  const std::string in_source = std::string(LIBBRDF_SOURCE_DIR) + "/tools/plot_bench.py";
  if (std::filesystem::exists(in_source)) return in_source;
#endif
  std::error_code ignored;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", ignored);
  if (!program.empty()) {
    const auto installed = program.parent_path().parent_path() / "share/libbrdf/tools/plot_bench.py";
    if (std::filesystem::exists(installed)) return installed.string();
  }
  return "tools/plot_bench.py";
}

// Runs /usr/bin/python3 SCRIPT CSV PNG (no shell); returns its exit status.
int run_plot(const std::string& csv, const std::string& png) {
  const std::string python = "/usr/bin/python3", script = plot_script();
  if (!std::filesystem::exists(script)) throw std::runtime_error("bench: plot script not found: " + script + " (set LIBBRDF_ROOT)");
  std::vector<std::string> args{python, script, csv, png};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ) != 0)
    throw std::runtime_error("bench: cannot run " + python);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

int run_bench(const BenchOptions& o) {
  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (!std::filesystem::is_directory(o.out)) throw libbrdf::InvalidArgument("out", "cannot create directory '" + o.out + "'");
  const auto start = std::chrono::steady_clock::now();
  Bench bench(o.quick);
  for (const BenchSurface& s : kSurfaces) {
    std::cerr << "bench: " << s.name << " surface\n";
    bench.run_surface(s);
  }
  std::cerr << "bench: " << kLongCorrelationSurface.name << " surface (ASF paths)\n";
  bench.run_asf_surface(kLongCorrelationSurface);
  bench.add_bake_row(kSurfaces[1]);
  const std::string csv = o.out + "/bench.csv", png = o.out + "/bench.png";
  write_csv(bench.rows(), csv);
  std::printf("%-9s %-13s %-12s %-38s %-13s %12s %9s %10s %10s\n", "kind", "model", "surface", "variant", "table",
              "evals/s", "vs ref", "max err", "vs landed");
  for (const Row& r : bench.rows())
    std::printf("%-9s %-13s %-12s %-38s %-13s %12.4g %9.3g %10.3g %10.3g\n", r.kind.c_str(), r.model.c_str(), r.surface.c_str(),
                r.variant.c_str(), (r.layout.empty() ? std::string("-") : r.layout + " " + r.shape).c_str(), r.evals_per_s,
                r.speed_ratio, r.max_rel_error, r.speed_vs_landed);
  if (run_plot(csv, png) != 0) throw std::runtime_error("bench: tools/plot_bench.py failed (bench.csv is written)");
  std::printf("wrote %s and %s in %.1f s\n", csv.c_str(), png.c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}

}  // namespace

void register_bench(CLI::App& app, ActionTable& actions) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* command = app.add_subcommand("bench", "Speed against error of every model, fast path and table (CSV + plot)");
  command->add_option("--out", options->out, "Output directory for bench.csv and bench.png (default out/bench)");
  command->add_flag("--quick", options->quick, "Fewer queries, smaller tables, shorter timings (well under a minute)");
  actions.emplace_back(command, [options]() { return run_bench(*options); });
}

}  // namespace brdf_cli
