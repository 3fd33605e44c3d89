// Metadata of baked tables (what every file header carries), consistency checks, and the
// temporary-file-then-rename write used by every writer.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "libbrdf/error.h"
#include "libbrdf/version.h"
#include "libbrdf/kernel_table.h"
#include "lut_internal.h"
#include "number_text.h"

namespace libbrdf::detail {
namespace {

std::string list_text(const std::vector<double>& values) {
  std::string out;
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? "," : "") + number_text(values[i]);
  return out;
}

// Parses "a,b,c" into finite numbers; empty optional on any malformed item.
bool parse_list(const std::string& text, std::vector<double>& out) {
  out.clear();
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != '\0' || !std::isfinite(v)) return false;
    out.push_back(v);
  }
  return !out.empty();
}

const char* g_term_name(GeometricTerm term) {
  switch (term) {
    case GeometricTerm::none: return "none";
    case GeometricTerm::smith: return "smith";
    case GeometricTerm::vgroove: return "vgroove";
  }
  return "?";
}

const char* mapping_name(SigmaGMapping mapping) {
  switch (mapping) {
    case SigmaGMapping::automatic: return "auto";
    case SigmaGMapping::rough: return "rough";
    case SigmaGMapping::polished: return "polished";
  }
  return "?";
}

}  // namespace

std::string axis_mapping_text(const Lut& lut) {
  const auto& s = lut.shape;
  std::ostringstream out;
  switch (lut.layout) {
    case LutLayout::kernel:
      out << "factored form f = K(theta_i) P (pi l_c^2/lambda^2) Sigma(g, c) (libbrdf/lut.h); the table is P on axis0 "
             "theta_h = (pi/2) i/" << s[0] - 1 << " (uniform), axis1 theta_d = (pi/2) j/" << s[1] - 1 << "; axis2 phi_d = pi k/"
          << s[2] - 1 << "; radians";
      break;
    case LutLayout::rusinkiewicz:
      out << "axis0 theta_h = (pi/2) (i/" << s[0] - 1 << ")^2, i = 0.." << s[0] - 1 << "; axis1 theta_d = (pi/2) j/"
          << s[1] - 1 << "; axis2 phi_d = pi k/" << s[2] - 1
          << " (azimuth of the incident direction in the half-vector frame, folded by phi_d -> -phi_d); radians";
      break;
    case LutLayout::merl:
      out << "axis0 theta_h = (pi/2) (i/90)^2, i = 0..89; axis1 theta_d = (pi/2) j/90; axis2 phi_d = pi k/180 "
             "(MERL: Matusik et al. 2003); radians";
      break;
    case LutLayout::slice: {
      const Direction l = normalized(lut.light), v = normalized(lut.view);
      out << "axis0 theta_h = (pi/2) (i/" << s[0] - 1 << ")^2; axis1 phi_d = pi j/" << s[1] - 1
          << "; theta_d fixed = " << number_text(slice_theta_d(lut.light, lut.view))
          << " (cos 2 theta_d = L.V, eq. 5); world light L = (" << number_text(l.x) << "," << number_text(l.y) << ","
          << number_text(l.z) << "), view V = (" << number_text(v.x) << "," << number_text(v.y) << "," << number_text(v.z)
          << "); from a normal N: cos theta_h = (N.L + N.V) / (2 cos theta_d), cos phi_d = (N.V - N.L) / (2 sin theta_h "
             "sin theta_d); radians";
      break;
    }
  }
  out << ". Side tables: R_spec(theta_i) and K(theta_i) at theta_i = (pi/2) m/" << kThetaINodes - 1 << ".";
  return out.str();
}

std::string texel_convention_text(LutLayout layout) {
  std::string text =
      "node grid: value [i] is the BRDF (1/sr) AT the node angle above (not a cell average, no half-texel offset: "
      "index = angle mapped to [0, span]); interpolation ";
  text += layout == LutLayout::slice ? "bilinear" : "trilinear";
  text += layout == LutLayout::merl ? "; beyond the last node (theta_h, theta_d near 90 deg, phi_d near 180 deg) the "
                                      "last node's value holds"
                                    : "; first and last nodes on the range ends";
  text += "; nodes with a direction at or below the horizon hold the model at polar angle " +
          number_text(kHorizonThetaLimitDeg) + " deg";
  return text;
}

void check_lut_consistency(const Lut& lut, const std::string& label) {
  auto fail = [&](const std::string& what) { throw LutFileError(label + ": " + what); };
  const int minimum = 2;
  const bool is_slice = lut.layout == LutLayout::slice;
  if (lut.shape[0] < minimum || lut.shape[1] < minimum || (is_slice ? lut.shape[2] != 1 : lut.shape[2] < minimum))
    fail("invalid shape " + std::to_string(lut.shape[0]) + "x" + std::to_string(lut.shape[1]) + "x" +
         std::to_string(lut.shape[2]) + " for layout " + std::string(layout_name(lut.layout)));
  if (lut.layout == LutLayout::merl && lut.shape != kMerlShape) fail("layout merl needs shape 90x90x180");
  if (lut.channels() < 1) fail("no channels");
  for (double w : lut.wavelengths_um)
    if (!(std::isfinite(w) && w > 0.0)) fail("invalid wavelength " + number_text(w));
  if (lut.nodes_per_channel() > (std::size_t{1} << 31)) fail("table too large");
  if (lut.values.size() != lut.nodes_per_channel() * lut.channels()) fail("value count does not match the shape");
  // A BRDF, R_spec and K are finite and >= 0: a negative value would be printed, interpolated and
  // rendered as negative reflectance.
  for (std::size_t i = 0; i < lut.values.size(); ++i)
    if (!(std::isfinite(lut.values[i]) && lut.values[i] >= 0.0f))
      fail("table value " + number_text(lut.values[i]) + " at channel " + std::to_string(i / std::max<std::size_t>(1, lut.nodes_per_channel())) +
           ", node " + std::to_string(i % std::max<std::size_t>(1, lut.nodes_per_channel())) + " is not a finite number >= 0");
  // The kernel layout's closed form evaluates all of P at lookup: its table holds P~ = 1 (lut.h),
  // which lookups do not interpolate.
  if (lut.layout == LutLayout::kernel && lut.kernel_angular == KernelAngular::closed_form)
    for (std::size_t i = 0; i < lut.values.size(); ++i)
      if (lut.values[i] != 1.0f) fail("a closed-form kernel table holds 1 at every node (got " + number_text(lut.values[i]) + ")");
  for (const auto* side : {&lut.specular_reflectance, &lut.renormalization}) {
    if (static_cast<int>(side->size()) != lut.channels()) fail("R_spec/K tables missing for some channels");
    for (const auto& table : *side) {
      if (table.size() < 2) fail("R_spec/K table too short");
      if (table.size() > (std::size_t{1} << 20)) fail("R_spec/K table too long");
      for (float v : table)
        if (!(std::isfinite(v) && v >= 0.0f)) fail("R_spec/K value " + number_text(v) + " is not a finite number >= 0");
    }
  }
  if (is_slice) {
    for (const Direction* d : {&lut.light, &lut.view}) {
      const double length2 = d->x * d->x + d->y * d->y + d->z * d->z;
      if (!(std::isfinite(length2) && length2 > 0.0)) fail("slice light/view direction is not a finite nonzero vector");
    }
  }
}

std::map<std::string, std::string> lut_metadata(const Lut& lut) {
  std::map<std::string, std::string> m = lut.attributes;
  m["format"] = "libbrdf-lut";
  m["format_version"] = "1";
  m["version"] = kVersion;
  m["layout"] = std::string(layout_name(lut.layout));
  m["shape"] = std::to_string(lut.shape[0]) + "," + std::to_string(lut.shape[1]) + "," + std::to_string(lut.shape[2]);
  m["channels"] = std::to_string(lut.channels());
  m["wavelengths_um"] = list_text(lut.wavelengths_um);
  m["axes"] = axis_mapping_text(lut);
  m["texel_convention"] = texel_convention_text(lut.layout);
  m["units"] = "BRDF values in 1/sr; R_spec and K dimensionless; wavelengths in um; angles as in axes";
  m["theta_i_nodes"] = std::to_string(lut.specular_reflectance.empty() ? 0 : lut.specular_reflectance[0].size());
  m["horizon_theta_limit_deg"] = number_text(kHorizonThetaLimitDeg);
  m["max_relative_error"] = number_text(lut.error.max_relative);
  m["rms_relative_error"] = number_text(lut.error.rms_relative);
  m["error_floor"] = number_text(lut.error.floor);
  m["error_samples"] = std::to_string(lut.error.samples);
  m["error_theta_limit_deg"] = number_text(lut.error.theta_limit_deg);
  m["max_relative_error_all"] = number_text(lut.error.max_relative_all);
  if (lut.layout == LutLayout::kernel) {
    m["kernel_sigma_over_lambda"] = list_text(lut.kernel_sigma_over_lambda);
    m["kernel_lc_over_lambda"] = list_text(lut.kernel_lc_over_lambda);
    std::vector<double> index;
    for (const ComplexIndex& n : lut.kernel_index) {
      index.push_back(n.n);
      index.push_back(n.kappa);
    }
    m["kernel_index"] = list_text(index);  // n0, kappa0, n1, kappa1, ...
    m["kernel_angular"] = lut.kernel_angular == KernelAngular::closed_form ? "closed-form" : "table";
    if (kernel_closed_form_reads_slopes(lut.kernel_model, lut.kernel_angular)) {
      m["kernel_sigma_g"] = list_text(lut.kernel_sigma_g);
      std::string terms;
      for (std::size_t c = 0; c < lut.kernel_g_term.size(); ++c) terms += (c ? "," : "") + std::string(g_term_name(lut.kernel_g_term[c]));
      m["kernel_g_term"] = terms;
    }
    // The tier lookups read (lut.h: kKernelLayoutSigmaTolerance; asf_auto's choice).
    const KernelTableSpec& tier = KernelTable::for_tolerance(kKernelLayoutSigmaTolerance)->spec();
    m["kernel_table"] = "Sigma(g, c) regenerated by libbrdf (kernel_table.h: ln g nodes 1/" +
                        std::to_string(tier.nodes_per_unit_x) + ", z = sqrt(c/(g+1)) nodes 1/" + std::to_string(tier.nodes_per_unit_z) +
                        " to z = " + number_text(kKernelZNear) + ", then ln z nodes 1/" + std::to_string(tier.nodes_per_unit_w) +
                        " to z = " + number_text(kKernelZFar) + ", 0 beyond; clamped bicubic spline of ln Sigma), certified relative error " +
                        number_text(tier.certified_error);
  }
  if (lut.layout == LutLayout::slice) {
    m["light_dir"] = list_text({lut.light.x, lut.light.y, lut.light.z});
    m["view_dir"] = list_text({lut.view.x, lut.view.y, lut.view.z});
  }
  return m;
}

void restore_from_metadata(Lut& lut, const std::map<std::string, std::string>& m, const std::string& label) {
  auto fail = [&](const std::string& what) { throw LutFileError(label + ": " + what); };
  auto get = [&](const char* key) -> const std::string& {
    auto it = m.find(key);
    if (it == m.end()) fail(std::string("missing header attribute '") + key + "'");
    return it->second;
  };
  auto numbers = [&](const char* key, std::size_t count) {
    std::vector<double> v;
    if (!parse_list(get(key), v) || (count && v.size() != count))
      fail(std::string("malformed header attribute '") + key + "' = '" + message_excerpt(get(key)) + "'");
    return v;
  };
  if (get("format") != "libbrdf-lut") fail("not a libbrdf table (format '" + message_excerpt(get("format")) + "')");
  if (get("format_version") != "1") fail("unsupported table format version '" + message_excerpt(get("format_version")) + "'");
  try {
    lut.layout = layout_from_name(get("layout"));
  } catch (const InvalidArgument&) {
    fail("unknown layout '" + message_excerpt(get("layout")) + "'");
  }
  const std::vector<double> shape = numbers("shape", 3);
  for (int k = 0; k < 3; ++k) {
    if (!(shape[k] >= 1 && shape[k] <= 1e8 && shape[k] == std::floor(shape[k]))) fail("malformed shape '" + message_excerpt(get("shape")) + "'");
    lut.shape[k] = static_cast<int>(shape[k]);
  }
  lut.wavelengths_um = numbers("wavelengths_um", 0);
  const std::vector<double> error = {numbers("max_relative_error", 1)[0], numbers("rms_relative_error", 1)[0],
                                     numbers("error_floor", 1)[0], numbers("error_samples", 1)[0]};
  lut.error = LutError{error[0], error[1], error[2], static_cast<int>(error[3]), numbers("error_theta_limit_deg", 1)[0],
                       numbers("max_relative_error_all", 1)[0]};
  if (lut.layout == LutLayout::kernel) {
    lut.kernel_sigma_over_lambda = numbers("kernel_sigma_over_lambda", lut.wavelengths_um.size());
    lut.kernel_lc_over_lambda = numbers("kernel_lc_over_lambda", lut.wavelengths_um.size());
    const std::vector<double> index = numbers("kernel_index", 2 * lut.wavelengths_um.size());
    lut.kernel_index.clear();
    try {
      lut.kernel_model = model_from_name(get("model"));
    } catch (const InvalidArgument&) {
      fail("unknown model '" + message_excerpt(get("model")) + "'");
    }
    if (!model_traits(lut.kernel_model).asf_based) fail("layout kernel holds an ASF model (" + asf_model_names() + ")");
    const auto angular = m.find("kernel_angular");  // absent in files before the closed form: table
    if (angular == m.end() || angular->second == "table") lut.kernel_angular = KernelAngular::table;
    else if (angular->second == "closed-form") lut.kernel_angular = KernelAngular::closed_form;
    else fail("kernel_angular must be 'table' or 'closed-form', got '" + message_excerpt(angular->second) + "'");
    lut.kernel_sigma_g.clear();
    lut.kernel_g_term.clear();
    if (kernel_closed_form_reads_slopes(lut.kernel_model, lut.kernel_angular)) {
      // G/S at lookup: sigma_g (0: a mirror, G = 1) and the G term per channel.
      lut.kernel_sigma_g = numbers("kernel_sigma_g", lut.wavelengths_um.size());
      for (double sigma_g : lut.kernel_sigma_g)
        if (!(sigma_g == 0.0 || (sigma_g >= kMinSigmaG && sigma_g <= kMaxSigmaG)))
          fail("kernel_sigma_g must be 0 (a mirror) or in [1e-7, 1e3] per channel");
      std::stringstream terms(get("kernel_g_term"));
      std::string term;
      while (std::getline(terms, term, ',')) {
        const GeometricTerm known[] = {GeometricTerm::none, GeometricTerm::smith, GeometricTerm::vgroove};
        const auto found = std::find_if(std::begin(known), std::end(known), [&](GeometricTerm t) { return term == g_term_name(t); });
        if (found == std::end(known)) fail("kernel_g_term holds an unknown G term '" + message_excerpt(term) + "' (none|smith|vgroove)");
        lut.kernel_g_term.push_back(*found);
      }
      if (lut.kernel_g_term.size() != lut.wavelengths_um.size()) fail("kernel_g_term must name one G term per channel");
    }
    for (std::size_t c = 0; c < lut.wavelengths_um.size(); ++c) {
      if (!(index[2 * c] > 0.0 && index[2 * c] <= 1e3 && index[2 * c + 1] >= 0.0 && index[2 * c + 1] <= 1e3))
        fail("kernel_index must hold n in (0, 1e3] and kappa in [0, 1e3] per channel");
      lut.kernel_index.push_back(ComplexIndex{index[2 * c], index[2 * c + 1]});
    }
    for (std::size_t c = 0; c < lut.kernel_lc_over_lambda.size(); ++c)
      if (!(lut.kernel_sigma_over_lambda[c] >= 0.0 && std::isfinite(lut.kernel_sigma_over_lambda[c]) &&
            lut.kernel_lc_over_lambda[c] > 0.0 && std::isfinite(lut.kernel_lc_over_lambda[c])))
        fail("kernel surface ratios must be finite, sigma_s/lambda >= 0 and l_c/lambda > 0");
  }
  if (lut.layout == LutLayout::slice) {
    const std::vector<double> l = numbers("light_dir", 3), v = numbers("view_dir", 3);
    lut.light = {l[0], l[1], l[2]};
    lut.view = {v[0], v[1], v[2]};
  }
  lut.attributes = m;
}

std::string parameters_json(ModelKind kind, const std::vector<ModelParameters>& channels) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const ModelParameters& p : channels) {
    nlohmann::ordered_json c;
    c["model"] = std::string(model_name(kind));
    c["wavelength_um"] = p.wavelength_um;
    if (p.sigma_s_um) c["sigma_s_um"] = *p.sigma_s_um;
    if (p.lc_um) c["lc_um"] = *p.lc_um;
    if (p.index) {
      c["n"] = p.index->n;
      c["kappa"] = p.index->kappa;
    }
    if (p.sigma_g) c["sigma_g"] = *p.sigma_g;
    if (p.rho_s) c["rho_s"] = *p.rho_s;
    c["rho_d"] = p.rho_d;
    c["g_term"] = g_term_name(p.g_term);
    c["sigma_g_mapping"] = mapping_name(p.sigma_g_mapping);
    c["k_mode"] = p.k_mode == KMode::plane ? "plane" : "tis";
    c["tolerance"] = p.tolerance;
    c["series_relative_tolerance"] = p.series.relative_tolerance;
    c["series_method"] = p.series.method == SeriesMethod::every_term ? "every_term" : "strided";
    out.push_back(c);
  }
  return out.dump();
}

}  // namespace libbrdf::detail
