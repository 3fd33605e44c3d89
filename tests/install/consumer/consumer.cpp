// Links an installed libbrdf and checks values it computes against formulas written here.
// Exit 0 when all hold; prints each check.
#include <exporters/povray.h>
#include <libbrdf/batch.h>
#include <libbrdf/fresnel.h>
#include <libbrdf/materials.h>
#include <libbrdf/models.h>
#include <libbrdf/version.h>

#include <cmath>
#include <cstdio>
#include <vector>

int main() {
  int failures = 0;
  const auto check = [&](bool ok, const char* what, double got, double want) {
    std::printf("%s %s: %.17g (expected %.17g)\n", ok ? "ok  " : "FAIL", what, got, want);
    failures += ok ? 0 : 1;
  };
  // Gold at 0.55 um from the built-in table: F at normal incidence is
  // ((n - 1)^2 + kappa^2) / ((n + 1)^2 + kappa^2) (the Fresnel equations at theta = 0).
  const libbrdf::ComplexIndex gold = libbrdf::material_index("Au", 0.55);
  const double n = gold.n, kappa = gold.kappa;
  const double normal_f = ((n - 1) * (n - 1) + kappa * kappa) / ((n + 1) * (n + 1) + kappa * kappa);
  const double f0 = libbrdf::fresnel_reflectance(gold.permittivity(), 1.0);
  check(std::abs(f0 - normal_f) <= 1e-12 * normal_f && normal_f > 0.3 && normal_f < 0.9,
        "Au 0.55 um: F(0) against ((n-1)^2+k^2)/((n+1)^2+k^2)", f0, normal_f);

  // The batch path (oneTBB, Highway dispatch: the library's private dependencies must link):
  // model `fresnel` at specular geometry (theta_s = theta_i, phi_s = 180) is F(theta_d = theta_i).
  libbrdf::ModelParameters parameters;
  parameters.index = gold;
  const libbrdf::Model model(libbrdf::ModelKind::fresnel, parameters);
  const std::size_t count = 10000;
  std::vector<double> theta(count), phi(count, 180.0), values(count);
  for (std::size_t k = 0; k < count; ++k) theta[k] = 89.0 * static_cast<double>(k) / count;
  libbrdf::evaluate_degrees_batch(model, theta.data(), theta.data(), phi.data(), count, values.data());
  double worst = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const double want = libbrdf::fresnel_reflectance(gold.permittivity(), std::cos(theta[k] * M_PI / 180.0));
    worst = std::max(worst, std::abs(values[k] - want) / want);
  }
  check(worst <= 1e-12, "batch F(theta) at specular, 1e4 angles: max relative difference", worst, 0.0);
  check(std::abs(values[0] - f0) <= 1e-14 * f0, "batch F at normal incidence (SIMD lanes: within rounding)", values[0], f0);
  // libbrdf::exporters: POV-Ray's slope pattern at N.d = 1/2 is 1/2 + asin(1/2)/pi = 2/3
  // (povray/libbrdf.inc, "Normal pass").
  const double slope = libbrdf::povray::slope_value(0.5);
  check(std::abs(slope - 2.0 / 3.0) <= 1e-15, "exporters: POV-Ray slope value at N.d = 1/2", slope, 2.0 / 3.0);
  std::printf("libbrdf %s\n", libbrdf::kVersion);
  return failures == 0 ? 0 : 1;
}
