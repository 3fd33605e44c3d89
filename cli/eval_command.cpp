// `brdf eval`: a model at query angles, CSV out. The interface is a contract other tools call:
//   brdf eval --model NAME [surface params] (--at TI,TS,PHIS ... | --queries FILE|-)
//   brdf eval --lut FILE [--channel I] (--at ... | --queries ...)   a baked table, same CSV contract
#include <cmath>
#include <ctime>
#include <iostream>
#include <memory>

#include <tbb/parallel_for.h>

#include "commands.h"
#include "libbrdf/batch.h"
#include "libbrdf/error.h"
#include "libbrdf/lut.h"
#include "libbrdf/models.h"
#include "model_options.h"
#include "query_input.h"

namespace brdf_cli {

namespace {
struct EvalOptions {
  ModelOptions model;
  std::vector<std::string> at;
  std::string queries;
  std::string lut;
  int channel = 0;
  bool timing = false;
};

// CPU seconds of this process (all threads): what --timing reports, without the CSV reading and
// writing around it.
double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// --timing's line on stderr.
void report_timing(double setup_seconds, double evaluation_seconds, std::size_t count) {
  std::cerr << "brdf eval: set-up " << setup_seconds << " s CPU; " << count << " evaluations " << evaluation_seconds << " s CPU ("
            << 1e9 * evaluation_seconds / static_cast<double>(count) << " ns each)\n";
}

// A baked table (OpenEXR or MERL binary) at the queries: channel `channel`, interpolated, through
// the batch API (libbrdf/batch.h: lookup_batch, as the Python module's Lut; in parallel). Set-up is
// reading the file. A query lookup_batch rejects (a slice table's off-slice geometry, eq. 5) is
// reported at its CSV line.
int evaluate_table(const EvalOptions& o, const std::vector<Query>& queries) {
  if (!o.model.model.empty()) throw libbrdf::InvalidArgument("lut", "give either --model or --lut, not both");
  const double setup_start = process_cpu_seconds();
  libbrdf::Lut lut;
  try {
    lut = libbrdf::read_lut_file(o.lut);
  } catch (const libbrdf::LutFileError& e) {
    throw libbrdf::InvalidArgument("lut", e.what());
  }
  const double setup_seconds = process_cpu_seconds() - setup_start;
  if (o.channel < 0 || o.channel >= lut.channels())
    throw libbrdf::InvalidArgument("channel", "must be in [0, " + std::to_string(lut.channels() - 1) + "] (got " +
                                                  std::to_string(o.channel) + ")");
  std::vector<libbrdf::ScatterAngles> angles(queries.size());
  for (std::size_t k = 0; k < queries.size(); ++k)
    angles[k] = libbrdf::scatter_angles_from_degrees(queries[k].theta_i_deg, queries[k].theta_s_deg, queries[k].phi_s_deg);
  std::vector<double> values(queries.size());
  const double evaluation_start = process_cpu_seconds();
  try {
    libbrdf::lookup_batch(lut, o.channel, angles.data(), angles.size(), values.data());
  } catch (const libbrdf::InvalidQuery& e) {
    throw libbrdf::InvalidArgument(e.parameter(), queries[e.index()].origin() + ": " + e.reason());
  }
  if (o.timing) report_timing(setup_seconds, process_cpu_seconds() - evaluation_start, values.size());
  write_evaluations(std::cout, queries, values);
  return 0;
}
}  // namespace

void register_eval(CLI::App& app, ActionTable& actions) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* command = app.add_subcommand("eval", "Evaluate a model at query angles (degrees); CSV on stdout");
  add_model_options(*command, options->model, /*require_model=*/false);
  command->add_option("--lut", options->lut, "Evaluate a baked table (.exr or MERL .binary) instead of a model");
  command->add_option("--channel", options->channel, "With --lut: channel (wavelength index) to evaluate, default 0");
  command->add_option("--at", options->at, "One query TI,TS,PHIS in degrees (repeatable)")->allow_extra_args(false);
  command->add_option("--queries", options->queries, "CSV file of theta_i,theta_s,phi_s lines, or - for stdin");
  command->add_flag("--timing", options->timing,
                    "Print to stderr the CPU seconds of the model's set-up (K tables, and the thread pool's start "
                    "for a parallel batch; with --lut reading the table) and of the evaluations, without the CSV input and output");
  actions.emplace_back(command, [options]() {
    if (!options->lut.empty()) {
      const std::vector<Query> queries = read_queries(options->at, options->queries);
      if (queries.empty()) throw libbrdf::InvalidArgument("at", "no queries: give --at TI,TS,PHIS or --queries FILE|-");
      return evaluate_table(*options, queries);
    }
    if (options->model.model.empty()) throw libbrdf::InvalidArgument("model", "required (or --lut FILE)");
    const std::vector<double> wavelengths = channel_wavelengths(options->model, {0.55});
    if (wavelengths.size() != 1)
      throw libbrdf::InvalidArgument("wavelength", "eval takes one wavelength (got " + std::to_string(wavelengths.size()) + ")");
    double setup_start = process_cpu_seconds();
    const libbrdf::Model model(parse_model_kind(options->model), model_parameters(options->model, wavelengths[0]));
    double setup_seconds = process_cpu_seconds() - setup_start;
    const std::vector<Query> queries = read_queries(options->at, options->queries);
    if (queries.empty()) throw libbrdf::InvalidArgument("at", "no queries: give --at TI,TS,PHIS or --queries FILE|-");
    if (options->timing && queries.size() >= libbrdf::kBatchParallelThreshold) {
      // oneTBB starts its scheduler at its first parallel loop (~3 ms of CPU here). A model with K
      // tables has started it in its set-up already; start it now for every model, so that the
      // evaluations' time is the same steady-state quantity whatever the model.
      setup_start = process_cpu_seconds();
      tbb::parallel_for(0, 1, [](int) {});
      setup_seconds += process_cpu_seconds() - setup_start;
    }
    // The batch API in degrees (libbrdf/batch.h): the same values as the Python module, in parallel.
    std::vector<double> theta_i(queries.size()), theta_s(queries.size()), phi_s(queries.size());
    for (std::size_t k = 0; k < queries.size(); ++k)
      theta_i[k] = queries[k].theta_i_deg, theta_s[k] = queries[k].theta_s_deg, phi_s[k] = queries[k].phi_s_deg;
    std::vector<double> values(queries.size());
    const double evaluation_start = process_cpu_seconds();
    try {
      libbrdf::evaluate_degrees_batch(model, theta_i.data(), theta_s.data(), phi_s.data(), queries.size(), values.data());
    } catch (const libbrdf::InvalidQuery& e) {
      throw libbrdf::InvalidArgument(e.parameter(), queries[e.index()].origin() + ": " + e.reason());
    }
    if (options->timing) report_timing(setup_seconds, process_cpu_seconds() - evaluation_start, values.size());
    write_evaluations(std::cout, queries, values);
    return 0;
  });
}

}  // namespace brdf_cli
