#pragma once
// Directional albedo ("white furnace") of a model: the fraction of the light arriving from theta_i
// that the surface sends back into the hemisphere,
//
//   a(ti) = integral over the hemisphere of f(ti, ts, phi_s) cos ts dw_s  +  R_spec(ti)
//         = integral over the unit disk of f d alpha d beta               +  R_spec(ti)
//
// with the specular spike (a delta of weight R_spec = F(ti) exp(-g(ti, ti)), conventions.md)
// included. a > 1 is energy created: under uniform white light (a renderer's white furnace) such a
// surface glows brighter than its surroundings. The MBK model with the plane K (eq. 13) exceeds 1
// near grazing on rough surfaces (conventions.md, "Its known defect"); K mode tis conserves
// energy by construction; bk's F_bk^2 grows towards the horizon.
//
// Quadrature, independent of the K integral (renormalization.cpp, fixed Gauss-Legendre panels):
// adaptive Gauss-Kronrod (Boost.Math, 15/31 points, error estimates) in polar coordinates
// (rho, psi) centred on the specular direction in the direction-cosine plane, the radial range
// cut at geometric breakpoints from a quarter of the narrowest lobe width (MBK: 1/(pi l_c/lambda);
// microfacet: ~sigma_g) so narrow lobes are found, the last panel mapped by rho = rho_max - u^2
// to remove the square-root edge of cos ts at the horizon.
#include <vector>

#include "libbrdf/models.h"

namespace libbrdf {

struct AlbedoOptions {
  double relative_tolerance = 1e-6;  // asked of each adaptive rule (relative to its own integral)
};

struct DirectionalAlbedo {
  double theta_i_rad = 0.0;
  double lobe = 0.0;            // integral of f cos ts over the hemisphere (the BRDF part)
  double specular = 0.0;        // R_spec(ti), the spike (0 for models without one)
  double total = 0.0;           // lobe + specular
  double error_estimate = 0.0;  // absolute, summed over the adaptive rules' own estimates
  long long evaluations = 0;    // model evaluations used
};

// a(theta_i) of a BRDF model (is_brdf(kind)); theta_i in [0, pi/2). Throws InvalidArgument
// otherwise. Thread-safe (evaluations of one Model).
DirectionalAlbedo directional_albedo(const Model& model, double theta_i_rad, const AlbedoOptions& options = {});

}  // namespace libbrdf
