#pragma once
// Gaussian random rough surface seen at one wavelength.
// All lengths in micrometres (conventions.md); the models depend only on the ratios to lambda.
namespace libbrdf {

struct Surface {
  double sigma_s_um = 0.0;    // rms height, >= 0 (0 = perfect mirror)
  double lc_um = 1.0;         // correlation length, > 0
  double wavelength_um = 0.55;  // > 0
  double sigma_over_lambda() const { return sigma_s_um / wavelength_um; }
  double lc_over_lambda() const { return lc_um / wavelength_um; }
};

// Domain of the surface. The models depend on sigma_s/lambda and l_c/lambda only, so the bounds
// are on those ratios (plus finite, positive lengths):
//   0 <= sigma_s/lambda <= kMaxSigmaOverLambda = 1e15 (sigma_s = 500 km at visible light): g of
//        eq. 12 is at most 16 pi^2 (sigma_s/lambda)^2 = 1.6e32, deep in the very-rough limit, and
//        K(theta_i) of eq. 13, which grows like ~0.8 (sigma_s/lambda)^2, stays below 1e30, inside
//        the float32 range of a table's K row (at 1e100 K = 2.6e200 could not be baked). The
//        series itself is bounded-time for any finite g (mbk_series.h).
//   kMinLcOverLambda = 1e-6 <= l_c/lambda <= kMaxLcOverLambda = 1e6: the lobe width
//        1/(pi l_c/lambda) stays between 3e-7 and 3e5 direction cosines: narrower lobes are
//        below any renderer's resolution and their K table (renormalization.h) needs more
//        nodes than it allows; wider ones scatter nothing (A ~ (l_c/lambda)^2 -> 0).
inline constexpr double kMaxSigmaOverLambda = 1e15;
inline constexpr double kMinLcOverLambda = 1e-6;
inline constexpr double kMaxLcOverLambda = 1e6;

// Throws InvalidArgument naming sigma_s, lc or wavelength (and the allowed range) when out of domain.
void validate_surface(const Surface& surface);

}  // namespace libbrdf
