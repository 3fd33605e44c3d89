#include "libbrdf/model_settings.h"

#include <initializer_list>
#include <sstream>
#include <utility>

#include "libbrdf/error.h"
#include "libbrdf/materials.h"

namespace libbrdf {
namespace {

template <class Enum>
Enum parse_choice(const std::string& text, const char* parameter, std::initializer_list<std::pair<const char*, Enum>> choices) {
  std::ostringstream names;
  for (const auto& [name, value] : choices) {
    if (text == name) return value;
    names << (names.tellp() > 0 ? "|" : "") << name;
  }
  throw InvalidArgument(parameter, "must be one of " + names.str() + " (got '" + message_excerpt(text) + "')");
}

// An option the model does not read is an error, never silently ignored (--rho-d with mbk).
void require_read(const ModelSettings& s, const ModelTraits& row) {
  const std::pair<ModelOption, bool> given[] = {{kRhoS, s.rho_s.has_value()}, {kRhoD, s.rho_d.has_value()},
                                                {kSigmaG, s.sigma_g.has_value()}, {kGTerm, s.g_term.has_value()},
                                                {kSigmaGMapping, s.sigma_g_mapping.has_value()}};
  for (const auto& [option, is_given] : given) {
    if (!is_given || row.reads(option)) continue;
    const std::string readers = model_names_where([option = option](const ModelTraits& r) { return r.reads(option); }, " or ");
    throw InvalidArgument(std::string(option_name(option)), "applies only to --model " + readers + " (got --model " + s.model + ")");
  }
}

}  // namespace

std::string_view option_name(ModelOption option) {
  switch (option) {
    case kNoOption: return "";
    case kRhoS: return "rho-s";
    case kRhoD: return "rho-d";
    case kSigmaG: return "sigma-g";
    case kGTerm: return "g-term";
    case kSigmaGMapping: return "sigma-g-mapping";
  }
  return "";
}

ModelParameters model_parameters(const ModelSettings& s, double wavelength_um) {
  require_positive("wavelength", wavelength_um, "um");
  ModelParameters p;
  p.sigma_s_um = s.sigma_s_um;
  p.lc_um = s.lc_um;
  p.wavelength_um = wavelength_um;
  if (!s.material.empty() && s.n) throw InvalidArgument("material", "give either --material or --n/--k, not both");
  if (!s.material.empty()) {
    p.index = material_index(s.material, wavelength_um);
  } else if (s.n) {
    p.index = ComplexIndex{*s.n, s.kappa.value_or(0.0)};
  } else if (s.kappa) {
    throw InvalidArgument("n", "required with --k");
  }
  require_read(s, model_traits(model_from_name(s.model)));
  p.sigma_g = s.sigma_g;
  p.rho_s = s.rho_s;
  p.rho_d = s.rho_d.value_or(0.0);
  p.g_term = parse_choice<GeometricTerm>(s.g_term.value_or("smith"), "g-term",
      {{"none", GeometricTerm::none}, {"smith", GeometricTerm::smith}, {"vgroove", GeometricTerm::vgroove}});
  p.k_mode = parse_choice<KMode>(s.k_mode, "k-mode", {{"plane", KMode::plane}, {"tis", KMode::tis}});
  p.sigma_g_mapping = parse_choice<SigmaGMapping>(s.sigma_g_mapping.value_or("auto"), "sigma-g-mapping",
      {{"auto", SigmaGMapping::automatic}, {"rough", SigmaGMapping::rough}, {"polished", SigmaGMapping::polished}});
  p.tolerance = s.tolerance;
  p.series.allow_kernel_table = parse_choice<bool>(s.asf_method, "asf-method", {{"auto", true}, {"series", false}});
  return p;
}

std::vector<ModelParameters> channel_parameters(const ModelSettings& s, const std::vector<double>& wavelengths_um) {
  if (wavelengths_um.empty()) throw InvalidArgument("wavelength", "at least one wavelength (um) is needed");
  for (double w : wavelengths_um) require_positive("wavelength", w, "um");
  std::vector<ModelParameters> channels;
  for (double w : wavelengths_um) channels.push_back(model_parameters(s, w));
  return channels;
}

}  // namespace libbrdf
