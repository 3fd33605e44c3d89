// Writing NAME.inc: POV-Ray include idioms as in POV-Ray's own metals.inc (a version guard against
// double inclusion, a File/Description header, a Source line per data block, prefixed names).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "libbrdf/image_file.h"
#include "exporters/energy.h"
#include "exporters/povray.h"
#include "libbrdf/error.h"
#include "libbrdf/version.h"

namespace libbrdf::povray {

namespace {

std::string number(double value, int digits = 9) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

std::string vector3(const std::array<double, 3>& v, int digits = 9) {
  return "<" + number(v[0], digits) + ", " + number(v[1], digits) + ", " + number(v[2], digits) + ">";
}

// A per-channel vector as POV-Ray rgb (the last channel repeats when there are fewer than 3).
std::array<double, 3> rgb_of(const std::vector<double>& channels) {
  std::array<double, 3> rgb{};
  for (std::size_t k = 0; k < 3 && !channels.empty(); ++k) rgb[k] = channels[std::min(k, channels.size() - 1)];
  return rgb;
}

std::string percent(double fraction) { return number(100.0 * fraction, 3) + "%"; }

std::string describe_channel(const ModelParameters& p) {
  std::ostringstream out;
  out << "lambda = " << number(p.wavelength_um, 6) << " um";
  if (p.sigma_s_um) out << ", sigma_s = " << number(*p.sigma_s_um, 6) << " um";
  if (p.lc_um) out << ", l_c = " << number(*p.lc_um, 6) << " um";
  if (p.index) out << ", n = " << number(p.index->n, 6) << ", kappa = " << number(p.index->kappa, 6);
  if (p.sigma_g) out << ", sigma_g = " << number(*p.sigma_g, 6);
  if (p.rho_s) out << ", rho_s = " << number(*p.rho_s, 6);
  if (p.rho_d != 0.0) out << ", rho_d = " << number(p.rho_d, 6);
  return out.str();
}

// NAME_Fit_Lobe_j textures and NAME_Fit (povray.h, FinishFit). Pigments: the lobe colour at
// kColourNodes slope values over N.V in [0, 1] (s = 1/2 + asin(N.V)/pi), linear in between.
std::string fit_textures(const std::string& N, const FinishFit& fit) {
  constexpr int kColourNodes = fit::kViewNodes;
  const std::vector<fit::Lobe>& lobes = fit.lobes.lobes;
  const double count = static_cast<double>(std::max<std::size_t>(lobes.size(), 1));
  std::ostringstream out;
  const std::string reflection = "reflection { rgb " + vector3(fit.reflection_min) + ", rgb " + vector3(fit.reflection_max) +
                                 " falloff " + number(fit.reflection_falloff) + " }";
  for (std::size_t j = 0; j < lobes.size(); ++j) {
    const fit::Lobe& l = lobes[j];
    const std::string lobe = N + "_Fit_Lobe_" + std::to_string(j + 1);
    out << "#declare " << lobe << "_Pigment = pigment { slope { " << N << "_View_Direction } color_map {";
    for (int i = 0; i < kColourNodes; ++i) {
      const double slope = 0.5 + 0.5 * i / (kColourNodes - 1);
      const double mu = fit::view_node_cosine(i);
      std::array<double, 3> rgb{};
      for (int c = 0; c < 3; ++c) rgb[static_cast<std::size_t>(c)] = fit::lobe_colour(l, c, mu);
      if (i == 0) out << " [0 rgb " << vector3(rgb, 7) << "]";
      out << " [" << number(slope, 9) << " rgb " << vector3(rgb, 7) << "]";
    }
    out << " } }\n";
    // The average divides by the lobe count: each lobe's S is multiplied by it.
    auto finish = [&](double exponent) {
      return "finish { ambient 0 emission 0 diffuse 0 " +
             (l.phong ? "phong " + number(count * l.specular) + " phong_size " + number(exponent)
                      : "specular " + number(count * l.specular) + " roughness " + number(1.0 / exponent)) +
             " metallic 1 " + reflection + " }";
    };
    if (l.roughness_slope == 0.0) {
      out << "#declare " << lobe << " = texture { pigment { " << lobe << "_Pigment } " << finish(l.roughness) << " }\n";
      continue;
    }
    // The exponent follows N.V (fit.h, blinn_exponent_at_node): one texture per view node, blended
    // linearly in the slope value.
    out << "#declare " << lobe << " = texture { slope { " << N << "_View_Direction } texture_map {\n";
    for (int i = 0; i < kColourNodes; ++i) {
      const double slope = 0.5 + 0.5 * i / (kColourNodes - 1);
      const std::string entry = "pigment { " + lobe + "_Pigment } " + finish(fit::blinn_exponent_at_node(l, i));
      if (i == 0) out << "  [0 " << entry << "]\n";
      out << "  [" << number(slope, 9) << " " << entry << "]\n";
    }
    out << "} }\n";
  }
  if (lobes.empty()) {
    out << "#declare " << N << "_Fit = texture { pigment { rgb 0 } finish { ambient 0 emission 0 diffuse 0 " << reflection
        << " } }\n";
  } else if (lobes.size() == 1) {
    out << "#declare " << N << "_Fit = texture { " << N << "_Fit_Lobe_1 }\n";
  } else {
    out << "#declare " << N << "_Fit = texture { average texture_map {";
    for (std::size_t j = 0; j < lobes.size(); ++j) out << " [1 " << N << "_Fit_Lobe_" << j + 1 << "]";
    out << " } }\n";
  }
  return out.str();
}

// The header's lines of the fit's error per band of sun-camera angle (fit.h, kSunAngleBands).
std::string sun_angle_lines(const fit::NativeFit& lobes) {
  std::ostringstream out;
  out << "//   Error by the angle between the light and the camera (a light in a band whose median exceeds 5% or p95\n"
      << "//   20% renders that error, not the target):\n";
  for (const fit::SunAngleQuality& b : lobes.by_sun_angle)
    out << "//     " << number(b.from_deg, 3) << "-" << number(b.to_deg, 3) << " deg: median " << percent(b.quality.median)
        << ", p95 " << percent(b.quality.p95) << "\n";
  return out.str();
}

// NAME_Fit_Sun_Angle_Deg (band edges) and NAME_Fit_Error_Median_By_Angle / _P95_By_Angle (one per band).
std::string sun_angle_declarations(const std::string& N, const fit::NativeFit& lobes) {
  if (lobes.by_sun_angle.empty()) return "";
  std::ostringstream edges, medians, p95s;
  edges << number(lobes.by_sun_angle.front().from_deg, 6);
  for (std::size_t b = 0; b < lobes.by_sun_angle.size(); ++b) {
    const fit::SunAngleQuality& q = lobes.by_sun_angle[b];
    edges << ", " << number(q.to_deg, 6);
    medians << (b ? ", " : "") << number(q.quality.median, 6);
    p95s << (b ? ", " : "") << number(q.quality.p95, 6);
  }
  const std::size_t bands = lobes.by_sun_angle.size();
  std::ostringstream out;
  out << "// Per band of light-camera angle: edges (deg), then the median and p95 error in each band.\n"
      << "#declare " << N << "_Fit_Sun_Angle_Deg = array[" << bands + 1 << "] {" << edges.str() << "};\n"
      << "#declare " << N << "_Fit_Error_Median_By_Angle = array[" << bands << "] {" << medians.str() << "};\n"
      << "#declare " << N << "_Fit_Error_P95_By_Angle = array[" << bands << "] {" << p95s.str() << "};\n";
  return out.str();
}

}  // namespace

void validate_include_name(const std::string& name) {
  bool ok = !name.empty() && name.size() <= 24 && std::isalpha(static_cast<unsigned char>(name[0]));
  for (char c : name) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
  if (!ok)
    throw InvalidArgument("name", "must be a POV-Ray identifier prefix: a letter, then letters, digits or '_', "
                                  "1 to 24 characters (got '" + name + "')");
}

std::string include_text(const std::string& name, ModelKind model, const std::vector<ModelParameters>& channels,
                         const HalfVectorSlice& slice, const FinishFit& fit) {
  const SliceGeometry& g = slice.geometry;
  const std::string N = name;
  const char* channel_names[] = {"R", "G", "B"};
  std::ostringstream out;
  out << "// File: " << N << ".inc\n"
      << "// Description: libbrdf BRDF '" << model_name(model) << "' for POV-Ray 3.7, as two textures:\n"
      << "//   " << N << "_Exact  radiance L = f_r cos(theta_i) " << N << "_Irradiance as emission, exact (up to the\n"
      << "//              table error below) for ONE parallel light along " << N << "_Light_Direction and an\n"
      << "//              orthographic or distant camera along " << N << "_View_Direction, on any object.\n"
      << "//              No light_source is involved; the specular spike (a delta) is not drawn.\n"
      << "//   " << N << "_Fit    a native finish fitted to the same BRDF, for scenes with any lights: each\n"
      << "//              light_source's colour is its irradiance, as " << N << "_Irradiance is for " << N
      << "_Exact.\n"
      << "// Generated by `brdf export povray` (libbrdf " << kVersion << "); regenerate rather than edit.\n"
      << "// Source: Butler, Nauyoks & Marciniak, Opt. Express 23, 29100 (2015); libbrdf conventions\n"
      << "//   (theta from the normal, phi_s = 180 deg forward, unpolarized Qbar).\n";
  for (std::size_t k = 0; k < channels.size(); ++k)
    out << "//   " << (k < 3 ? channel_names[k] : "?") << ": " << describe_channel(channels[k]) << "\n";
  {  // energy (issue 11): the model's directional albedo, spike included (libbrdf/albedo.h)
    const ::exporters::EnergySummary energy = ::exporters::energy_summary(model, channels);
    out << "// Directional albedo (white furnace, spike included) at theta_i =";
    for (double t : energy.theta_i_deg) out << " " << t;
    out << " deg:\n";
    for (std::size_t k = 0; k < energy.albedo.size(); ++k) {
      out << "//   " << (k < 3 ? channel_names[k] : "?") << ":";
      for (double a : energy.albedo[k]) out << " " << a;
      out << "\n";
    }
    out << "//   " << energy.advice << "\n";
    out << "#declare " << N << "_Albedo_Max = " << energy.max_albedo << ";\n";
  }
  // The usage lines are a complete scene (tests/povray/test_include_usage.py renders them verbatim).
  // The camera sits on the view side (+View_Direction, which points from the surface towards it);
  // a vertical view needs another sky than POV-Ray's default y; look_at comes last, as POV-Ray asks.
  const std::string sky = std::abs(g.view[1]) > 0.999 ? " sky z" : "";
  out << "//\n"
      << "// Usage (a complete scene: uncomment the lines below):\n"
      << "//   #declare " << N << "_Irradiance = 1;  // optional, before the include (float or rgb)\n"
      << "//   #include \"" << N << ".inc\"\n"
      << "//   camera { orthographic location 100*" << N << "_View_Direction right 2.4*x*image_width/image_height up 2.4*y"
      << sky << " look_at 0 }\n"
      << "//   sphere { 0, 1 texture { " << N << "_Exact } }\n"
      << "// Or, for " << N << "_Fit (any lights, shadows, reflections), replace the sphere line by:\n"
      << "//   light_source { 1e6*" << N << "_Light_Direction rgb " << N << "_Irradiance parallel point_at 0 }\n"
      << "//   sphere { 0, 1 texture { " << N << "_Fit } }\n"
      << "//\n"
      << "// Directions are POV-Ray world vectors (left-handed, y up) from the surface towards the light\n"
      << "// and towards the camera; theta_i = angle(N, light), theta_s = angle(N, view), and phi_s follows\n"
      << "// from eq. 5 (cos 2theta_d = light . view), so handedness does not matter. The slope patterns\n"
      << "// below stay in world space when the object is moved, rotated or scaled.\n"
      << "//\n"
      << "// " << N << "_Exact table: R = f_r cos(theta_i) [1/sr] on " << slice.half_nodes.size() << " x "
      << slice.light_nodes.size() << " nodes over\n"
      << "//   (N.H, N.L), H = half vector. Outer map: slope { " << N << "_Half_Vector } (nodes dense at the\n"
      << "//   specular peak N = H); inner maps: slope { " << N << "_Light_Direction } (N.L = 0 is a node, so the\n"
      << "//   terminator is exact). Map positions are slope values 1/2 + asin(N.d)/pi; POV-Ray interpolates\n"
      << "//   linearly between them. Peak radiance per unit irradiance (N = H): " << vector3(rgb_of(slice.peak), 6)
      << ".\n"
      << "//   Measured error against the model at random normals (" << slice.error.samples
      << " values above " << number(slice.error.floor, 3) << " 1/sr,\n"
      << "//   theta_i, theta_s <= " << number(slice.error.theta_limit_deg, 3) << " deg): "
      << (slice.error.samples > 0
              ? "max " + percent(slice.error.max_relative) + ", rms " + percent(slice.error.rms_relative)
              : std::string("n/a (no such normal is lit and seen)"))
      << "; up to the horizon (silhouettes) max " << percent(slice.error.max_relative_all) << ".\n"
      << "// " << N << "_Fit: " << fit.lobes.lobes.size() << " Blinn or Phong lobe(s) (specular or phong, metallic 1, pigment following N.V through\n"
      << "//   slope { " << N << "_View_Direction }) averaged by a texture_map, + reflection fitted to R_spec = F exp(-g); a lobe's\n"
      << "//   exponent follows N.V too (a texture_map over the same slope: a polished lobe narrows as 1/cos(theta_d)).\n"
      << "//   Measured per pixel and channel against the exact radiance f_r cos(theta_i) on orthographic spheres lit\n"
      << "//   by one sun at two angles from the camera in each band below (theta_i, theta_s <= 70 deg, values above 1%\n"
      << "//   of the maximum), all bands: median " << percent(fit.lobes.quality.median) << ", p95 "
      << percent(fit.lobes.quality.p95) << ", max " << percent(fit.lobes.quality.max) << " (target p95 "
      << percent(fit.lobes.target_error) << (fit.lobes.target_met ? "" : ", not met") << "); peak (N = H) fit/exact "
      << vector3(fit.peak_ratio, 3) << "; reflection rms " << number(fit.reflection_rms_error, 3) << ".\n"
      << sun_angle_lines(fit.lobes)
      << "\n"
      << "#ifndef(" << N << "_Inc_Temp)\n"
      << "#declare " << N << "_Inc_Temp = version;\n"
      << "#version 3.7;\n"
      << "\n"
      << "#ifndef(" << N << "_Irradiance) #declare " << N << "_Irradiance = 1; #end\n"
      << "#declare " << N << "_Light_Direction = " << vector3(g.light, 12) << ";\n"
      << "#declare " << N << "_View_Direction = " << vector3(g.view, 12) << ";\n"
      << "#declare " << N << "_Half_Vector = " << vector3(g.half, 12) << ";\n"
      << "// f_r cos(theta_i) at N = H per unit irradiance, 1/sr (an exposure hint).\n"
      << "#declare " << N << "_Peak_Radiance = " << vector3(rgb_of(slice.peak)) << ";\n"
      << "\n"
      << "// Source: libbrdf model '" << model_name(model) << "', channels as listed in the header.\n"
      << "#declare " << N << "_Radiance_Pigment = pigment {\n"
      << "  slope { " << N << "_Half_Vector }\n"
      << "  pigment_map {\n";
  const int nc = slice.channels();
  for (std::size_t i = 0; i < slice.half_nodes.size(); ++i) {
    out << "    [" << number(slice.half_slopes[i], 12) << " slope { " << N << "_Light_Direction } color_map {";
    for (std::size_t j = 0; j < slice.light_nodes.size(); ++j) {
      std::array<double, 3> rgb{};
      for (int k = 0; k < 3; ++k) rgb[static_cast<std::size_t>(k)] = slice.value(std::min(k, nc - 1), i, j);
      out << " [" << number(slice.light_slopes[j], 12) << " rgb " << vector3(rgb, 7) << "]";
    }
    out << " }]\n";
  }
  out << "  }\n"
      << "}\n"
      << "#declare " << N << "_Exact_Finish = finish { ambient 0 diffuse 0 specular 0 phong 0 reflection 0 emission "
      << N << "_Irradiance }\n"
      << "#declare " << N << "_Exact = texture { pigment { " << N << "_Radiance_Pigment } finish { " << N
      << "_Exact_Finish } }\n"
      << "\n"
      << "// Source: least-squares fit of the same model (see header).\n"
      << "#declare " << N << "_Fit_Error_Median = " << number(fit.lobes.quality.median, 6) << ";\n"
      << "#declare " << N << "_Fit_Error_P95 = " << number(fit.lobes.quality.p95, 6) << ";\n"
      << sun_angle_declarations(N, fit.lobes)
      << fit_textures(N, fit)
      << "\n"
      << "#version " << N << "_Inc_Temp;\n"
      << "#end\n";
  return out.str();
}

ExportResult export_povray(const SliceRequest& request, const std::string& name, const std::string& directory) {
  validate_include_name(name);
  if (request.channels.size() != 3)
    throw InvalidArgument("wavelength", "POV-Ray colours need exactly 3 wavelengths for R,G,B (got " +
                                            std::to_string(request.channels.size()) + ")");
  ExportResult result;
  result.slice = bake_half_vector_slice(request);
  const std::vector<Model> models = channel_models(request.model, request.channels);
  result.fit = fit_finish(result.slice, models, request.fit_target_error);

  const std::string text = include_text(name, request.model, request.channels, result.slice, result.fit);
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec) throw std::runtime_error("cannot create directory '" + directory + "': " + ec.message());
  const fs::path path = fs::path(directory) / (name + ".inc");
  write_text_file_atomically(path.string(), text);
  result.include_path = path.string();
  return result;
}

}  // namespace libbrdf::povray
