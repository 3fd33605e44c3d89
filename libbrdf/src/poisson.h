#pragma once
// Internal: ln of the Poisson weight e^-g g^m / m!, accurate for g up to ~1e8 (see mbk_series.cpp).
namespace libbrdf::detail {
double log_poisson_weight(int m, double g);
}
