// `brdf albedo`: directional albedo (white furnace) of a BRDF model against theta_i, CSV out.
//   brdf albedo --model NAME [surface params as in eval] [--theta-i A,B,...] [--tolerance-albedo REL]
// CSV: theta_i,albedo,lobe,specular,error_estimate -- albedo = lobe + specular, lobe the integral of
// f cos ts over the hemisphere, specular R_spec (the spike), error_estimate the quadrature's own
// (absolute). libbrdf/include/libbrdf/albedo.h says how; docs/reference.md which models exceed 1 where.
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "commands.h"
#include "libbrdf/albedo.h"
#include "libbrdf/error.h"
#include "model_options.h"

namespace brdf_cli {

namespace {
struct AlbedoOptions {
  ModelOptions model;
  std::string theta_i = "0,10,20,30,40,50,60,70,75,80,85,88";
  double tolerance = 1e-6;
};

int run_albedo(const AlbedoOptions& o) {
  using libbrdf::InvalidArgument;
  const libbrdf::ModelKind kind = parse_model_kind(o.model);
  if (!libbrdf::is_brdf(kind))
    throw InvalidArgument("model", std::string(libbrdf::model_name(kind)) +
                                       " is not a BRDF (one of mbk, mbk-polished, mbk-rough, mbk-fg, bk, bk-modified, microfacet)");
  const std::vector<double> wavelengths = channel_wavelengths(o.model, {0.55});
  if (wavelengths.size() != 1)
    throw InvalidArgument("wavelength", "albedo takes one wavelength (got " + std::to_string(wavelengths.size()) + ")");
  const std::vector<double> angles = parse_number_list(o.theta_i, 0, "theta-i");
  for (double a : angles) libbrdf::require_polar_angle("theta-i", libbrdf::degrees_to_radians(a));
  const libbrdf::Model model(kind, model_parameters(o.model, wavelengths[0]));
  libbrdf::AlbedoOptions options;
  options.relative_tolerance = o.tolerance;
  std::vector<libbrdf::DirectionalAlbedo> results(angles.size());
  tbb::parallel_for(std::size_t{0}, angles.size(), [&](std::size_t k) {
    results[k] = libbrdf::directional_albedo(model, libbrdf::degrees_to_radians(angles[k]), options);
  });
  std::cout << "theta_i,albedo,lobe,specular,error_estimate\n";
  char line[192];
  for (std::size_t k = 0; k < angles.size(); ++k) {
    const auto& r = results[k];
    if (!std::isfinite(r.total)) throw InvalidArgument("value", "albedo is not finite at theta_i = " + std::to_string(angles[k]));
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g,%.3g\n", angles[k], r.total, r.lobe, r.specular, r.error_estimate);
    std::cout << line;
  }
  return 0;
}
}  // namespace

void register_albedo(CLI::App& app, ActionTable& actions) {
  auto options = std::make_shared<AlbedoOptions>();
  CLI::App* command = app.add_subcommand(
      "albedo", "Directional albedo (white furnace, specular spike included) of a BRDF model against theta_i; CSV on stdout");
  add_model_options(*command, options->model);
  command->add_option("--theta-i", options->theta_i, "Incidence angles A,B,... in degrees, each in [0, 90) (default 0,10,...,88)");
  command->add_option("--albedo-tolerance", options->tolerance, "Relative tolerance of the adaptive quadrature, in (0, 0.01) (default 1e-6)");
  actions.emplace_back(command, [options]() { return run_albedo(*options); });
}

}  // namespace brdf_cli
