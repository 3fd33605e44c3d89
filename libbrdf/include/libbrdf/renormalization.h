#pragma once
// Renormalization K(theta_i) of the MBK model, eq. 13 (Krywonos, Harvey & Choi 2011), read as
// fixed in conventions.md ("The MBK family"):
//
//  plane (default): K = 1 + [(1 - e^-g1) - D(g1)] / D
//      D     = integral of the ASF (true g(ti, ts)) over the unit disk, d alpha d beta
//      g1    = g(ti, 90 deg) = (2 pi sigma_s cos ti / lambda)^2, the g of the evanescent region
//      D(g1) = the same disk integral with the constant g1; (1 - e^-g1) - D(g1) is evaluated
//              directly as the integral outside the disk (no cancellation).
//      K >= 1 always; K = 1 at sigma_s = 0.
//  tis: K_tis = (1 - e^-g(ti, ti)) / D  (Generalized Harvey-Shack practice; conserves energy
//      exactly, may fall below 1 at grazing).
//
// K depends on theta_i, sigma_s/lambda and l_c/lambda only: a 1D table per wavelength and surface.
#include <memory>
#include <vector>

#include "libbrdf/surface.h"

namespace libbrdf {

enum class KMode { plane, tis };

// Parts of eq. 13 at one incidence angle (all dimensionless).
struct RenormalizationParts {
  double disk = 0.0;          // D: ASF integrated over the unit disk (= hemispherical integral of A cos ts)
  double outside = 0.0;       // integral outside the disk with the constant g1
  double total_scatter = 0.0; // 1 - exp(-g(ti, ti)): the energy the series carries (TIS)
  double k = 1.0;             // the K of the requested mode
};

// Quadrature resolution of the direct computation. Against 4x finer rules the defaults differ by
// <= 2e-7 (sigma_s/lambda = 0.2, l_c/lambda = 2, any ti) and 2e-6 (l_c/lambda = 1e3 at 89.5 deg).
struct RenormalizationQuadrature {
  int azimuth_nodes = 48;      // Gauss-Legendre nodes over the half disk's azimuth around specular
  int radial_nodes = 12;       // Gauss-Legendre nodes per radial panel
};

// Direct computation by quadrature in polar coordinates centred on the specular point.
RenormalizationParts renormalization_direct(const Surface& surface, double theta_i_rad, KMode mode,
                                            const RenormalizationQuadrature& quadrature = {});

// K(ti) tabulated on a uniform theta_i grid over [0, 90] deg and interpolated by a monotone cubic
// (Fritsch-Carlson) in theta_i. Build once per (surface, mode); evaluation is O(1).
class RenormalizationTable {
 public:
  static constexpr int kDefaultNodes = 91;  // 1 deg spacing

  RenormalizationTable(const Surface& surface, KMode mode, int nodes = kDefaultNodes);

  double operator()(double theta_i_rad) const;
  const std::vector<double>& node_values() const { return k_; }
  double node_spacing_rad() const { return step_; }
  KMode mode() const { return mode_; }

 private:
  KMode mode_;
  double step_;
  std::vector<double> k_;
  std::vector<double> slope_;
};

// Shared, thread-safe cache: one table per (sigma/lambda, l_c/lambda, mode).
std::shared_ptr<const RenormalizationTable> cached_renormalization_table(const Surface& surface,
                                                                          KMode mode);

}  // namespace libbrdf
