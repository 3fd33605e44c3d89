// `brdf export blender`: a material for the Blender add-on (blender_addon/libbrdf_materials).
//   brdf export blender --model NAME [surface params] [--wavelength R,G,B] --output DIR/NAME.json
//                       [--mode lut|osl|fit] [--resolution N0,N1,N2 | --target-error E] [--name NAME]
// Writes NAME.json (always), NAME.exr (lut, osl: the side rows of the factored form for the ASF
// models, else the rusinkiewicz table as an atlas), the shared angular atlas and Sigma image beside
// it unless present (ASF models), and NAME.osl (osl); prints each written path on its own line.
// Formats: exporters/include/exporters/blender.h.
#include <iostream>
#include <memory>

#include "commands.h"
#include "exporters/blender_export.h"
#include "interrupt.h"
#include "model_options.h"

namespace brdf_cli {

namespace {

struct ExportBlenderOptions {
  ModelOptions model;
  std::string output;
  std::string mode = "lut";
  std::string resolution;
  std::optional<double> target_error;
  std::string name;
};

int run_export_blender(const ExportBlenderOptions& o) {
  handle_interrupts("export blender");
  libbrdf::blender::MaterialExportRequest request;
  request.model = parse_model_kind(o.model);
  request.mode = o.mode;
  request.output = o.output;
  if (!o.resolution.empty()) request.resolution = parse_node_counts(o.resolution, 3);
  request.target_error = o.target_error;
  request.name = o.name;
  for (double w : channel_wavelengths(o.model, {0.65, 0.55, 0.45})) request.channels.push_back(model_parameters(o.model, w));
  const libbrdf::blender::MaterialExport exported = libbrdf::blender::export_material(request);
  outputs_published();
  std::cerr << exported.log;
  for (const std::string& path : exported.written) std::cout << path << "\n";
  return 0;
}
}  // namespace

void register_export_blender(CLI::App& app, ActionTable& actions) {
  auto options = std::make_shared<ExportBlenderOptions>();
  CLI::App* command = export_parent(app).add_subcommand(
      "blender", "Bake a material for the libbrdf Blender add-on: atlas EXR + node description JSON (+ OSL shader)");
  add_model_options(*command, options->model);
  command->add_option("--output", options->output, "Description file DIR/NAME.json (NAME.exr, NAME.osl beside it)")->required();
  command->add_option("--mode", options->mode, "lut (table + emission nodes, default) | osl (also an OSL shader) | fit (native BSDF only, no table)");
  command->add_option("--resolution", options->resolution, "Table nodes N0,N1,N2 (theta_h, theta_d, phi_d): the angular factor P~ of the ASF models (default 54,54,54), else the rusinkiewicz table (default: the bake's)");
  command->add_option("--target-error", options->target_error, "lut/osl: smallest table whose measured max relative error meets this; fit: p95 per-pixel error the lobe count must meet (default 0.1)");
  command->add_option("--name", options->name, "Material name (default: NAME of --output)");
  actions.emplace_back(command, [options]() { return run_export_blender(*options); });
}

}  // namespace brdf_cli
