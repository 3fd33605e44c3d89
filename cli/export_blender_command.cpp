// `brdf export blender`: a material for the Blender add-on (blender_addon/libbrdf_materials).
//   brdf export blender --model NAME [surface params] [--wavelength R,G,B] --output DIR/NAME.json
//                       [--mode lut|osl|fit] [--resolution N0,N1,N2 | --target-error E] [--name NAME]
// Writes NAME.json (always), NAME.exr (lut, osl: the side rows of the factored form for the ASF
// models, else the rusinkiewicz table as an atlas), the shared angular atlas and Sigma image beside
// it unless present (ASF models), and NAME.osl (osl); prints each written path on its own line.
// Formats: exporters/include/exporters/blender.h.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

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
constexpr int kReusedErrorSamples = 4000;

struct ExportBlenderOptions {
  ModelOptions model;
  std::string output;
  std::string mode = "lut";
  std::string resolution;
  std::optional<double> target_error;
  std::string name;
};


// One line per channel: wavelength, sigma_s, l_c, n + i kappa (the OSL shader's header comment).
std::string channels_summary(const std::vector<libbrdf::ModelParameters>& channels) {
  std::ostringstream out;
  out.precision(7);
  out << "channels (lambda um, sigma_s um, l_c um, n, kappa):";
  for (const libbrdf::ModelParameters& p : channels) {
    out << "\n  " << p.wavelength_um << ", " << p.sigma_s_um.value_or(0.0) << ", " << p.lc_um.value_or(0.0);
    if (p.index) out << ", " << p.index->n << ", " << p.index->kappa;
  }
  return out.str();
}

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
    fit_request.view_dependent_roughness = true;  // Cycles: alpha(N.V) per lobe (fit.h, lobe_alpha)
    lobes = libbrdf::fit::fit_native_lobes(models, fit_request);
    fit_request.view_dependent_roughness = false;
    fit_request.shape = libbrdf::fit::LobeShape::ggx;
    // EEVEE: signed GGX lobes (lit one by one through Shader to RGB in the add-on): a non-negative GGX
    // mixture cannot fall off like MBK's Gaussian lobe (measured in EEVEE: median error ~45%).
    fit_request.signed_colours = true;
    // ... and none in the roughness band where EEVEE's GGX is not GGX (blender.h).
    fit_request.excluded_alpha_low = libbrdf::blender::kEeveeGgxBandLow * libbrdf::blender::kEeveeGgxBandLow;
    fit_request.excluded_alpha_high = libbrdf::blender::kEeveeGgxBandHigh * libbrdf::blender::kEeveeGgxBandHigh;
    lobes_eevee = libbrdf::fit::fit_native_lobes(models, fit_request);
    e.lobes = &lobes;
    e.lobes_eevee = &lobes_eevee;
    for (const auto* f : {&lobes, &lobes_eevee})
      std::cerr << "fit (" << (f == &lobes ? "Cycles, Beckmann" : "EEVEE, GGX") << "): " << f->lobes.size()
                << " lobes, per-pixel error median " << 100.0 * f->quality.median << "%, p95 " << 100.0 * f->quality.p95
                << "% (target " << 100.0 * fit_request.target_error << "%" << (f->target_met ? "" : ", not met") << ")\n";
    for (const auto* f : {&lobes, &lobes_eevee}) {
      std::cerr << "  by sun-camera angle (" << (f == &lobes ? "Cycles" : "EEVEE") << "), median / p95:";
      for (const libbrdf::fit::SunAngleQuality& b : f->by_sun_angle)
        std::cerr << " " << b.from_deg << "-" << b.to_deg << " deg " << 100.0 * b.quality.median << "% / "
                  << 100.0 * b.quality.p95 << "%;";
      std::cerr << "\n";
    }
  }

  std::vector<std::string> written;
  // NAME.exr, NAME.osl and NAME.json (and the shared images the export writes) are published
  // together (image_file.h): a failure or a signal before the end leaves none of them, and the
  // add-on never sees a description beside another export's images.
  libbrdf::PublicationGroup files;
  libbrdf::Lut lut;
  libbrdf::blender::KernelFiles kernel;
  const std::string header = "Generated by brdf export blender (libbrdf " + std::string(libbrdf::kVersion) + ").\n" +
                             "Model " + std::string(libbrdf::model_name(kind)) + ", " + channels_summary(e.channels);
  const auto publish_osl = [&](const std::string& source) {
    const fs::path osl_path = fs::path(output).replace_extension(".osl");
    libbrdf::write_text_file_atomically(osl_path.string(), source);
    written.push_back(osl_path.string());
  };
  if (o.mode != "fit") {
    if (o.mode == "osl") {
      e.osl_file = fs::path(output).replace_extension(".osl").filename().string();
      e.osl_shader_name = libbrdf::blender::osl_identifier(e.name);
    }
    libbrdf::BakeRequest request;
    request.model = kind;
    request.channels = e.channels;
    if (!o.resolution.empty()) request.resolution = parse_node_counts(o.resolution, 3);
    request.target_error = o.target_error;
    const fs::path side_path = fs::path(output).replace_extension(".exr");
    if (libbrdf::blender::kernel_export_model(kind)) {
      // The factored form (blender.h): only the side rows depend on sigma_s and l_c (and P~ of
      // mbk-fg); the angular atlas and the Sigma image are reused when present beside the output.
      request.layout = libbrdf::LutLayout::kernel;
      request.kernel_angular = libbrdf::KernelAngular::table;  // the node graph reads P~ from the atlas
      // The shared images beside the output, spelt as the output's own directory: the publication
      // locks each target directory by its path, and two spellings of one directory would deadlock.
      const fs::path directory = output.parent_path();
      const std::vector<libbrdf::Model> models = libbrdf::channel_models(kind, e.channels);
      kernel.sigma = libbrdf::blender::sigma_image_layout();
      kernel.sigma_file = libbrdf::blender::sigma_image_file_name(kernel.sigma);
      const fs::path sigma_path = directory / kernel.sigma_file;
      kernel.sigma_reused = fs::exists(sigma_path);
      if (!kernel.sigma_reused) {
        libbrdf::blender::write_sigma_image_exr(kernel.sigma, sigma_path.string());
        written.push_back(sigma_path.string());
      }
      const std::string table = o.target_error ? "target-error " + std::to_string(*o.target_error)
                                               : libbrdf::shape_text(request.resolution.value_or(libbrdf::default_resolution(request.layout)),
                                                                     request.layout);
      kernel.angular_file = libbrdf::blender::angular_file_name(libbrdf::blender::angular_cache_key(models, table));
      const fs::path angular_path = directory / kernel.angular_file;
      kernel.angular_reused = fs::exists(angular_path);
      if (kernel.angular_reused) {
        // The error of the reused P~ with this surface's K and Sigma, measured on fewer samples than
        // a bake's (a roughness change should take well under a second; 0.2 s CPU at 20000).
        lut = libbrdf::blender::kernel_lut_from_angular_atlas(angular_path.string(), models);
        lut.error = libbrdf::measure_lut_error(lut, models, kReusedErrorSamples, request.error_floor_fraction, request.seed,
                                               request.error_theta_limit_deg);
      } else {
        lut = libbrdf::bake(request);
      }
      kernel.angular = libbrdf::blender::blender_atlas_layout(lut.shape, 0);
      if (!kernel.angular_reused) {
        libbrdf::blender::write_blender_atlas_exr(lut, kernel.angular, angular_path.string());
        written.push_back(angular_path.string());
      }
      kernel.side_file = side_path.filename().string();
      libbrdf::blender::write_side_rows_exr(models, side_path.string());
      written.push_back(side_path.string());
      e.kernel = &kernel;
      e.lut = &lut;
      if (o.mode == "osl")
        publish_osl(libbrdf::blender::osl_kernel_shader_source(e, fs::absolute(directory).string(), header));
    } else {
      request.layout = libbrdf::LutLayout::rusinkiewicz;
      lut = libbrdf::bake(request);
      e.lut = &lut;
      e.atlas = libbrdf::blender::blender_atlas_layout(lut.shape, static_cast<int>(lut.specular_reflectance.at(0).size()));
      e.atlas_file = side_path.filename().string();
      libbrdf::blender::write_blender_atlas_exr(lut, e.atlas, side_path.string());
      written.push_back(side_path.string());
      if (o.mode == "osl")
        publish_osl(libbrdf::blender::osl_shader_source(e.atlas, e.osl_shader_name,
                                                        fs::absolute(side_path).lexically_normal().string(),
                                                        header));
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
  command->add_option("--resolution", options->resolution, "Table nodes N0,N1,N2 (theta_h, theta_d, phi_d): the angular factor P~ of the ASF models (default 54,54,54), else the rusinkiewicz table (default: the bake's)");
  command->add_option("--target-error", options->target_error, "lut/osl: smallest table whose measured max relative error meets this; fit: p95 per-pixel error the lobe count must meet (default 0.1)");
  command->add_option("--name", options->name, "Material name (default: NAME of --output)");
  actions.emplace_back(command, [options]() { return run_export_blender(*options); });
}

}  // namespace brdf_cli
