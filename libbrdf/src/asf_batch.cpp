// asf_auto over a batch of queries (mbk_series.h).
#include "libbrdf/mbk_series.h"

namespace libbrdf {

void asf_auto_batch(const double* g, const double* c, std::size_t count, double prefactor, double tolerance,
                    const SeriesOptions& options, double* asf_out) {
  for (std::size_t k = 0; k < count; ++k) asf_out[k] = asf_auto(AsfArguments{g[k], c[k], prefactor}, tolerance, nullptr, options);
}

}  // namespace libbrdf
