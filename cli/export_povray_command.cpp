// `brdf export povray`: a POV-Ray 3.7 include with NAME_Exact (exact radiance for one sun and a
// distant camera, as emission) and NAME_Fit (a fitted native finish). See exporters/povray.h.
//   brdf export povray --model NAME [surface params] [--wavelength R,G,B] --light-dir X,Y,Z
//                      --view-dir X,Y,Z --name NAME [--resolution N] [--target-error E] -o DIR
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.h"
#include "interrupt.h"
#include "exporters/povray.h"
#include "libbrdf/error.h"
#include "model_options.h"

namespace brdf_cli {

namespace {
struct ExportPovrayOptions {
  ModelOptions model;
  std::string light_dir, view_dir, name, output;
  int resolution = libbrdf::povray::kMaxMapEntries;
  double target_error = libbrdf::fit::kDefaultTargetError;  // NAME_Fit's lobe count (exporters/fit.h)
};

// The output directory, checked before any work: an existing writable directory, or a path whose
// nearest existing ancestor is a writable directory (export_povray creates the rest).
void require_output_directory(const std::string& output) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path existing = fs::absolute(fs::path(output), ec);
  while (!existing.empty() && !fs::exists(existing, ec) && existing.has_parent_path() && existing != existing.parent_path())
    existing = existing.parent_path();
  const std::string shown = libbrdf::message_excerpt(existing.string());
  if (!fs::is_directory(existing, ec)) throw libbrdf::InvalidArgument("output", "'" + shown + "' exists and is not a directory");
  if (::access(existing.c_str(), W_OK | X_OK) != 0) throw libbrdf::InvalidArgument("output", "directory '" + shown + "' is not writable");
}

}  // namespace

void register_export_povray(CLI::App& app, ActionTable& actions) {
  auto options = std::make_shared<ExportPovrayOptions>();
  CLI::App* command = export_parent(app).add_subcommand(
      "povray",
      "POV-Ray 3.7 include: NAME_Exact (exact radiance for one sun, distant camera) and NAME_Fit (native finish)");
  add_model_options(*command, options->model);
  command->add_option("--light-dir", options->light_dir,
                      "POV-Ray world vector X,Y,Z from the surface towards the (parallel) light")->required();
  command->add_option("--view-dir", options->view_dir,
                      "POV-Ray world vector X,Y,Z from the surface towards the (distant) camera")->required();
  command->add_option("--name", options->name, "Identifier prefix and file name: writes DIR/NAME.inc")->required();
  command->add_option("--resolution", options->resolution,
                      "Map entries per table axis, 8..256 (POV-Ray 3.7's limit; default 256)");
  command->add_option("--target-error", options->target_error,
                      "NAME_Fit: p95 per-pixel relative error the number of fitted lobes must meet, (0, 1] (default 0.1)");
  command->add_option("-o,--output", options->output, "Output directory (created if missing)")->required();
  actions.emplace_back(command, [options]() {
    handle_interrupts("export povray");
    libbrdf::povray::validate_include_name(options->name);
    require_output_directory(options->output);
    const std::vector<double> wavelengths = channel_wavelengths(options->model, {0.65, 0.55, 0.45});
    if (wavelengths.size() != 3)
      throw libbrdf::InvalidArgument("wavelength", "POV-Ray colours need exactly 3 wavelengths R,G,B (got " +
                                                       std::to_string(wavelengths.size()) + ")");
    libbrdf::povray::SliceRequest request;
    request.model = parse_model_kind(options->model);
    for (double w : wavelengths) request.channels.push_back(model_parameters(options->model, w));
    request.light = parse_direction(options->light_dir, "light-dir");
    request.view = parse_direction(options->view_dir, "view-dir");
    request.entries = options->resolution;
    libbrdf::fit::validate_target_error(options->target_error);
    request.fit_target_error = options->target_error;
    const libbrdf::povray::ExportResult result =
        libbrdf::povray::export_povray(request, options->name, options->output);
    outputs_published();
    const auto& e = result.slice.error;
    std::cout << "wrote " << result.include_path << "\n"
              << "  exact table: " << result.slice.half_nodes.size() << " x " << result.slice.light_nodes.size()
              << " nodes (N.H x N.L), max error ";
    if (e.samples > 0) std::cout << 100.0 * e.max_relative << "%, rms " << 100.0 * e.rms_relative << "%";
    else std::cout << "n/a";
    std::cout << " (theta <= " << e.theta_limit_deg << " deg; up to the horizon " << 100.0 * e.max_relative_all
              << "%)\n"
              << "  fit: " << result.fit.lobes.lobes.size() << " Blinn lobes, per-pixel error median "
              << 100.0 * result.fit.lobes.quality.median << "%, p95 " << 100.0 * result.fit.lobes.quality.p95
              << "% (target " << 100.0 * options->target_error << "%" << (result.fit.lobes.target_met ? "" : ", not met")
              << "), peak fit/exact "
              << result.fit.peak_ratio[0] << ", " << result.fit.peak_ratio[1] << ", " << result.fit.peak_ratio[2]
              << "\n";
    return 0;
  });
}

}  // namespace brdf_cli
