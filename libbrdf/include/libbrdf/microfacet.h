#pragma once
// Microfacet terms of eq. 2 (surface reflection only, rho_v = 0) with the Gaussian slope
// distribution of eq. 7, and the mapping from MBK surface statistics (eqs 20, 25).
//
// | symbol  | meaning                                         | eq. | unit |
// |---------|-------------------------------------------------|-----|------|
// | D_g     | Gaussian facet distribution, projected-area norm | 7,8 | 1/sr |
// | sigma_g | slope parameter of D_g                           | 7   | 1    |
// | G       | shadowing-masking                                | 2   | 1    |
// | sigma   | cross-section to BRDF conversion 1/(4 ci cs)     | 3   | 1    |
#include "libbrdf/geometry.h"

namespace libbrdf {

enum class GeometricTerm { none, smith, vgroove };

// eq. 7: D_g = exp(-tan^2 th / (2 sigma_g^2)) / (2 pi sigma_g^2 cos^4 th). sigma_g > 0.
double gaussian_facet_distribution(double cos_theta_h, double sigma_g);
// Range of sigma_g a model accepts (given, or mapped by eqs 20/25). Below 1e-7 the peak of D_g,
// 1/(2 pi sigma_g^2) > 1.6e13 1/sr, is a mirror no table or renderer resolves (and at 1e-160 it
// overflowed to NaN); above 1e3 the rms facet slope is beyond vertical walls.
inline constexpr double kMinSigmaG = 1e-7;
inline constexpr double kMaxSigmaG = 1e3;
// Range of the microfacet amplitudes: rho_s in [0, kMaxRhoS] (default K, which is >= 1 and
// below ~10 for every surface of the domain), rho_d in [0, 1] (a Lambertian albedo).
inline constexpr double kMaxRhoS = 1000.0;

// G(ti, ts):
//  none:    1
//  smith:   uncorrelated Smith for the Gaussian (Beckmann) slopes, G1(ti) G1(ts),
//           G1 = 1/(1 + Lambda), Lambda(a) = (erf(a) - 1)/2 + exp(-a^2)/(2 a sqrt(pi)),
//           a = 1/(sqrt(2) sigma_g tan theta)   (B. Walter et al., EGSR 2007, eq. 27; Heitz 2014)
//  vgroove: Torrance-Sparrow / Cook-Torrance, min(1, 2 ch cs / cd, 2 ch ci / cd)
double geometric_term(GeometricTerm term, const ScatterGeometry& geo, double sigma_g);

// eq. 20 (very rough): sigma_g = sqrt(2) sigma_s / l_c.
double sigma_g_from_rough_surface(double sigma_s_um, double lc_um);
// eq. 25 (polished): sigma_g = lambda / (pi l_c sqrt 2).
double sigma_g_from_polished_surface(double lc_um, double wavelength_um);

}  // namespace libbrdf
