#include "quadrature.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>

#include "libbrdf/geometry.h"

namespace libbrdf::detail {

namespace {
GaussLegendreRule compute_rule(int n) {
  GaussLegendreRule rule;
  rule.nodes.resize(n);
  rule.weights.resize(n);
  for (int i = 0; i < n; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;  // Legendre recurrence up to P_n
      for (int k = 2; k <= n; ++k) {
        const double pk = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = pk;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    rule.nodes[i] = x;
    rule.weights[i] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
  return rule;
}
}  // namespace

const GaussLegendreRule& gauss_legendre(int order) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<GaussLegendreRule>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  auto& slot = cache[order];
  if (!slot) slot = std::make_unique<GaussLegendreRule>(compute_rule(order));
  return *slot;
}

double distance_to_unit_circle(double s, double psi) {
  const double cos_psi = std::cos(psi), sin_psi = std::sin(psi);
  return std::max(0.0, -s * cos_psi + std::sqrt(std::max(0.0, 1.0 - s * s * sin_psi * sin_psi)));
}

}  // namespace libbrdf::detail
