#include "libbrdf/surface.h"

#include <cstdio>
#include <string>

#include "libbrdf/error.h"

namespace libbrdf {

namespace {
std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}
}  // namespace

void validate_surface(const Surface& surface) {
  require_at_least("sigma_s", surface.sigma_s_um, 0.0, "um");
  require_positive("lc", surface.lc_um, "um");
  require_positive("wavelength", surface.wavelength_um, "um");
  // Ratios: see surface.h. Written as products so that an overflowing ratio is caught too.
  if (!(surface.sigma_s_um <= kMaxSigmaOverLambda * surface.wavelength_um))
    throw InvalidArgument("sigma_s", "must be in [0, " + number(kMaxSigmaOverLambda) + "] x the wavelength (got sigma_s = " +
                                         number(surface.sigma_s_um) + " um at wavelength " + number(surface.wavelength_um) + " um)");
  if (!(surface.lc_um >= kMinLcOverLambda * surface.wavelength_um && surface.lc_um <= kMaxLcOverLambda * surface.wavelength_um))
    throw InvalidArgument("lc", "must be in [" + number(kMinLcOverLambda) + ", " + number(kMaxLcOverLambda) +
                                    "] x the wavelength (got l_c = " + number(surface.lc_um) + " um at wavelength " +
                                    number(surface.wavelength_um) + " um)");
}

}  // namespace libbrdf
