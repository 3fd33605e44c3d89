#include "libbrdf/fresnel.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "libbrdf/error.h"

namespace libbrdf {

Complex ComplexIndex::permittivity() const {
  const Complex index(n, kappa);
  return index * index;
}

void validate_index(const ComplexIndex& index) {
  // fresnel.h: kMaxIndex bounds n and kappa (eps stays far inside the double range).
  if (!(std::isfinite(index.n) && index.n > 0.0 && index.n <= kMaxIndex)) {
    char got[40];
    std::snprintf(got, sizeof got, "%.17g", index.n);
    throw InvalidArgument("n", "must be in (0, 1000] (got " + std::string(got) + ")");
  }
  require_in_range("k", index.kappa, 0.0, kMaxIndex);
}

namespace {
// w = sqrt(eps - sin^2 theta), principal branch: std::sqrt returns Re >= 0; for eps with
// Im >= 0 (kappa >= 0) this is also Im w >= 0 (conventions.md).
Complex normal_wavenumber(const Complex& eps, double sin2_theta) { return std::sqrt(eps - sin2_theta); }
}  // namespace

FresnelSP fresnel_sp(const Complex& eps, double cos_theta) {
  const double sin2 = std::max(0.0, 1.0 - cos_theta * cos_theta);
  const Complex w = normal_wavenumber(eps, sin2);
  const Complex r_s = (cos_theta - w) / (cos_theta + w);
  const Complex r_p = (eps * cos_theta - w) / (eps * cos_theta + w);
  return {std::norm(r_s), std::norm(r_p)};
}

double fresnel_reflectance(const Complex& eps, double cos_theta) {
  const FresnelSP rsp = fresnel_sp(eps, cos_theta);
  return 0.5 * (rsp.r_s + rsp.r_p);
}

PolarizationFactors stover_q(const Complex& eps, const ScatterGeometry& geo) {
  const double ci = geo.cos_theta_i, cs = geo.cos_theta_s;
  const Complex wi = normal_wavenumber(eps, geo.sin_theta_i * geo.sin_theta_i);
  const Complex ws = normal_wavenumber(eps, geo.sin_theta_s * geo.sin_theta_s);
  // Stover's azimuth is 0 at specular: phi = phi_s - pi (conventions.md).
  const double cos_phi = -geo.cos_phi_s;
  const double sin_phi = -geo.sin_phi_s;
  const Complex eps_minus_1 = eps - 1.0;
  const Complex s_i = ci + wi, s_s = cs + ws;              // s denominators
  const Complex p_i = eps * ci + wi, p_s = eps * cs + ws;  // p denominators
  PolarizationFactors q{};
  q.ss = std::norm(eps_minus_1 * cos_phi / (s_i * s_s));
  q.sp = std::norm(eps_minus_1 * ws * sin_phi / (s_i * p_s));
  q.ps = std::norm(eps_minus_1 * wi * sin_phi / (p_i * s_s));
  q.pp = std::norm(eps_minus_1 * (wi * ws * cos_phi - eps * geo.sin_theta_i * geo.sin_theta_s) / (p_i * p_s));
  return q;
}

}  // namespace libbrdf
