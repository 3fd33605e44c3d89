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

// Throws InvalidArgument naming sigma_s, lc or wavelength when out of domain.
void validate_surface(const Surface& surface);

}  // namespace libbrdf
