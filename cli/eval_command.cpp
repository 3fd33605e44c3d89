// `brdf eval`: a model at query angles, CSV out. The interface is a contract other tools call:
//   brdf eval --model NAME [surface params] (--at TI,TS,PHIS ... | --queries FILE|-)
#include <iostream>
#include <memory>

#include "commands.h"
#include "libbrdf/error.h"
#include "libbrdf/models.h"
#include "model_options.h"
#include "query_input.h"

namespace brdf_cli {

namespace {
struct EvalOptions {
  ModelOptions model;
  std::vector<std::string> at;
  std::string queries;
};
}  // namespace

void register_eval(CLI::App& app, ActionTable& actions) {
  auto options = std::make_shared<EvalOptions>();
  CLI::App* command = app.add_subcommand("eval", "Evaluate a model at query angles (degrees); CSV on stdout");
  add_model_options(*command, options->model);
  command->add_option("--at", options->at, "One query TI,TS,PHIS in degrees (repeatable)")->allow_extra_args(false);
  command->add_option("--queries", options->queries, "CSV file of theta_i,theta_s,phi_s lines, or - for stdin");
  actions.emplace_back(command, [options]() {
    const std::vector<double> wavelengths = channel_wavelengths(options->model, {0.55});
    if (wavelengths.size() != 1)
      throw libbrdf::InvalidArgument("wavelength", "eval takes one wavelength (got " + std::to_string(wavelengths.size()) + ")");
    const libbrdf::Model model(parse_model_kind(options->model), model_parameters(options->model, wavelengths[0]));
    const std::vector<Query> queries = read_queries(options->at, options->queries);
    if (queries.empty()) throw libbrdf::InvalidArgument("at", "no queries: give --at TI,TS,PHIS or --queries FILE|-");
    write_evaluations(std::cout, queries, [&](const libbrdf::ScatterAngles& a) { return model.evaluate(a); });
    return 0;
  });
}

}  // namespace brdf_cli
