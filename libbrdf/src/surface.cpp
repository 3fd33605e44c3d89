#include "libbrdf/surface.h"

#include "libbrdf/error.h"

namespace libbrdf {

void validate_surface(const Surface& surface) {
  require_at_least("sigma_s", surface.sigma_s_um, 0.0, "um");
  require_positive("lc", surface.lc_um, "um");
  require_positive("wavelength", surface.wavelength_um, "um");
}

}  // namespace libbrdf
