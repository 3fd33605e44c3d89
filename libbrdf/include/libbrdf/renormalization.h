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
#include <cstddef>
#include <memory>
#include <vector>

#include "libbrdf/geometry.h"
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
// <= 1e-8 for polished to rough surfaces (sigma_s/lambda 0.01-1, l_c/lambda 4-1000, 0-89.9 deg,
// both modes), <= 2.7e-7 for wide lobes (l_c/lambda 0.3-1.25, sigma_s/lambda 0.3-1), and, on a very
// rough surface (sigma_s/lambda = 6, l_c/lambda = 2) at grazing, 1.1e-6 (89.5 deg) and 5.7e-6 (tis,
// 89.9 deg; the radial rule's); against an independent adaptive quadrature in
// (theta_s, phi_s) (tests/cpp) D agrees to <= 1.7e-7 for polished, intermediate and rough surfaces
// at ti = 0, 40, 75 deg, and to <= 1.1e-8 for three wide lobes.
struct RenormalizationQuadrature {
  int azimuth_nodes = 48;      // Gauss-Legendre nodes over the half disk's azimuth around specular
  int radial_nodes = 12;       // Gauss-Legendre nodes per radial panel
};

// Direct computation by quadrature in polar coordinates centred on the specular point (the ASF at
// its points by asf_auto_batch, each value within 1e-9 of the series).
RenormalizationParts renormalization_direct(const Surface& surface, double theta_i_rad, KMode mode,
                                            const RenormalizationQuadrature& quadrature = {});

// K(ti) tabulated over [0, 90] deg on nodes uniform in u = 1 - sqrt(cos ti), which are 12 deg
// apart at normal incidence (where the factors below are smooth in ti^2 ~ 4u) and close up like
// sqrt(90 deg - ti) near grazing (the last interval of 91 nodes is 0.007 deg); the coordinate needs
// no inverse trigonometry. K is steep near grazing (K - 1 and
// K_tis vanish like cos^2 ti at 90 deg), so the table interpolates the smooth factors of K instead,
// ln D(ti) and the outside fraction r(ti) = outside / (1 - e^-g1), by cubic Hermite with
// fourth-order slopes. A lookup evaluates one cubic: q = (K - 1) / cos^2 ti (plane) or
// K / cos^2 ti (tis), computed from the smooth factors with the exact g1(ti) and g(ti, ti) on a
// grid 23x finer (kDenseMinNodes; 33 KB for 91 nodes), times the query's exact cos^2 ti. Build once
// per (surface, mode); evaluation is O(1). Span lookup, one core: 4.98 ns per query, against
// 8.75 ns rebuilding K from the smooth factors (an exp, an expm1 and a division per query) and
// 14.5 ns with the arcsine node map below; errors vs direct unchanged to 2 digits.
// Accuracy (tests/cpp/test_renormalization.cpp, RenormalizationTable.MatchesDirectBetweenNodesTo1e5,
// off-node angles over [0, 89.5] deg) measured max relative error vs renormalization_direct:
// <= 1.0e-7 (plane) and 4.4e-7 (tis) for polished (sigma/lambda = 0.01, l_c/lambda = 5),
// intermediate (0.1, 2) and rough (0.5, 3) surfaces, 2.9e-6 for l_c/lambda = 1e3; tis-mode figures
// are at the direct quadrature's own noise. (A uniform 1-deg table interpolating K itself had
// 4e-4 in plane mode and 20% in tis mode at 89.25 deg. The earlier node map, uniform in
// y = (2/pi) asin(ti / 90 deg), measured the same to within a factor 2 either way with 1.4x the
// nodes for narrow lobes, and cost an arctangent and an arcsine per span query: 14.5 against
// 8.8 ns per query for the span, one core.)
class RenormalizationTable {
 public:
  static constexpr int kDefaultNodes = 91;  // the fewest nodes the automatic count uses
  // Nodes for a surface: kDefaultNodes, more for narrow lobes (l_c/lambda >~ 100).
  static int automatic_node_count(const Surface& surface);

  // nodes = 0: automatic_node_count(surface).
  RenormalizationTable(const Surface& surface, KMode mode, int nodes = 0);

  double operator()(double theta_i_rad) const;
  // k[j] = (*this)(theta_i of geos[j]) for a span, in SIMD (angular_simd.cpp): the node coordinate
  // 1 - sqrt(cos theta_i) from the geometry's cos theta_i (no inverse trigonometry), the same
  // Hermite cubic. Agrees with operator() to <= 1e-13 relative (tests/cpp/test_renormalization.cpp).
  void at_geometries(const ScatterGeometry* geos, std::size_t count, double* k) const;
  // The nodes (radians, from 0 to pi/2) and K there.
  const std::vector<double>& node_angles() const { return angles_; }
  const std::vector<double>& node_values() const { return k_; }
  KMode mode() const { return mode_; }

 private:
  KMode mode_;
  Surface surface_;
  double scale_ = 1.0;  // node index per unit of the node coordinate u = 1 - sqrt(cos theta_i)
  std::vector<double> angles_, k_;
  std::vector<double> log_disk_, log_disk_slope_;
  std::vector<double> outside_fraction_, outside_fraction_slope_;
  bool linear_only_ = false;  // no scatter anywhere in the disk (underflow): K interpolated linearly
  static constexpr int kDenseRefinement = 4;   // dense intervals per coarse one, at least
  static constexpr int kDenseMinNodes = 2048;  // ... and at least this many dense intervals
  // The lookup's table, on a grid kDenseRefinement times finer in u, from the smooth factors:
  // q = (K - b) / cos^2 ti with b = 1 (plane) or 0 (tis), smooth in u up to grazing, where K - b
  // vanishes like cos^2 ti (g1 = g(ti, 0) and g(ti, ti) do); K = b + cos^2 ti q keeps that
  // steep factor exact and costs one cubic per query (no exp or division). Interleaved (q, dq per
  // dense node index).
  std::vector<double> dense_;  // 2 dense_nodes_ values (in plane mode, those below kNegligibleQ stored as 0)
  static constexpr double kNegligibleQ = 1e-200;
  int dense_nodes_ = 0;
  double dense_scale_ = 1.0;  // dense node index per unit of u

  double q_from_smooth_factors(double u) const;
};

// Shared, thread-safe cache: one table per (sigma/lambda, l_c/lambda, mode).
std::shared_ptr<const RenormalizationTable> cached_renormalization_table(const Surface& surface,
                                                                          KMode mode);

}  // namespace libbrdf
