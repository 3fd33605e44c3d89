#pragma once
// Internal: Gauss-Legendre rules (nodes and weights on [-1, 1]), computed once per order, and the
// geometry of the polar coordinates around the specular point that K and the albedo integrate in.
#include <vector>

namespace libbrdf::detail {

struct GaussLegendreRule {
  std::vector<double> nodes, weights;
};

// Cached, thread-safe. Newton iteration on P_n from the Chebyshev guesses (accurate to ~1e-15).
const GaussLegendreRule& gauss_legendre(int order);

// Integral of f over [a, b] with the n-point rule.
template <class F>
double integrate_gauss_legendre(const GaussLegendreRule& rule, double a, double b, F&& f) {
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  double sum = 0.0;
  for (std::size_t k = 0; k < rule.nodes.size(); ++k) sum += rule.weights[k] * f(mid + half * rule.nodes[k]);
  return sum * half;
}

// In the plane of direction cosines, the distance from the specular point (at distance s from the
// origin, s = sin theta_i) to the unit circle along azimuth psi, measured from the outward radial
// direction (away from the normal's foot): the root rho >= 0 of rho^2 + 2 s rho cos psi + s^2 = 1.
double distance_to_unit_circle(double s, double psi);

}  // namespace libbrdf::detail
