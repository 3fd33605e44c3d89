// export_material (blender_export.h): the body of `brdf export blender`, shared with Python.
#include "exporters/blender_export.h"

#include <filesystem>
#include <sstream>

#include "exporters/blender.h"
#include "exporters/fit.h"
#include "libbrdf/error.h"
#include "libbrdf/image_file.h"
#include "libbrdf/lut.h"
#include "libbrdf/version.h"

namespace libbrdf::blender {
namespace {
namespace fs = std::filesystem;

// The error of a reused P~ with this surface's K and Sigma is measured on fewer samples than a
// bake's: a roughness change should take well under a second (0.2 s CPU at 20000).
constexpr int kReusedErrorSamples = 4000;

// One line per channel: wavelength, sigma_s, l_c, n + i kappa (the OSL shader's header comment).
std::string channels_summary(const std::vector<ModelParameters>& channels) {
  std::ostringstream out;
  out.precision(7);
  out << "channels (lambda um, sigma_s um, l_c um, n, kappa):";
  for (const ModelParameters& p : channels) {
    out << "\n  " << p.wavelength_um << ", " << p.sigma_s_um.value_or(0.0) << ", " << p.lc_um.value_or(0.0);
    if (p.index) out << ", " << p.index->n << ", " << p.index->kappa;
  }
  return out.str();
}

void validate(const MaterialExportRequest& r) {
  if (r.mode != "lut" && r.mode != "osl" && r.mode != "fit")
    throw InvalidArgument("mode", "must be one of lut|osl|fit (got '" + message_excerpt(r.mode) + "')");
  if (fs::path(r.output).extension() != ".json")
    throw InvalidArgument("output", "must name a .json file (got '" + message_excerpt(r.output) + "')");
  if (r.resolution && r.target_error)
    throw InvalidArgument("target-error", "give either --resolution or --target-error, not both");
  if (!is_brdf(r.model))
    throw InvalidArgument("model", std::string(model_name(r.model)) +
                                       " is not a BRDF (one of mbk, mbk-polished, mbk-rough, mbk-fg, bk, bk-modified, microfacet)");
  if (r.channels.size() != 1 && r.channels.size() != 3)
    throw InvalidArgument("wavelength", "Blender materials take 1 or 3 wavelengths (R,G,B; got " +
                                            std::to_string(r.channels.size()) + ")");
  if (r.mode == "fit" && r.resolution)
    throw InvalidArgument("resolution", "--mode fit bakes no table (give --target-error for the fit)");
}

// FIT: Beckmann lobes for Cycles; signed GGX lobes for EEVEE (lit one by one through Shader to RGB
// in the add-on: a non-negative GGX mixture cannot fall off like MBK's Gaussian lobe, measured in
// EEVEE: median error ~45%), none in the roughness band where EEVEE's GGX is not GGX (blender.h).
void fit_lobes(const MaterialExportRequest& r, const std::vector<Model>& models, fit::NativeFit& cycles,
               fit::NativeFit& eevee, std::string& log) {
  fit::FitRequest fit_request;
  fit_request.target_error = r.target_error.value_or(fit::kDefaultTargetError);
  fit_request.shape = fit::LobeShape::beckmann;
  fit_request.view_dependent_roughness = true;  // Cycles: alpha(N.V) per lobe (fit.h, lobe_alpha)
  cycles = fit::fit_native_lobes(models, fit_request);
  fit_request.view_dependent_roughness = false;
  fit_request.shape = fit::LobeShape::ggx;
  fit_request.signed_colours = true;
  fit_request.excluded_alpha_low = kEeveeGgxBandLow * kEeveeGgxBandLow;
  fit_request.excluded_alpha_high = kEeveeGgxBandHigh * kEeveeGgxBandHigh;
  eevee = fit::fit_native_lobes(models, fit_request);
  std::ostringstream out;
  for (const auto* f : {&cycles, &eevee})
    out << "fit (" << (f == &cycles ? "Cycles, Beckmann" : "EEVEE, GGX") << "): " << f->lobes.size()
        << " lobes, per-pixel error median " << 100.0 * f->quality.median << "%, p95 " << 100.0 * f->quality.p95
        << "% (target " << 100.0 * fit_request.target_error << "%" << (f->target_met ? "" : ", not met") << ")\n";
  for (const auto* f : {&cycles, &eevee}) {
    out << "  by sun-camera angle (" << (f == &cycles ? "Cycles" : "EEVEE") << "), median / p95:";
    for (const fit::SunAngleQuality& b : f->by_sun_angle)
      out << " " << b.from_deg << "-" << b.to_deg << " deg " << 100.0 * b.quality.median << "% / " << 100.0 * b.quality.p95 << "%;";
    out << "\n";
  }
  log += out.str();
}

}  // namespace

MaterialExport export_material(const MaterialExportRequest& r) {
  validate(r);
  const fs::path output(r.output);
  require_writable_output(output.string(), "output", /*create_directory=*/true);  // bl/x.json creates bl/
  MaterialExport result;
  std::vector<std::string>& written = result.written;

  BlenderExport e;
  e.mode = r.mode;
  e.model = r.model;
  e.name = r.name.empty() ? output.stem().string() : r.name;
  e.channels = r.channels;
  e.spike = spike_fit(r.model, e.channels);
  const std::vector<Model> models = channel_models(r.model, e.channels);
  fit::NativeFit lobes, lobes_eevee;
  if (r.mode == "fit") {
    fit_lobes(r, models, lobes, lobes_eevee, result.log);
    e.lobes = &lobes;
    e.lobes_eevee = &lobes_eevee;
  }

  // NAME.exr, NAME.osl and NAME.json (and the shared images the export writes) are published
  // together (image_file.h): a failure or a signal before the end leaves none of them, and the
  // add-on never sees a description beside another export's images.
  PublicationGroup files;
  Lut lut;
  KernelFiles kernel;
  const std::string header = "Generated by brdf export blender (libbrdf " + std::string(kVersion) + ").\n" +
                             "Model " + std::string(model_name(r.model)) + ", " + channels_summary(e.channels);
  const auto publish_osl = [&](const std::string& source) {
    const fs::path osl_path = fs::path(output).replace_extension(".osl");
    write_text_file_atomically(osl_path.string(), source);
    written.push_back(osl_path.string());
  };
  if (r.mode != "fit") {
    if (r.mode == "osl") {
      e.osl_file = fs::path(output).replace_extension(".osl").filename().string();
      e.osl_shader_name = osl_identifier(e.name);
    }
    BakeRequest request;
    request.model = r.model;
    request.channels = e.channels;
    request.resolution = r.resolution;
    request.target_error = r.target_error;
    const fs::path side_path = fs::path(output).replace_extension(".exr");
    if (kernel_export_model(r.model)) {
      // The factored form (blender.h): only the side rows depend on sigma_s and l_c (and P~ of
      // mbk-fg); the angular atlas and the Sigma image are reused when present beside the output.
      request.layout = LutLayout::kernel;
      request.kernel_angular = KernelAngular::table;  // the node graph reads P~ from the atlas
      // The shared images beside the output, spelt as the output's own directory: the publication
      // locks each target directory by its path, and two spellings of one directory would deadlock.
      const fs::path directory = output.parent_path();
      kernel.sigma = sigma_image_layout();
      kernel.sigma_file = sigma_image_file_name(kernel.sigma);
      const fs::path sigma_path = directory / kernel.sigma_file;
      kernel.sigma_reused = fs::exists(sigma_path);
      if (!kernel.sigma_reused) {
        write_sigma_image_exr(kernel.sigma, sigma_path.string());
        written.push_back(sigma_path.string());
      }
      const std::string table = r.target_error ? "target-error " + std::to_string(*r.target_error)
                                               : shape_text(request.resolution.value_or(default_resolution(request.layout)),
                                                            request.layout);
      kernel.angular_file = angular_file_name(angular_cache_key(models, table));
      const fs::path angular_path = directory / kernel.angular_file;
      kernel.angular_reused = fs::exists(angular_path);
      if (kernel.angular_reused) {
        lut = kernel_lut_from_angular_atlas(angular_path.string(), models);
        lut.error = measure_lut_error(lut, models, kReusedErrorSamples, request.error_floor_fraction, request.seed,
                                      request.error_theta_limit_deg);
      } else {
        lut = bake(request);
      }
      kernel.angular = blender_atlas_layout(lut.shape, 0);
      if (!kernel.angular_reused) {
        write_blender_atlas_exr(lut, kernel.angular, angular_path.string());
        written.push_back(angular_path.string());
      }
      kernel.side_file = side_path.filename().string();
      write_side_rows_exr(models, side_path.string());
      written.push_back(side_path.string());
      e.kernel = &kernel;
      e.lut = &lut;
      if (r.mode == "osl") publish_osl(osl_kernel_shader_source(e, fs::absolute(directory).string(), header));
    } else {
      request.layout = LutLayout::rusinkiewicz;
      lut = bake(request);
      e.lut = &lut;
      e.atlas = blender_atlas_layout(lut.shape, static_cast<int>(lut.specular_reflectance.at(0).size()));
      e.atlas_file = side_path.filename().string();
      write_blender_atlas_exr(lut, e.atlas, side_path.string());
      written.push_back(side_path.string());
      if (r.mode == "osl")
        publish_osl(osl_shader_source(e.atlas, e.osl_shader_name, fs::absolute(side_path).lexically_normal().string(), header));
    }
  }
  write_text_file_atomically(output.string(), blender_description_json(e));
  written.push_back(output.string());
  files.publish();
  return result;
}

}  // namespace libbrdf::blender
