// Blender export: the atlas images, the Sigma image, the side rows, the spike parameters, the fitted
// lobes and the JSON description (blender.h).
#include "exporters/blender.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "exporters/energy.h"
#include "libbrdf/beckmann_kirchhoff.h"
#include "libbrdf/error.h"
#include "libbrdf/fresnel.h"
#include "libbrdf/image_file.h"
#include "libbrdf/kernel_table.h"
#include "libbrdf/mbk_series.h"
#include "libbrdf/version.h"

namespace libbrdf::blender {

namespace {

int channel_of_rgb(const Lut& lut, int rgb) { return lut.channels() == 1 ? 0 : rgb; }

void require_blender_table(const Lut& lut) {
  if (lut.layout != LutLayout::rusinkiewicz && lut.layout != LutLayout::kernel)
    throw InvalidArgument("layout", "the Blender atlas packs a rusinkiewicz or kernel table (got " +
                                        std::string(layout_name(lut.layout)) + ")");
  if (lut.channels() != 1 && lut.channels() != 3)
    throw InvalidArgument("wavelength", "Blender materials take 1 or 3 wavelengths (R,G,B; got " +
                                            std::to_string(lut.channels()) + ")");
}

// Texel (x, y) of table node (i0, i1, k) in the atlas (blender.h), y from the bottom.
std::pair<int, int> node_texel(const BlenderAtlas& a, int i0, int i1, int k) {
  return {(k % a.columns) * a.shape[0] + i0, (k / a.columns) * a.shape[1] + i1};
}

std::string atlas_layout_text(const BlenderAtlas& a) {
  std::ostringstream out;
  out << "tile k (phi_d index) at column k%" << a.columns << ", tile row k/" << a.columns << "; texel x = (k%"
      << a.columns << ")*" << a.shape[0] << " + i_theta_h, y = (k/" << a.columns << ")*" << a.shape[1]
      << " + i_theta_d, y counted from the bottom row; ";
  if (a.specular_nodes > 0)
    out << "row y=" << a.specular_row << " holds R_spec at theta_i = 90 deg * x/" << (a.specular_nodes - 1) << "; ";
  out << "node at texel centre ((x+0.5)/" << a.width << ", (y+0.5)/" << a.height
      << "); sample Closest and interpolate between nodes (trilinear)";
  return out.str();
}

// EXR scanlines run top to bottom; the images' rows count from the bottom (Blender's v = 0).
ExrPart bottom_up_exr_part(int width, int height, const std::vector<float>& rgb_texels) {
  ExrPart image{"", width, height, {"R", "G", "B"}, {}, {}};
  const std::size_t row = static_cast<std::size_t>(width) * 3;
  image.pixels.resize(rgb_texels.size());
  for (int y = 0; y < height; ++y)
    std::copy_n(rgb_texels.begin() + static_cast<std::ptrdiff_t>(row * (height - 1 - y)), row,
                image.pixels.begin() + static_cast<std::ptrdiff_t>(row * y));
  return image;
}

// FNV-1a, 64 bit: a stable file-name hash (std::hash is not stable across builds).
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char ch : text) h = (h ^ ch) * 1099511628211ULL;
  return h;
}

std::string hex16(std::uint64_t value) {
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(value));
  return buffer;
}

// One fit's lobes and measured error (the description's "fit" / "fit.eevee").
nlohmann::json lobes_json(const fit::NativeFit& n) {
  using nlohmann::json;
  json lobes = json::array();
  for (const fit::Lobe& l : n.lobes) {
    json colour = json::array();
    for (int c = 0; c < 3; ++c) colour.push_back(l.colour[static_cast<std::size_t>(c)]);
    lobes.push_back({{"alpha", l.roughness}, {"roughness", std::sqrt(l.roughness)}, {"alpha_slope", l.roughness_slope},
                     {"colour", colour}});
  }
  json tried = json::array();
  for (const fit::FitQuality& q : n.tried) tried.push_back(q.p95);
  const bool ggx = n.shape == fit::LobeShape::ggx;
  json out;
  out["distribution"] = ggx ? "ggx" : "beckmann";
  out["signed"] = n.signed_colours;
  out["lobes"] = lobes;
  out["colour_basis"] = "per channel sum_k colour[c][k] B_k(N.V), B_k = C(" + std::to_string(fit::kColourDegree) +
                        ", k) mu^k (1 - mu)^(" + std::to_string(fit::kColourDegree) + " - k), mu = N.V";
  out["bsdf"] = std::string("Glossy BSDF (") + (ggx ? "GGX" : "Beckmann") +
                ") per lobe, roughness = sqrt(alpha(N.V)), added; radiance / E = C D G1 G1 / (4 N.V)";
  out["alpha_of_view"] = "alpha(N.V) = min(alpha max(N.V, min_view_cosine)^-alpha_slope, 1) (alpha_slope 0: a fixed alpha)";
  out["min_view_cosine"] = fit::kMinViewCosine;
  out["error"] = {{"median", n.quality.median},
                  {"p95", n.quality.p95},
                  {"max", n.quality.max},
                  {"values", n.quality.values},
                  {"lowest", n.quality.lowest},
                  {"target_p95", n.target_error},
                  {"target_met", n.target_met},
                  {"p95_by_lobe_count", tried},
                  {"measure", "per pixel and channel |fit - exact| / exact, exact = f_r cos(theta_i), on orthographic "
                              "spheres lit by one sun at two angles from the camera in each band of by_sun_angle; pixels "
                              "with theta_i, theta_s <= 70 deg and every channel above 1% of the scene's maximum; the lobes "
                              "as the renderer evaluates them; lowest = min fit / scene maximum"}};
  // The error per band of the sun-camera angle (fit.h): what a render under one sun at that angle
  // shows, where the pooled numbers above would hide a band that misses the target.
  json bands = json::array();
  for (const fit::SunAngleQuality& b : n.by_sun_angle)
    bands.push_back({{"from_deg", b.from_deg}, {"to_deg", b.to_deg}, {"median", b.quality.median}, {"p95", b.quality.p95},
                     {"values", b.quality.values}});
  out["error"]["by_sun_angle"] = bands;
  return out;
}

// The side rows' values at node j (theta = 90 deg j/(M-1)): R_spec(theta), K(theta), F(theta).
std::array<double, kSideRows> side_node(const Model& model, int j) {
  const double theta = 0.5 * kPi * j / (kThetaINodes - 1);
  return {model.specular_reflectance(theta), model.renormalization(theta),
          fresnel_reflectance(model.parameters().index.value().permittivity(), std::cos(theta))};
}

}  // namespace

BlenderAtlas blender_atlas_layout(const std::array<int, 3>& shape, int specular_nodes) {
  for (int n : shape)
    if (n < 2) throw InvalidArgument("resolution", "each axis needs at least 2 nodes for the Blender atlas");
  if (specular_nodes == 1 || specular_nodes < 0)
    throw InvalidArgument("resolution", "the R_spec table needs at least 2 nodes");
  BlenderAtlas a;
  a.shape = shape;
  a.specular_nodes = specular_nodes;
  // About square: C N0 ~ R N1 with C R >= N2.
  const double ideal = std::sqrt(double(shape[2]) * shape[1] / shape[0]);
  a.columns = std::clamp(static_cast<int>(std::ceil(ideal)), 1, shape[2]);
  a.columns = std::max(a.columns, (specular_nodes + shape[0] - 1) / shape[0]);
  a.tile_rows = (shape[2] + a.columns - 1) / a.columns;
  a.specular_row = a.tile_rows * shape[1];
  a.width = std::max(a.columns * shape[0], specular_nodes);
  a.height = a.specular_row + (specular_nodes > 0 ? 1 : 0);
  if (a.width > 16384 || a.height > 16384)
    throw InvalidArgument("resolution", "the atlas would be " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                            " texels; GPUs take at most 16384 per side");
  return a;
}

std::vector<float> blender_atlas_texels(const Lut& lut, const BlenderAtlas& a) {
  require_blender_table(lut);
  if (lut.shape != a.shape) throw std::logic_error("blender_atlas_texels: atlas made for another table shape");
  const auto [n0, n1, n2] = lut.shape;
  std::vector<float> texels(static_cast<std::size_t>(a.width) * a.height * 3, 0.0f);
  auto at = [&](int x, int y, int rgb) -> float& { return texels[(static_cast<std::size_t>(y) * a.width + x) * 3 + rgb]; };
  const std::size_t per_channel = lut.nodes_per_channel();
  for (int rgb = 0; rgb < 3; ++rgb) {
    const int c = channel_of_rgb(lut, rgb);
    for (int i0 = 0; i0 < n0; ++i0)
      for (int i1 = 0; i1 < n1; ++i1)
        for (int k = 0; k < n2; ++k) {
          const auto [x, y] = node_texel(a, i0, i1, k);
          at(x, y, rgb) = lut.values[c * per_channel + (static_cast<std::size_t>(i0) * n1 + i1) * n2 + k];
        }
    if (a.specular_nodes == 0) continue;
    const std::vector<float>& spec = lut.specular_reflectance.at(c);
    if (static_cast<int>(spec.size()) != a.specular_nodes)
      throw std::logic_error("blender_atlas_texels: atlas made for another R_spec table");
    for (int j = 0; j < a.specular_nodes; ++j) at(j, a.specular_row, rgb) = spec[j];
  }
  return texels;
}

void write_blender_atlas_exr(const Lut& lut, const BlenderAtlas& a, const std::string& path) {
  ExrPart image = bottom_up_exr_part(a.width, a.height, blender_atlas_texels(lut, a));
  const bool kernel = lut.layout == LutLayout::kernel;
  image.attributes["libbrdf:format"] = kernel ? "blender-angular-atlas" : "blender-atlas";
  image.attributes["libbrdf:version"] = kVersion;
  image.attributes["libbrdf:layout"] = std::string(layout_name(lut.layout));
  image.attributes["libbrdf:shape"] = std::to_string(a.shape[0]) + "x" + std::to_string(a.shape[1]) + "x" + std::to_string(a.shape[2]);
  image.attributes["libbrdf:atlas"] = atlas_layout_text(a);
  image.attributes["libbrdf:axis_mapping"] =
      std::string(kernel ? "theta_h = (pi/2) i0/(N0-1)" : "theta_h = (pi/2)(i0/(N0-1))^2") +
      ", theta_d = (pi/2) i1/(N1-1), phi_d = pi k/(N2-1) (MERL's half-vector frame)";
  std::ostringstream wavelengths;
  for (int c = 0; c < lut.channels(); ++c) wavelengths << (c ? "," : "") << lut.wavelengths_um[c];
  image.attributes["libbrdf:wavelengths_um"] = wavelengths.str();
  image.attributes["libbrdf:units"] = kernel ? "angular factor P~ = P / F(theta_d) of the kernel layout (lut.h), dimensionless"
                                             : "BRDF 1/sr; R_spec row dimensionless";
  // The kernel atlas is shared by every roughness: no surface parameters in its header.
  if (!kernel)
    for (const auto& [key, value] : lut.attributes) image.attributes["libbrdf:" + key] = value;
  write_exr(path, {image});
}

// ---- The kernel (factored) form ----------------------------------------------------------------

bool kernel_export_model(ModelKind kind) { return model_traits(kind).asf_based; }

SigmaImage sigma_image_layout() {
  SigmaImage image;
  image.x_min = std::log(kKernelGMin);
  image.dx = kSigmaImageDx;
  image.dz = kSigmaImageDz;
  image.width = static_cast<int>(std::ceil((std::log(kKernelGMax) - image.x_min) / image.dx)) + 1;
  image.height = static_cast<int>(std::lround(kSigmaImageZMax / image.dz)) + 1;
  return image;
}

std::vector<float> sigma_image_values(const SigmaImage& image) {
  std::vector<float> values(static_cast<std::size_t>(image.width) * image.height);
  tbb::parallel_for(0, image.height, [&](int j) {
    const double z = j * image.dz;
    for (int i = 0; i < image.width; ++i) {
      const double x = image.x_min + i * image.dx, g = std::exp(x), z2 = z * z;
      // Sigma by the library's own choice at the kernel table's certified error (prefactor 1).
      const double sigma = asf_auto({g, (g + 1.0) * z2, 1.0}, kKernelTableCertifiedError);
      const double s = std::log(sigma) - (x - std::log1p(g * g)) + z2;
      if (!std::isfinite(s)) throw std::logic_error("sigma_image_values: Sigma underflowed inside the image");
      values[static_cast<std::size_t>(j) * image.width + i] = static_cast<float>(s);
    }
  });
  return values;
}

std::string sigma_image_file_name(const SigmaImage& image) {
  std::ostringstream key;
  key.precision(17);
  key << kVersion << ' ' << image.x_min << ' ' << image.dx << ' ' << image.dz << ' ' << image.width << ' ' << image.height
      << ' ' << kKernelTableCertifiedError << " S = ln Sigma - ln(g/(1+g^2)) + z^2";
  return "libbrdf_sigma_" + hex16(fnv1a(key.str())) + ".exr";
}

void write_sigma_image_exr(const SigmaImage& image, const std::string& path) {
  const std::vector<float> values = sigma_image_values(image);
  std::vector<float> rgb(values.size() * 3);
  for (std::size_t k = 0; k < values.size(); ++k) rgb[3 * k] = rgb[3 * k + 1] = rgb[3 * k + 2] = values[k];
  ExrPart part = bottom_up_exr_part(image.width, image.height, rgb);
  char grid[256];
  std::snprintf(grid, sizeof grid, "x_i = %.17g + i * %.17g (i = 0..%d), z_j = j * %.17g (j = 0..%d, rows from the bottom)",
                image.x_min, image.dx, image.width - 1, image.dz, image.height - 1);
  part.attributes["libbrdf:format"] = "blender-sigma-image";
  part.attributes["libbrdf:version"] = kVersion;
  part.attributes["libbrdf:grid"] = grid;
  part.attributes["libbrdf:value"] =
      "S(x, z) = ln Sigma(g, c) - ln(g/(1+g^2)) + z^2, g = e^x, c = (g+1) z^2 (exporters/include/exporters/blender.h); R = G = B";
  write_exr(path, {part});
}

std::string angular_cache_key(const std::vector<Model>& models, const std::string& table_request) {
  std::ostringstream key;
  key.precision(17);
  key << kVersion << " model " << model_name(models.front().kind()) << " table " << table_request;
  for (const Model& m : models) {
    const ModelParameters& p = m.parameters();
    key << " | lambda " << p.wavelength_um;
    if (p.index) key << " n " << p.index->n << " kappa " << p.index->kappa;
    // P~ = P / F: Qbar / F (mbk), 1 (bk, bk-modified) depend on the geometry and n only; mbk-fg's
    // G / S also on sigma_g (mapped from sigma_s and l_c unless given) and the G term.
    if (model_traits(m.kind()).reads(libbrdf::kSigmaG)) key << " sigma_g " << m.sigma_g() << " g_term " << static_cast<int>(p.g_term);
  }
  return key.str();
}

std::string angular_file_name(const std::string& key) { return "libbrdf_angular_" + hex16(fnv1a(key)) + ".exr"; }

std::vector<float> side_row_texels(const std::vector<Model>& models) {
  if (models.size() != 1 && models.size() != 3)
    throw InvalidArgument("wavelength", "Blender materials take 1 or 3 wavelengths (R,G,B; got " +
                                            std::to_string(models.size()) + ")");
  const int m = kThetaINodes;
  std::vector<float> texels(static_cast<std::size_t>(m) * kSideRows * 3);
  tbb::parallel_for(0, 3, [&](int rgb) {
    const Model& model = models[models.size() == 1 ? 0 : rgb];
    for (int j = 0; j < m; ++j) {
      const std::array<double, kSideRows> row = side_node(model, j);
      for (int r = 0; r < kSideRows; ++r) texels[(static_cast<std::size_t>(r) * m + j) * 3 + rgb] = static_cast<float>(row[r]);
    }
  });
  return texels;
}

void write_side_rows_exr(const std::vector<Model>& models, const std::string& path) {
  ExrPart part = bottom_up_exr_part(kThetaINodes, kSideRows, side_row_texels(models));
  part.attributes["libbrdf:format"] = "blender-side-rows";
  part.attributes["libbrdf:version"] = kVersion;
  part.attributes["libbrdf:rows"] = "y = 0 R_spec(theta_i), y = 1 K(theta_i), y = 2 F(theta_d) (rows from the bottom), theta = 90 deg x/" +
                                    std::to_string(kThetaINodes - 1);
  write_exr(path, {part});
}

Lut kernel_lut_from_angular_atlas(const std::string& angular_path, const std::vector<Model>& models) {
  const std::vector<ExrPart> parts = read_exr(angular_path);
  const auto attribute = [&](const char* key) {
    const auto found = parts.front().attributes.find(key);
    return found == parts.front().attributes.end() ? std::string() : found->second;
  };
  std::array<int, 3> shape{0, 0, 0};
  const bool tagged = parts.size() == 1 && attribute("libbrdf:format") == "blender-angular-atlas" &&
                      std::sscanf(attribute("libbrdf:shape").c_str(), "%dx%dx%d", &shape[0], &shape[1], &shape[2]) == 3 &&
                      std::min({shape[0], shape[1], shape[2]}) >= 2;
  const BlenderAtlas a = tagged ? blender_atlas_layout(shape, 0) : BlenderAtlas{};
  if (!tagged || parts[0].width != a.width || parts[0].height != a.height || parts[0].channel_names.size() != 3)
    throw LutFileError(angular_path + ": not a libbrdf angular atlas (blender.h)");
  Lut lut;
  lut.layout = LutLayout::kernel;
  lut.shape = shape;
  lut.kernel_model = models.front().kind();
  for (const Model& m : models) {
    lut.wavelengths_um.push_back(m.parameters().wavelength_um);
    lut.kernel_sigma_over_lambda.push_back(m.surface().sigma_over_lambda());
    lut.kernel_lc_over_lambda.push_back(m.surface().lc_over_lambda());
    lut.kernel_index.push_back(m.parameters().index.value());
    std::vector<float> spec(kThetaINodes), k(kThetaINodes);
    for (int j = 0; j < kThetaINodes; ++j) {
      const std::array<double, kSideRows> row = side_node(m, j);
      spec[j] = static_cast<float>(row[0]);
      k[j] = static_cast<float>(row[1]);
    }
    lut.specular_reflectance.push_back(std::move(spec));
    lut.renormalization.push_back(std::move(k));
  }
  const std::size_t per_channel = lut.nodes_per_channel();
  lut.values.resize(per_channel * models.size());
  const std::vector<float>& pixels = parts[0].pixels;  // rows from the top, channels as stored (by name)
  std::array<std::size_t, 3> position{};
  for (int rgb = 0; rgb < 3; ++rgb) {
    const auto& names = parts[0].channel_names;
    const auto found = std::find(names.begin(), names.end(), std::string(1, "RGB"[rgb]));
    if (found == names.end()) throw LutFileError(angular_path + ": no channel " + std::string(1, "RGB"[rgb]));
    position[rgb] = static_cast<std::size_t>(found - names.begin());
  }
  for (std::size_t c = 0; c < models.size(); ++c)
    for (int i0 = 0; i0 < shape[0]; ++i0)
      for (int i1 = 0; i1 < shape[1]; ++i1)
        for (int k = 0; k < shape[2]; ++k) {
          const auto [x, y] = node_texel(a, i0, i1, k);
          const std::size_t texel = static_cast<std::size_t>(a.height - 1 - y) * a.width + x;
          lut.values[c * per_channel + (static_cast<std::size_t>(i0) * shape[1] + i1) * shape[2] + k] =
              pixels[texel * 3 + position[models.size() == 1 ? 0 : c]];
        }
  return lut;
}

std::array<KernelChannel, 3> kernel_channels(const std::vector<ModelParameters>& channels) {
  std::array<KernelChannel, 3> out;
  for (int rgb = 0; rgb < 3; ++rgb) {
    const ModelParameters& p = channels.at(channels.size() == 1 ? 0 : rgb);
    const double s = p.sigma_s_um.value_or(0.0) / p.wavelength_um, l = p.lc_um.value_or(0.0) / p.wavelength_um;
    out[rgb].g_scale = (2.0 * kPi * s) * (2.0 * kPi * s);  // eq. 12 over (N.L + N.V)^2
    out[rgb].c_scale = kPi * kPi * l * l;                 // c over eta_r^2
    out[rgb].prefactor = kPi * l * l;                     // pi l_c^2 / lambda^2 of eq. 11
  }
  return out;
}

std::string kernel_closed_form_name(ModelKind kind) {
  switch (model_traits(kind).closed_angular) {
    case ClosedAngularForm::none: return "none";
    case ClosedAngularForm::bk_eq26: return "bk_eq27";  // the shader's name (F_bk^2 of eq. 26, eq. 27's form)
    case ClosedAngularForm::bk_modified_eq28: return "bk_modified_eq28";
  }
  return "none";
}

SpikeFit spike_fit(ModelKind kind, const std::vector<ModelParameters>& channels) {
  SpikeFit spike;
  for (const ModelParameters& p : channels) {
    if (!p.index) throw InvalidArgument("n", "the specular spike needs the complex index (--n/--k or --material)");
    spike.f0.push_back(fresnel_reflectance(p.index->permittivity(), 1.0));
    spike.g0.push_back(p.sigma_s_um ? roughness_g(*p.sigma_s_um / p.wavelength_um, 1.0, 1.0) : 0.0);
  }
  spike.has_spike = Model(kind, channels.front()).specular_reflectance(0.0) > 0.0;
  return spike;
}

std::string blender_description_json(const BlenderExport& e) {
  using nlohmann::json;
  json d;
  d["format"] = "libbrdf-blender-material";
  d["format_version"] = 1;
  d["libbrdf_version"] = kVersion;
  d["name"] = e.name;
  d["mode"] = e.mode;
  d["model"] = std::string(model_name(e.model));
  json wavelengths = json::array();
  for (const ModelParameters& p : e.channels) wavelengths.push_back(p.wavelength_um);
  d["wavelengths_um"] = wavelengths;
  d["rgb_channels"] = "R, G, B = wavelengths_um[0, 1, 2] (one wavelength: grey)";
  d["conventions"] = "angles from the normal; BRDF in 1/sr; radiance = BRDF * cos(theta_i) * sun strength * sun colour";

  json channels = json::array();  // what every channel was exported with (tests evaluate the model from it)
  for (const ModelParameters& p : e.channels) {
    json c = {{"wavelength_um", p.wavelength_um}, {"k_mode", p.k_mode == KMode::tis ? "tis" : "plane"}};
    c["sigma_s_um"] = p.sigma_s_um ? json(*p.sigma_s_um) : json(nullptr);
    c["lc_um"] = p.lc_um ? json(*p.lc_um) : json(nullptr);
    c["n"] = p.index ? json(p.index->n) : json(nullptr);
    c["kappa"] = p.index ? json(p.index->kappa) : json(nullptr);
    channels.push_back(c);
  }
  d["channels"] = channels;

  if (e.lut) {
    json lut;
    lut["error"] = {{"max_relative", e.lut->error.max_relative},
                    {"rms_relative", e.lut->error.rms_relative},
                    {"floor", e.lut->error.floor},
                    {"samples", e.lut->error.samples},
                    {"measure", "the table's C++ lookup (Sigma exact) against the model at random off-grid geometries, both "
                                "polar angles <= 85 deg, values below the floor ignored"}};
    if (e.kernel) {
      const KernelFiles& k = *e.kernel;
      const BlenderAtlas& a = k.angular;
      lut["layout"] = "kernel";
      lut["formula"] = "f = K(theta_i) F(theta_d) P~(theta_h, theta_d, phi_d) C prefactor Sigma(g, c); g = g_scale (N.L + N.V)^2, "
                       "c = c_scale |N x (L + V)|^2 (exporters/include/exporters/blender.h)";
      lut["file"] = k.side_file;
      lut["side"] = {{"file", k.side_file},
                     {"width", kThetaINodes},
                     {"height", kSideRows},
                     {"rows", {{"r_spec", 0}, {"k", 1}, {"fresnel", 2}}},
                     {"formula", "theta = (pi/2) j/(M-1), M = width; R_spec and K over theta_i, F over theta_d; linear"}};
      lut["angular"] = {{"file", k.angular_file},
                        {"width", a.width},
                        {"height", a.height},
                        {"columns", a.columns},
                        {"tile_rows", a.tile_rows},
                        {"origin", "bottom-left"},
                        {"texel", atlas_layout_text(a)},
                        {"theta_h", {{"nodes", a.shape[0]}, {"map", "uniform"}, {"formula", "theta_h = (pi/2) i/(N-1)"}}},
                        {"theta_d", {{"nodes", a.shape[1]}, {"map", "linear"}, {"formula", "theta_d = (pi/2) i/(N-1)"}}},
                        {"phi_d", {{"nodes", a.shape[2]}, {"map", "linear"}, {"formula", "phi_d = pi i/(N-1)"},
                                   {"cos_phi_d", "(cos theta_h cos theta_d - N.L) / (sin theta_h sin theta_d)"}}},
                        {"reused", k.angular_reused}};
      lut["sigma"] = {{"file", k.sigma_file},
                      {"width", k.sigma.width},
                      {"height", k.sigma.height},
                      {"x_min", k.sigma.x_min},
                      {"dx", k.sigma.dx},
                      {"dz", k.sigma.dz},
                      {"origin", "bottom-left"},
                      {"value", "S(x, z) = ln Sigma - ln(g/(1+g^2)) + z^2 at x = x_min + i dx (column i), z = j dz (row j); "
                                "ln Sigma = S(clamp(x), min(z, z_max)) + x - ln(1+g^2) - z^2, x = ln g, z^2 = c/(g+1); bilinear"},
                      {"reused", k.sigma_reused}};
      json per_channel = json::array();
      for (const KernelChannel& c : kernel_channels(e.channels))
        per_channel.push_back({{"g_scale", c.g_scale}, {"c_scale", c.c_scale}, {"prefactor", c.prefactor}});
      lut["kernel_channels"] = per_channel;
      lut["closed_form"] = kernel_closed_form_name(e.model);
    } else {
      const BlenderAtlas& a = e.atlas;
      lut["layout"] = "rusinkiewicz";
      lut["file"] = e.atlas_file;
      lut["width"] = a.width;
      lut["height"] = a.height;
      lut["columns"] = a.columns;
      lut["tile_rows"] = a.tile_rows;
      lut["origin"] = "bottom-left";
      lut["texel"] = atlas_layout_text(a);
      lut["theta_h"] = {{"nodes", a.shape[0]}, {"map", "square"}, {"formula", "theta_h = (pi/2) (i/(N-1))^2"}};
      lut["theta_d"] = {{"nodes", a.shape[1]}, {"map", "linear"}, {"formula", "theta_d = (pi/2) i/(N-1)"}};
      lut["phi_d"] = {{"nodes", a.shape[2]},
                      {"map", "linear"},
                      {"formula", "phi_d = pi i/(N-1)"},
                      {"cos_phi_d", "(cos theta_h cos theta_d - N.L) / (sin theta_h sin theta_d)"}};
      lut["specular"] = {{"row", a.specular_row}, {"nodes", a.specular_nodes}, {"formula", "theta = (pi/2) j/(M-1)"}};
      json attributes = json::object();
      for (const auto& [key, value] : e.lut->attributes) attributes[key] = value;
      lut["attributes"] = attributes;
    }
    d["lut"] = lut;
  }
  if (!e.osl_file.empty()) d["osl"] = {{"file", e.osl_file}, {"shader", e.osl_shader_name}};
  {  // energy (issue 11): the exported model's directional albedo, spike included
    const ::exporters::EnergySummary energy = ::exporters::energy_summary(e.model, e.channels);
    d["albedo"] = {{"theta_i_deg", energy.theta_i_deg}, {"per_channel", energy.albedo}, {"max", energy.max_albedo},
                   {"k_mode", energy.k_mode}, {"other_k_mode_max", energy.other_k_mode_max_albedo},
                   {"advice", energy.advice}};
  }

  const SpikeFit& spike = e.spike;
  json fit = {{"f0", spike.f0},
              {"g0", spike.g0},
              {"has_spike", spike.has_spike},
              {"rho_d", e.channels.empty() ? 0.0 : e.channels.front().rho_d},
              {"spike", "(f0 + (1 - f0) (1 - cos theta_v)^5) exp(-g0 cos^2 theta_v): R_spec with Schlick's F from the exact F(0)"}};
  if (e.lobes) fit.update(lobes_json(*e.lobes));
  if (e.lobes_eevee) {
    fit["eevee"] = lobes_json(*e.lobes_eevee);
    fit["eevee"]["excluded_roughness"] = {kEeveeGgxBandLow, kEeveeGgxBandHigh};  // blender.h
  }
  d["fit"] = fit;
  return d.dump(2) + "\n";
}


}  // namespace libbrdf::blender
