// `brdf export blender`: a material for the Blender add-on (blender_addon/libbrdf_materials).
//   brdf export blender --model NAME [surface params] [--wavelength R,G,B] --output DIR/NAME.json
//                       [--mode lut|osl|fit] [--resolution N0,N1,N2 | --target-error E] [--name NAME]
// Writes NAME.json (always), NAME.exr (lut, osl: the rusinkiewicz table as an atlas) and NAME.osl
// (osl); prints each written path on its own line. Formats: exporters/include/exporters/blender.h.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.h"
#include "interrupt.h"
#include "libbrdf/image_file.h"
#include "exporters/blender.h"
#include "libbrdf/error.h"
#include "libbrdf/lut.h"
#include "libbrdf/version.h"
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
  namespace fs = std::filesystem;
  using libbrdf::InvalidArgument;
  handle_interrupts("export blender");
  if (o.mode != "lut" && o.mode != "osl" && o.mode != "fit")
    throw InvalidArgument("mode", "must be one of lut|osl|fit (got '" + o.mode + "')");
  const fs::path output(o.output);
  if (output.extension() != ".json") throw InvalidArgument("output", "must name a .json file (got '" + libbrdf::message_excerpt(o.output) + "')");
  require_writable_output(o.output, "output");
  if (!o.resolution.empty() && o.target_error)
    throw InvalidArgument("target-error", "give either --resolution or --target-error, not both");

  const libbrdf::ModelKind kind = parse_model_kind(o.model);
  if (!libbrdf::is_brdf(kind))
    throw InvalidArgument("model", std::string(libbrdf::model_name(kind)) +
                                       " is not a BRDF (one of mbk, mbk-polished, mbk-rough, mbk-fg, bk, bk-modified, microfacet)");
  const std::vector<double> wavelengths = channel_wavelengths(o.model, {0.65, 0.55, 0.45});
  if (wavelengths.size() != 1 && wavelengths.size() != 3)
    throw InvalidArgument("wavelength", "Blender materials take 1 or 3 wavelengths (R,G,B; got " +
                                            std::to_string(wavelengths.size()) + ")");
  libbrdf::blender::BlenderExport e;
  e.mode = o.mode;
  e.model = kind;
  e.name = o.name.empty() ? output.stem().string() : o.name;
  for (double w : wavelengths) e.channels.push_back(model_parameters(o.model, w));
  e.spike = libbrdf::blender::spike_fit(kind, e.channels);
  libbrdf::fit::NativeFit lobes, lobes_eevee;
  if (o.mode == "fit") {
    // --target-error is the fit's (p95 per-pixel error, fit.h); in lut/osl mode the table's.
    libbrdf::fit::FitRequest fit_request;
    fit_request.target_error = o.target_error.value_or(libbrdf::fit::kDefaultTargetError);
    if (!o.resolution.empty()) throw InvalidArgument("resolution", "--mode fit bakes no table (give --target-error for the fit)");
    const std::vector<libbrdf::Model> models = libbrdf::channel_models(kind, e.channels);
    fit_request.shape = libbrdf::fit::LobeShape::beckmann;
    lobes = libbrdf::fit::fit_native_lobes(models, fit_request);
    fit_request.shape = libbrdf::fit::LobeShape::ggx;
    // EEVEE: signed GGX lobes (lit one by one through Shader to RGB in the add-on): a non-negative GGX
    // mixture cannot fall off like MBK's Gaussian lobe (measured in EEVEE: median error ~45%).
    fit_request.signed_colours = true;
    lobes_eevee = libbrdf::fit::fit_native_lobes(models, fit_request);
    e.lobes = &lobes;
    e.lobes_eevee = &lobes_eevee;
    for (const auto* f : {&lobes, &lobes_eevee})
      std::cerr << "fit (" << (f == &lobes ? "Cycles, Beckmann" : "EEVEE, GGX") << "): " << f->lobes.size()
                << " lobes, per-pixel error median " << 100.0 * f->quality.median << "%, p95 " << 100.0 * f->quality.p95
                << "% (target " << 100.0 * fit_request.target_error << "%" << (f->target_met ? "" : ", not met") << ")\n";
  }

  std::vector<std::string> written;
  // NAME.exr, NAME.osl and NAME.json are published together (image_file.h): a failure or a
  // signal before the end leaves none of them, and the add-on never sees a description beside
  // another export's atlas.
  libbrdf::PublicationGroup files;
  libbrdf::Lut lut;
  if (o.mode != "fit") {
    libbrdf::BakeRequest request;
    request.model = kind;
    request.channels = e.channels;
    request.layout = libbrdf::LutLayout::rusinkiewicz;
    if (!o.resolution.empty()) request.resolution = parse_node_counts(o.resolution, 3);
    request.target_error = o.target_error;
    lut = libbrdf::bake(request);
    e.lut = &lut;
    e.atlas = libbrdf::blender::blender_atlas_layout(lut.shape, static_cast<int>(lut.specular_reflectance.at(0).size()));
    const fs::path atlas_path = fs::path(output).replace_extension(".exr");
    e.atlas_file = atlas_path.filename().string();
    libbrdf::blender::write_blender_atlas_exr(lut, e.atlas, atlas_path.string());
    written.push_back(atlas_path.string());
    if (o.mode == "osl") {
      const fs::path osl_path = fs::path(output).replace_extension(".osl");
      e.osl_file = osl_path.filename().string();
      e.osl_shader_name = libbrdf::blender::osl_identifier(e.name);
      const std::string header = "Generated by brdf export blender (libbrdf " + std::string(libbrdf::kVersion) + ").\n" +
                                 "Model " + std::string(libbrdf::model_name(kind)) + ", parameters " +
                                 lut.attributes["parameters"];
      libbrdf::write_text_file_atomically(
          osl_path.string(), libbrdf::blender::osl_shader_source(e.atlas, e.osl_shader_name,
                                                                   fs::absolute(atlas_path).lexically_normal().string(), header));
      written.push_back(osl_path.string());
    }
  }
  libbrdf::write_text_file_atomically(output.string(), libbrdf::blender::blender_description_json(e));
  written.push_back(output.string());
  files.publish();
  outputs_published();
  for (const std::string& path : written) std::cout << path << "\n";
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
  command->add_option("--resolution", options->resolution, "Table nodes N0,N1,N2 (theta_h, theta_d, phi_d); default: the bake's");
  command->add_option("--target-error", options->target_error, "lut/osl: smallest table whose measured max relative error meets this; fit: p95 per-pixel error the lobe count must meet (default 0.1)");
  command->add_option("--name", options->name, "Material name (default: NAME of --output)");
  actions.emplace_back(command, [options]() { return run_export_blender(*options); });
}

}  // namespace brdf_cli
