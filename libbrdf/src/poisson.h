#pragma once
// Internal: ln of the Poisson weight e^-g g^m / m!, accurate for g up to ~1e8 (see mbk_series.cpp).
#include <cstdint>

namespace libbrdf::detail {
double log_poisson_weight(std::int64_t m, double g);

// Moments of the terms t_m of Sigma(g, c) (mbk_series.h), for the kernel table's derivatives:
//   a = sum t_m, b = sum t_m (m - g), c = sum t_m / m, d = sum t_m (m - g) / m, e = sum t_m / m^2,
// each divided by exp(log_scale). By the SIMD blocks truncated at 1e-16 (see mbk_series.cpp).
struct SeriesMoments {
  double log_scale = 0.0, a = 0.0, b = 0.0, c = 0.0, d = 0.0, e = 0.0;
};
SeriesMoments series_moments(double g, double c);
}
