#pragma once
// A model named with its options as the front ends take them (the `brdf` options --model,
// --sigma-s, ..., the Python module's Model(name, sigma_s=..., ...) keywords), mapped onto
// ModelParameters in one place so that every option means the same everywhere. Which model reads
// which option is its row in model_registry.h.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "libbrdf/models.h"

namespace libbrdf {

struct ModelSettings {
  std::string model;  // a registry name (model_from_name)
  // Options only some models read are optional: given to another model, they are an error.
  std::optional<double> sigma_s_um, lc_um, n, kappa, sigma_g, rho_s, rho_d;
  std::string material;                        // built-in material (materials.h), or empty: n, kappa
  std::optional<std::string> g_term;           // none|smith|vgroove, default smith
  std::string k_mode = "plane";                // plane|tis
  std::optional<std::string> sigma_g_mapping;  // auto|rough|polished, default auto
  double tolerance = 1e-6;
  std::string asf_method = "auto";             // auto|series
};

// The option's name as the CLI spells it (the Python module writes '_' for '-'): "rho-s", ...
std::string_view option_name(ModelOption option);

// ModelParameters at one wavelength (um, > 0): the index from n/kappa or from the material at that
// wavelength. Throws InvalidArgument naming the option for a bad value, an unknown model or choice,
// or an option the model does not read ("rho-d: applies only to --model microfacet ...").
ModelParameters model_parameters(const ModelSettings& settings, double wavelength_um);
// One ModelParameters per channel, at the given wavelengths (um, each > 0; at least one).
std::vector<ModelParameters> channel_parameters(const ModelSettings& settings, const std::vector<double>& wavelengths_um);

}  // namespace libbrdf
