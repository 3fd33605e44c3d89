#include "libbrdf/materials.h"

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <sstream>
#include <strings.h>

#include "libbrdf/error.h"

namespace libbrdf {
namespace {

struct NkSample {
  double wavelength_um, n, kappa;
};
struct MaterialEntry {
  const char* name;
  const char* description;
  const NkSample* samples;
  std::size_t count;
  const char* source;
};

#include "material_table_data.inc"

const MaterialEntry& find_material(std::string_view name) {
  for (const MaterialEntry& entry : kMaterialTable) {
    if (name.size() == std::char_traits<char>::length(entry.name) &&
        strncasecmp(entry.name, name.data(), name.size()) == 0)
      return entry;
  }
  std::ostringstream known;
  for (const MaterialEntry& entry : kMaterialTable) known << (&entry == kMaterialTable ? "" : ", ") << entry.name;
  throw InvalidArgument("material", "unknown material '" + std::string(name) + "' (known: " + known.str() + ")");
}

}  // namespace

std::vector<MaterialInfo> builtin_materials() {
  std::vector<MaterialInfo> out;
  for (const MaterialEntry& entry : kMaterialTable)
    out.push_back({entry.name, entry.description, entry.source, entry.samples[0].wavelength_um,
                   entry.samples[entry.count - 1].wavelength_um});
  return out;
}

ComplexIndex material_index(std::string_view name, double wavelength_um) {
  const MaterialEntry& entry = find_material(name);
  const NkSample* first = entry.samples;
  const NkSample* last = entry.samples + entry.count;
  require_finite("wavelength", wavelength_um);
  if (wavelength_um < first->wavelength_um || wavelength_um > (last - 1)->wavelength_um) {
    std::ostringstream msg;
    msg << "must be within the tabulated range of " << entry.name << ", [" << first->wavelength_um << ", "
        << (last - 1)->wavelength_um << "] um (got ";
    msg.precision(17);  // full precision: 0.8920000000000001 must not print as the bound 0.892
    msg << wavelength_um << ")";
    throw InvalidArgument("wavelength", msg.str());
  }
  const NkSample* upper = std::lower_bound(first, last, wavelength_um,
                                           [](const NkSample& s, double w) { return s.wavelength_um < w; });
  if (upper == first) return {first->n, first->kappa};
  const NkSample* lower = upper - 1;
  // Linear interpolation in wavelength between the source's own samples.
  const double t = (wavelength_um - lower->wavelength_um) / (upper->wavelength_um - lower->wavelength_um);
  return {lower->n + t * (upper->n - lower->n), lower->kappa + t * (upper->kappa - lower->kappa)};
}

}  // namespace libbrdf
