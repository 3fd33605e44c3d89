#pragma once
// Fresnel reflectance F and Stover's polarization factors Q (Rayleigh-Rice), for a complex index.
//
// References: J. D. Jackson, Classical Electrodynamics, 3rd ed. (1999), sec. 7.3 (Fresnel);
// J. C. Stover, Optical Scattering, 3rd ed. (SPIE, 2012), Q_ss, Q_sp, Q_ps, Q_pp.
// Conventions (conventions.md, "Fresnel and Stover's polarization factors"):
//   n~ = n + i kappa, kappa >= 0; permittivity eps = n~^2; w = sqrt(eps - sin^2 theta) on the
//   principal branch (Im w >= 0). Stover's azimuth is phi = phi_s - pi (0 at specular).
//   Qbar = (Q_s + Q_p)/2 is the unpolarized BRDF factor (= F at specular); the paper's
//   Q = Q_s + Q_p (= 2F at specular) is used only by the analysis terms (eqs 22, 23).
#include <complex>

#include "libbrdf/geometry.h"

namespace libbrdf {

using Complex = std::complex<double>;

// Complex refractive index n~ = n + i kappa (dimensionless, kappa >= 0).
struct ComplexIndex {
  double n = 1.5;
  double kappa = 0.0;
  Complex permittivity() const;  // eps = n~^2
};

// Largest n and kappa accepted. Measured metals and dielectrics stay below ~100 (n, kappa of the
// infrared metals); 1000 keeps eps = (n + i kappa)^2 (|eps| <= 2e6) and every Fresnel / Stover
// factor far inside the double range, where --n 1e308 overflowed to NaN.
inline constexpr double kMaxIndex = 1000.0;
// Smallest n accepted (the lowest measured n of metals in the visible, Na and Ag, are ~0.05): at
// n = 1e-300 eps underflowed to 0 and r_p = (eps cos - w)/(eps cos + w) was 0/0 at normal incidence.
inline constexpr double kMinIndexN = 1e-3;
// Throws InvalidArgument unless kMinIndexN <= n <= kMaxIndex and 0 <= kappa <= kMaxIndex.
void validate_index(const ComplexIndex& index);

// Exact unpolarized Fresnel reflectance (|r_s|^2 + |r_p|^2)/2 at incidence angle theta (cos given).
double fresnel_reflectance(const Complex& permittivity, double cos_theta);

// s and p reflectances separately, R_s = |r_s|^2, R_p = |r_p|^2.
struct FresnelSP {
  double r_s, r_p;
};
FresnelSP fresnel_sp(const Complex& permittivity, double cos_theta);

// Stover's polarization factors for one geometry (each dimensionless, >= 0).
struct PolarizationFactors {
  double ss, sp, ps, pp;
  double q_s() const { return ss + sp; }               // s-polarized incidence
  double q_p() const { return ps + pp; }               // p-polarized incidence
  double q_paper() const { return q_s() + q_p(); }     // the paper's Q (= 2F at specular)
  double q_bar() const { return 0.5 * q_paper(); }     // unpolarized BRDF factor (= F at specular)
};
PolarizationFactors stover_q(const Complex& permittivity, const ScatterGeometry& geo);

}  // namespace libbrdf
