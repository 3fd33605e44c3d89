#pragma once
// Built-in optical constants n + i kappa of common metals and dielectrics, from published
// tables (sources cited beside the data in src/material_table_data.inc).
#include <string>
#include <string_view>
#include <vector>

#include "libbrdf/fresnel.h"

namespace libbrdf {

struct MaterialInfo {
  std::string name;         // short name used on the command line, e.g. "Au"
  std::string description;  // e.g. "gold"
  std::string source;       // citation of the data
  double min_wavelength_um, max_wavelength_um;
};

// All built-in materials.
std::vector<MaterialInfo> builtin_materials();

// Complex index of a built-in material at a wavelength (um), linearly interpolated between the
// source's samples. Throws InvalidArgument naming "material" (unknown name, list given) or
// "wavelength" (outside the tabulated range, range given).
ComplexIndex material_index(std::string_view name, double wavelength_um);

}  // namespace libbrdf
