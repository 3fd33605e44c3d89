#pragma once
// Internal: ln of the Poisson weight e^-g g^m / m!, accurate for g up to ~1e8 (see mbk_series.cpp).
#include <cstdint>

namespace libbrdf::detail {
double log_poisson_weight(std::int64_t m, double g);
}
