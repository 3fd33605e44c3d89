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
  require_in_range("n", index.n, kMinIndexN, kMaxIndex);
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
  // |a/b|^2 as |a|^2/|b|^2: no complex division (GCC's C99 __divdc3 was 10% of an mbk
  // evaluation), and with Re w >= 0 each ratio is <= 1 exactly as computed (= 1 under total
  // internal reflection, where w is imaginary and |c - w| = |c + w| term by term).
  const Complex eps_cos = eps * cos_theta;
  return {std::norm(cos_theta - w) / std::norm(cos_theta + w), std::norm(eps_cos - w) / std::norm(eps_cos + w)};
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
  // |a/b|^2 = |a|^2/|b|^2 (no complex division).
  const double e2 = std::norm(eps_minus_1);
  const double n_si = std::norm(s_i), n_ss = std::norm(s_s), n_pi = std::norm(p_i), n_ps = std::norm(p_s);
  q.ss = e2 * cos_phi * cos_phi / (n_si * n_ss);
  q.sp = e2 * std::norm(ws) * sin_phi * sin_phi / (n_si * n_ps);
  q.ps = e2 * std::norm(wi) * sin_phi * sin_phi / (n_pi * n_ss);
  q.pp = e2 * std::norm(wi * ws * cos_phi - eps * geo.sin_theta_i * geo.sin_theta_s) / (n_pi * n_ps);
  return q;
}

}  // namespace libbrdf
