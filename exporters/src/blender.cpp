// Blender export: the atlas image, the spike parameters, the fitted lobes and the JSON description (blender.h).
#include "exporters/blender.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "exporters/energy.h"
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#include "libbrdf/error.h"
#include "libbrdf/fresnel.h"
#include "libbrdf/image_file.h"
#include "libbrdf/version.h"

namespace libbrdf::blender {

namespace {

int channel_of_rgb(const Lut& lut, int rgb) { return lut.channels() == 1 ? 0 : rgb; }

void require_blender_table(const Lut& lut) {
  if (lut.layout != LutLayout::rusinkiewicz)
    throw InvalidArgument("layout", "the Blender atlas packs a rusinkiewicz table (got " +
                                        std::string(layout_name(lut.layout)) + ")");
  if (lut.channels() != 1 && lut.channels() != 3)
    throw InvalidArgument("wavelength", "Blender materials take 1 or 3 wavelengths (R,G,B; got " +
                                            std::to_string(lut.channels()) + ")");
}

std::string atlas_layout_text(const BlenderAtlas& a) {
  std::ostringstream out;
  out << "tile k (phi_d index) at column k%" << a.columns << ", tile row k/" << a.columns << "; texel x = (k%"
      << a.columns << ")*" << a.shape[0] << " + i_theta_h, y = (k/" << a.columns << ")*" << a.shape[1]
      << " + i_theta_d, y counted from the bottom row; row y=" << a.specular_row << " holds R_spec at theta_i = 90 deg * x/"
      << (a.specular_nodes - 1) << "; node at texel centre ((x+0.5)/" << a.width << ", (y+0.5)/" << a.height
      << "); sample Closest and interpolate between nodes (trilinear)";
  return out.str();
}

// One fit's lobes and measured error (the description's "fit" / "fit.eevee").
nlohmann::json lobes_json(const fit::NativeFit& n) {
  using nlohmann::json;
  json lobes = json::array();
  for (const fit::Lobe& l : n.lobes) {
    json colour = json::array();
    for (int c = 0; c < 3; ++c) colour.push_back(l.colour[static_cast<std::size_t>(c)]);
    lobes.push_back({{"alpha", l.roughness}, {"roughness", std::sqrt(l.roughness)}, {"colour", colour}});
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
                ") per lobe, roughness = sqrt(alpha), added; radiance / E = C D G1 G1 / (4 N.V)";
  out["error"] = {{"median", n.quality.median},
                  {"p95", n.quality.p95},
                  {"max", n.quality.max},
                  {"values", n.quality.values},
                  {"lowest", n.quality.lowest},
                  {"target_p95", n.target_error},
                  {"target_met", n.target_met},
                  {"p95_by_lobe_count", tried},
                  {"measure", "per pixel and channel |fit - exact| / exact, exact = f_r cos(theta_i), on orthographic "
                              "spheres lit by one sun at 10, 40, 70, 100 deg from the camera; pixels with theta_i, "
                              "theta_s <= 70 deg and every channel above 1% of the scene's maximum; the lobes as Cycles "
                              "evaluates them; lowest = min fit / scene maximum"}};
  return out;
}

}  // namespace

BlenderAtlas blender_atlas_layout(const std::array<int, 3>& shape, int specular_nodes) {
  for (int n : shape)
    if (n < 2) throw InvalidArgument("resolution", "each axis needs at least 2 nodes for the Blender atlas");
  if (specular_nodes < 2) throw InvalidArgument("resolution", "the R_spec table needs at least 2 nodes");
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
  a.height = a.specular_row + 1;
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
          const std::size_t index = c * per_channel + (static_cast<std::size_t>(i0) * n1 + i1) * n2 + k;
          at((k % a.columns) * n0 + i0, (k / a.columns) * n1 + i1, rgb) = lut.values[index];
        }
    const std::vector<float>& spec = lut.specular_reflectance.at(c);
    if (static_cast<int>(spec.size()) != a.specular_nodes)
      throw std::logic_error("blender_atlas_texels: atlas made for another R_spec table");
    for (int j = 0; j < a.specular_nodes; ++j) at(j, a.specular_row, rgb) = spec[j];
  }
  return texels;
}

void write_blender_atlas_exr(const Lut& lut, const BlenderAtlas& a, const std::string& path) {
  const std::vector<float> texels = blender_atlas_texels(lut, a);
  ExrPart image{"", a.width, a.height, {"R", "G", "B"}, {}, {}};
  image.attributes["libbrdf:format"] = "blender-atlas";
  image.attributes["libbrdf:version"] = kVersion;
  image.attributes["libbrdf:layout"] = "rusinkiewicz";
  image.attributes["libbrdf:shape"] = std::to_string(a.shape[0]) + "x" + std::to_string(a.shape[1]) + "x" + std::to_string(a.shape[2]);
  image.attributes["libbrdf:atlas"] = atlas_layout_text(a);
  image.attributes["libbrdf:axis_mapping"] =
      "theta_h = (pi/2)(i0/(N0-1))^2, theta_d = (pi/2) i1/(N1-1), phi_d = pi k/(N2-1) (MERL's half-vector frame)";
  std::ostringstream wavelengths;
  for (int c = 0; c < lut.channels(); ++c) wavelengths << (c ? "," : "") << lut.wavelengths_um[c];
  image.attributes["libbrdf:wavelengths_um"] = wavelengths.str();
  image.attributes["libbrdf:units"] = "BRDF 1/sr; R_spec row dimensionless";
  for (const auto& [key, value] : lut.attributes) image.attributes["libbrdf:" + key] = value;
  // EXR scanlines run top to bottom; the atlas' rows count from the bottom.
  const std::size_t row = static_cast<std::size_t>(a.width) * 3;
  image.pixels.resize(texels.size());
  for (int y = 0; y < a.height; ++y)
    std::copy_n(texels.begin() + static_cast<std::ptrdiff_t>(row * (a.height - 1 - y)), row,
                image.pixels.begin() + static_cast<std::ptrdiff_t>(row * y));
  write_exr(path, {image});
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

  if (e.lut) {
    const BlenderAtlas& a = e.atlas;
    json lut;
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
    lut["error"] = {{"max_relative", e.lut->error.max_relative},
                    {"rms_relative", e.lut->error.rms_relative},
                    {"floor", e.lut->error.floor},
                    {"samples", e.lut->error.samples}};
    json attributes = json::object();
    for (const auto& [key, value] : e.lut->attributes) attributes[key] = value;
    lut["attributes"] = attributes;
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
  if (e.lobes_eevee) fit["eevee"] = lobes_json(*e.lobes_eevee);
  d["fit"] = fit;
  return d.dump(2) + "\n";
}

std::string osl_identifier(const std::string& text) {
  std::string id = "libbrdf_";
  for (char ch : text) id += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  return id;
}

}  // namespace libbrdf::blender
