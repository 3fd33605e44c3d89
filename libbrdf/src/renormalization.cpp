#include "libbrdf/renormalization.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <map>
#include <mutex>
#include <tuple>
#include <vector>

#include "angular_simd.h"
#include "libbrdf/error.h"
#include "libbrdf/geometry.h"
#include "libbrdf/mbk_series.h"
#include "poisson.h"
#include "quadrature.h"

namespace libbrdf {
namespace {

// Panels [a, b) covering [0, length], the first `first` wide (clamped to length), each next
// `ratio` times as far out: geometric grading away from a feature at 0.
template <class Panel>
void graded_panels(double length, double first, double ratio, const Panel& panel) {
  for (double a = 0.0, b = std::min(first, length); a < length; a = b, b = std::min(length, ratio * b)) panel(a, b);
}

// The azimuth nodes psi in [0, pi] and weights of the half disk's rule (the integrands are
// symmetric in alpha). The distance to the unit circle, -s cos psi + sqrt(cos^2 ti + s^2 cos^2 psi),
// has a rounded kink of width ~cos ti at psi = pi/2, a corner at grazing: the range is split there
// into two panels of azimuth_nodes / 2 nodes, and near grazing (cos ti < 1/4) into panels growing
// 4x away from pi/2 from the width cos ti, of azimuth_nodes / 6 nodes each, so that Gauss-Legendre
// resolves the kink. Against a rule 4x finer, K at 89.9 deg moved from 8.7e-5 to 5.7e-6
// (sigma_s/lambda = 6, tis; the rest is radial) and, for l_c/lambda = 1000 at 89-89.9 deg, from
// 5.6e-6 to <= 3.3e-9 (both modes; plane through the outside integral). K tables cost about the
// same (within this machine's ~20% noise), where panels growing 2x with azimuth_nodes / 2 nodes
// each took 3-4x longer for no better accuracy.
// Each node carries its distance from the specular point to the unit circle, which both the disk
// and the outside integral need (computed once per K node).
struct AzimuthNode {
  double psi, weight;
  double rho_max;  // detail::distance_to_unit_circle(sin theta_i, psi)
};
std::vector<AzimuthNode> half_disk_azimuth_nodes(const RenormalizationQuadrature& quad, double theta_i) {
  const double cos_theta_i = std::cos(theta_i), sin_theta_i = std::sin(theta_i);
  std::vector<AzimuthNode> nodes;
  auto panel = [&](const detail::GaussLegendreRule& rule, double a, double b) {
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    for (std::size_t k = 0; k < rule.nodes.size(); ++k) {
      const double psi = mid + half * rule.nodes[k];
      nodes.push_back({psi, half * rule.weights[k], detail::distance_to_unit_circle(sin_theta_i, psi)});
    }
  };
  const double mid = 0.5 * kPi;
  if (!(cos_theta_i < 0.25)) {
    const detail::GaussLegendreRule& rule = detail::gauss_legendre(quad.azimuth_nodes / 2);
    panel(rule, 0.0, mid);
    panel(rule, mid, kPi);
    return nodes;
  }
  const detail::GaussLegendreRule& rule = detail::gauss_legendre(std::max(4, quad.azimuth_nodes / 6));
  graded_panels(mid, cos_theta_i, 4.0, [&](double near, double far) {
    panel(rule, mid - far, mid - near);  // panels below pi/2
    panel(rule, mid + near, mid + far);  // and above
  });
  return nodes;
}

// Disk integral D of the ASF with the true g(ti, ts): polar coordinates (rho, psi) centred on the
// specular point, where eta_r = rho exactly (eq. 10), so the Gaussian lobes are radial. The radial
// range is cut into panels growing geometrically from a quarter of the narrowest lobe width
// (m = 1: 1/(pi l_c/lambda)), so lobes from l_c/lambda ~ 1e3 to rough surfaces are resolved.
double disk_integral(const Surface& surface, double theta_i, const std::vector<AzimuthNode>& azimuths,
                     const RenormalizationQuadrature& quad) {
  const double s = std::sin(theta_i), ci = std::cos(theta_i);
  const double lc_over_lambda = surface.lc_over_lambda();
  const double prefactor = kPi * lc_over_lambda * lc_over_lambda;
  const double sigma_over_lambda = surface.sigma_over_lambda();
  const double first_panel = 0.25 / (kPi * lc_over_lambda);
  const auto& radial_rule = detail::gauss_legendre(quad.radial_nodes);
  const SeriesOptions series;
  // Each ASF value within 1e-6 (relative) of the series: the kernel table (kernel_table.h) where
  // it holds (g, c), the series in SIMD lanes elsewhere. Its interpolation errors change sign from
  // cell to cell and average out in the integral: K moved by <= 1.8e-10 relative against ASF
  // values within 1e-9 (polished to rough surfaces and l_c/lambda = 200, 0-89 deg), far below the
  // quadrature's own error (~1e-7, renormalization.h), and K's set-up took 1.2-2x less CPU.
  constexpr double kAsfTolerance = 1e-6;

  // Every quadrature point of every radial line collected first (thread-local buffers, reused
  // across the nodes of a K table), then the ASF of all of them in one asf_auto_batch call
  // (queries in SIMD lanes, each lane alone). The points' g, c and weights in one loop per line,
  // which vectorises (with -fno-math-errno: libbrdf/CMakeLists.txt). A K table (91 nodes, one
  // CPU, best of 5, same run) took 9.7 / 17.1 / 14.8 ms of CPU with a batch call per radial line
  // and a point at a time, 6.5 / 9.5 / 10.3 ms now (sigma_s/lambda, l_c/lambda = 0.01, 4 / 1, 4 /
  // 0.01, 40).
  thread_local std::vector<double> g, c, weight, value;
  g.clear(), c.clear(), weight.clear();
  for (const AzimuthNode& azimuth : azimuths) {
    const double rho_max = azimuth.rho_max;
    const double cos_psi = std::cos(azimuth.psi);
    // The line's points: rho in c, rho's weight (Gauss-Legendre weight x panel half-width, x 2u
    // below) in weight; then g, c and the weight with its Jacobian rho in one loop over them.
    const std::size_t line_begin = c.size();
    auto add = [&](double rho, double w) { c.push_back(rho), weight.push_back(w); };
    auto add_panel = [&](double a, double b, auto&& map) {
      const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
      for (std::size_t k = 0; k < radial_rule.nodes.size(); ++k) map(mid + half * radial_rule.nodes[k], radial_rule.weights[k] * half);
    };
    // Regular panels end at most half-way to the unit circle: the square-root singularity there
    // (below) then stays at least a panel width away from each of them, where Gauss-Legendre
    // converges geometrically. (Panels that doubled up to the circle itself could end just short
    // of it, at azimuths where rho_max is slightly above a panel end: K was off by up to 1.5e-5 at
    // sigma_s/lambda = 1, l_c/lambda = 0.5, 31.7 deg, erratically in theta_i.)
    double a = 0.0, b = first_panel;
    while (b <= 0.5 * rho_max) {
      add_panel(a, b, add);
      a = b;
      b *= 2.0;
    }
    // The rest ends on the unit circle, where cos ts ~ sqrt(rho_max - rho) has a square-root
    // singularity that Gauss-Legendre resolves only algebraically (~1e-5 relative error in D for
    // rough surfaces). With rho = rho_max - u^2 the integrand is smooth in u, and cos ts ~ u there.
    // Near grazing incidence a rough surface's ASF turns from ~g to ~1/g where g(ti, ts) =
    // (k (cos ti + cos ts))^2 ~ 1, k = 2 pi sigma_s/lambda: a layer of width ~1/k in cos ts along
    // the circle. The u panels grow geometrically from a quarter of it (at least two; one more
    // per octave of k for rough surfaces). At sigma_s/lambda = 6, l_c/lambda = 2, 85 deg, K moved
    // from 1.0e-6 (one u panel) to 3e-10 of a rule 8x finer; with the azimuth grading above, what
    // is left at 89.9 deg (5.7e-6, tis) is this radial rule's.
    const double u_max = std::sqrt(rho_max - a);
    auto add_u = [&](double u, double w) { add(rho_max - u * u, 2.0 * u * w); };
    graded_panels(u_max, std::min(0.5 * u_max, 0.25 / (2.0 * kPi * sigma_over_lambda)), 2.0,
                  [&](double ua, double ub) { add_panel(ua, ub, add_u); });
    g.resize(c.size());
    const double two_s_cos_psi = 2.0 * s * cos_psi, one_minus_s2 = 1.0 - s * s;
    for (std::size_t k = line_begin; k < c.size(); ++k) {
      const double rho = c[k];
      // cos ts of the scattered direction at (alpha, beta) = (rho sin psi, s + rho cos psi).
      const double cos2_ts = std::max(0.0, one_minus_s2 - two_s_cos_psi * rho - rho * rho);
      g[k] = roughness_g(sigma_over_lambda, ci, std::sqrt(cos2_ts));
      c[k] = kPi * prefactor * rho * rho;
      weight[k] *= azimuth.weight * rho;
    }
  }
  value.resize(g.size());
  asf_auto_batch(g.data(), c.data(), g.size(), prefactor, kAsfTolerance, series, value.data());
  double total = 0.0;
  for (std::size_t k = 0; k < g.size(); ++k) total += weight[k] * value[k];
  return 2.0 * total;  // symmetric in alpha: twice the half disk
}

// Integral outside the unit disk of the ASF with the constant g1, done per series term m in
// closed form radially: each term is a Poisson weight P(m; g1) times a unit-mass Gaussian of
// rho with 1/(2 variance) = pi^2 (l_c/lambda)^2 / m, whose mass beyond rho_max(psi) is
// exp(-a_m rho_max^2). No cancellation against the disk integral.
double outside_integral(const Surface& surface, double theta_i, const std::vector<AzimuthNode>& azimuths) {
  const double ci = std::cos(theta_i);
  const double g1 = roughness_g(surface.sigma_over_lambda(), ci, 0.0);
  if (!(g1 > 0.0)) return 0.0;
  const double lc_over_lambda = surface.lc_over_lambda();
  const double a1 = kPi * kPi * lc_over_lambda * lc_over_lambda;
  // a1 rho_max(psi)^2 at the azimuth nodes, once for every term m.
  std::vector<double> a1_r2(azimuths.size());
  for (std::size_t k = 0; k < azimuths.size(); ++k) a1_r2[k] = a1 * azimuths[k].rho_max * azimuths[k].rho_max;
  auto outside_fraction = [&](double m) {
    double sum = 0.0;
    for (std::size_t k = 0; k < azimuths.size(); ++k) sum += azimuths[k].weight * std::exp(-a1_r2[k] / m);
    return sum / kPi;
  };
  // Poisson weights from the mode outward until they no longer matter against 1 - e^-g1. The term
  // index is 64-bit (an int overflowed at g1 >= 2^31, sigma_s/lambda ~ 7400, and never ended).
  // Wide windows are summed every `stride`-th term times the stride: outside_fraction(m) varies on
  // the scale of m itself, so by the Poisson summation formula (as for the strided series,
  // mbk_series.h) the relative error is ~exp(-2 pi^2 (sqrt(g1) / stride)^2) = e^-316 with
  // stride = sqrt(g1)/4, and the sum takes ~80 terms for any g1 instead of ~20 sqrt(g1).
  // Beyond g1 = 1e18 (and the 64-bit index range) the window, of relative width 1/sqrt(g1) <= 1e-9,
  // is one point: the sum is (1 - e^-g1) outside_fraction(g1) up to f'' var / 2, relative
  // ~ a1 / g1^2 < 1e-22 (a1 = pi^2 (l_c/lambda)^2 <= 1e13).
  const double total_weight = -std::expm1(-g1);
  if (g1 > 1e18) return total_weight * outside_fraction(g1);
  const std::int64_t stride = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::sqrt(g1) / 4.0));
  const std::int64_t mode = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::floor(g1)));
  double sum = 0.0;
  for (const std::int64_t direction : {std::int64_t{+1}, std::int64_t{-1}}) {
    for (std::int64_t m = (direction > 0 ? mode : mode - stride); m >= 1; m += direction * stride) {
      const double weight = std::exp(detail::log_poisson_weight(m, g1)) * static_cast<double>(stride);
      sum += weight * outside_fraction(static_cast<double>(m));
      // "Not above" rather than "below": for g1 ~ 1e-310 the threshold underflows to 0, and so do
      // the weights past m = 1; "below 0" never came (sigma_s = 1e-160 um hung here).
      if (!(weight > 1e-17 * total_weight) && (direction < 0 || static_cast<double>(m) > g1)) break;
    }
  }
  return sum;
}

// The surface K is computed for. Below sigma_s/lambda = kLinearSigmaOverLambda (g < 2e-38) the
// disk and outside integrals are linear in g to double precision (the m = 1 term; the mass of
// term m is O(g^(m-1)) smaller) and K, their ratio, no longer depends on sigma_s. It is computed
// at that sigma_s: at the true one the whole quadrature ran in denormal numbers (27x slower; a K
// table at sigma_s = 1e-160 um took minutes).
constexpr double kLinearSigmaOverLambda = 1e-20;
Surface k_surface(const Surface& surface) {
  Surface s = surface;
  if (s.sigma_s_um > 0.0 && s.sigma_s_um < kLinearSigmaOverLambda * s.wavelength_um)
    s.sigma_s_um = kLinearSigmaOverLambda * s.wavelength_um;
  return s;
}

}  // namespace

RenormalizationParts renormalization_direct(const Surface& true_surface, double theta_i, KMode mode,
                                            const RenormalizationQuadrature& quadrature) {
  validate_surface(true_surface);
  if (!std::isfinite(theta_i) || theta_i < 0.0 || theta_i > 0.5 * kPi)
    throw InvalidArgument("theta_i", "must be in [0, 90] degrees for K");
  RenormalizationParts parts;
  const double ci = std::cos(theta_i);
  parts.total_scatter = -std::expm1(-roughness_g(true_surface.sigma_over_lambda(), ci, ci));
  if (true_surface.sigma_s_um == 0.0) return parts;  // no scatter: K = 1 by convention
  const Surface surface = k_surface(true_surface);
  // disk and outside scale like g ~ sigma_s^2 where k_surface changed sigma_s.
  const double ratio = true_surface.sigma_s_um / surface.sigma_s_um, scale = ratio * ratio;
  const std::vector<AzimuthNode> azimuths = half_disk_azimuth_nodes(quadrature, theta_i);
  parts.disk = disk_integral(surface, theta_i, azimuths, quadrature);
  if (!(parts.disk > 0.0)) return parts;  // nothing scattered into the disk at all: K = 1
  if (mode == KMode::plane) {
    const double outside = outside_integral(surface, theta_i, azimuths);
    parts.k = 1.0 + outside / parts.disk;  // eq. 13 with the plane read of conventions.md
    parts.outside = outside * scale;
  } else {
    // TIS renormalization (Krywonos et al. 2011), both parts at the surface of the quadrature.
    parts.k = -std::expm1(-roughness_g(surface.sigma_over_lambda(), ci, ci)) / parts.disk;
  }
  parts.disk *= scale;
  return parts;
}

namespace {
// Node placement: uniform in the node coordinate u = 1 - sqrt(cos theta_i) in [0, 1], which
// needs no inverse trigonometry (the span lookup takes cos theta_i from the geometry: one square
// root per query instead of an arctangent and an arcsine). Near grazing 1 - u = sqrt(cos theta_i)
// ~ sqrt(90 deg - theta_i): the spacing shrinks like that square root, which resolves a narrow lobe
// crossing the unit circle (structure over ~sqrt(2 / (pi l_c/lambda)) rad below 90 deg). Near
// normal incidence u ~ theta_i^2 / 4, and the tabulated factors, even in theta_i, are smooth
// functions of theta_i^2, hence of u (one-sided slopes there: no mirror symmetry in u).
double node_angle(double u) { return std::acos((1.0 - u) * (1.0 - u)); }

// Cubic Hermite slopes (per unit of node index) with fourth-order central differences, and
// one-sided fourth-order differences at the two nodes nearest either end.
std::vector<double> hermite_slopes(const std::vector<double>& f) {
  const int n = static_cast<int>(f.size());
  std::vector<double> slope(n);
  for (int i = 0; i < n; ++i) {
    if (i >= 2 && i + 2 < n) {
      slope[i] = (-f[i + 2] + 8.0 * f[i + 1] - 8.0 * f[i - 1] + f[i - 2]) / 12.0;
      continue;
    }
    // At the start (i = 0, 1) the nodes i, i+1, ... forward; at the end, i, i-1, ... backward
    // (the backward slope is the forward formula's with its sign turned).
    const bool start = i < 2;
    const int direction = start ? 1 : -1, k = start ? i : n - 1 - i;  // k: 0 at the end node, 1 beside it
    const int base = start ? 0 : n - 1;
    auto at = [&](int j) { return f[base + direction * j]; };
    const double one_sided = k == 0 ? (-25.0 * at(0) + 48.0 * at(1) - 36.0 * at(2) + 16.0 * at(3) - 3.0 * at(4)) / 12.0
                                    : (-3.0 * at(0) - 10.0 * at(1) + 18.0 * at(2) - 6.0 * at(3) + at(4)) / 12.0;
    slope[i] = direction * one_sided;
  }
  return slope;
}

// The cubic Hermite interpolant at t in [0, 1] of values f0, f1 and slopes s0, s1 (per cell).
double hermite_cell(double f0, double s0, double f1, double s1, double t) {
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  return h00 * f0 + h10 * s0 + h01 * f1 + h11 * s1;
}

double hermite(const std::vector<double>& f, const std::vector<double>& slope, double x) {
  const int i = std::min(static_cast<int>(x), static_cast<int>(f.size()) - 2);
  return hermite_cell(f[i], slope[i], f[i + 1], slope[i + 1], x - i);
}
}  // namespace

int RenormalizationTable::automatic_node_count(const Surface& surface) {
  // The lobe (width 1/(pi l_c/lambda) in direction cosines) crosses the unit circle within
  // ~sqrt(2 width) rad of 90 deg, i.e. within 1 - u = sqrt(cos theta_i) ~ (2 width)^(1/4) of the
  // last node; 24 nodes per that distance keep the interpolation error ~1e-5 (l_c/lambda = 100, 1000).
  const double width = 1.0 / (kPi * surface.lc_over_lambda());
  const double grazing_band = std::sqrt(std::sqrt(2.0 * width));
  return static_cast<int>(std::clamp(std::ceil(24.0 / grazing_band) + 1.0, double(kDefaultNodes), 4001.0));
}

// K itself is steep near grazing (K - 1 and K_tis both vanish like cos^2 theta_i at 90 deg), so the
// table holds the smooth factors instead and rebuilds K from them with the exact g(theta_i):
//   ln D(ti)                             the disk integral (a smooth, positive function)
//   r(ti) = outside / (1 - e^-g1)        the fraction of the constant-g1 lobe outside the disk
//   plane: K = 1 + (1 - e^-g1) r / D;    tis: K = (1 - e^-g(ti,ti)) / D
RenormalizationTable::RenormalizationTable(const Surface& true_surface, KMode mode, int requested_nodes)
    : mode_(mode), surface_(k_surface(true_surface)) {
  validate_surface(true_surface);
  const Surface& surface = surface_;  // K of a sigma_s below kLinearSigmaOverLambda is K there
  if (requested_nodes != 0 && requested_nodes < 8)
    throw InvalidArgument("nodes", "K table needs at least 8 nodes (or 0 = automatic)");
  const int nodes = requested_nodes == 0 ? automatic_node_count(surface) : requested_nodes;
  angles_.resize(nodes);
  k_.assign(nodes, 1.0);
  scale_ = nodes - 1;
  for (int i = 0; i < nodes; ++i) angles_[i] = node_angle(i / scale_);
  angles_[nodes - 1] = 0.5 * kPi;
  if (surface.sigma_s_um == 0.0) return;  // a mirror: K = 1 everywhere
  std::vector<double> disk(nodes), outside(nodes);
  tbb::parallel_for(0, nodes, [&](int i) {
    // The grazing node is taken just inside 90 deg, where g1 > 0 keeps r = outside / (1 - e^-g1)
    // a ratio of nonzero numbers (its limit at 90 deg).
    const double ti = std::min(angles_[i], 0.5 * kPi - 1e-6);
    const RenormalizationParts parts = renormalization_direct(surface, ti, KMode::plane);
    disk[i] = parts.disk;
    const double g1 = roughness_g(surface.sigma_over_lambda(), std::cos(ti), 0.0);
    outside[i] = g1 > 0.0 ? parts.outside / -std::expm1(-g1) : 0.0;
  });
  if (!std::all_of(disk.begin(), disk.end(), [](double d) { return d > 0.0; })) {
    // Scatter underflows somewhere (no lobe at all): fall back to K at the nodes, linearly.
    for (int i = 0; i < nodes; ++i) k_[i] = renormalization_direct(surface, angles_[i], mode).k;
    linear_only_ = true;
    return;
  }
  log_disk_.resize(nodes);
  for (int i = 0; i < nodes; ++i) log_disk_[i] = std::log(disk[i]);
  outside_fraction_ = std::move(outside);
  log_disk_slope_ = hermite_slopes(log_disk_);
  outside_fraction_slope_ = hermite_slopes(outside_fraction_);
  // The evaluation grid: q from the smooth factors at every dense node (the coarse nodes among
  // them), Hermite slopes by the same fourth-order differences. q is smooth in u up to grazing.
  const int refinement = std::max(kDenseRefinement, (kDenseMinNodes + nodes - 2) / (nodes - 1));
  const int dense_nodes = refinement * (nodes - 1) + 1;
  dense_scale_ = dense_nodes - 1;
  std::vector<double> dense_q(dense_nodes);
  for (int j = 0; j < dense_nodes; ++j) dense_q[j] = q_from_smooth_factors(j / dense_scale_);
  const std::vector<double> dense_slope = hermite_slopes(dense_q);
  dense_nodes_ = dense_nodes;
  dense_.assign(2 * static_cast<std::size_t>(dense_nodes), 0.0);
  for (int j = 0; j < dense_nodes; ++j) dense_[2 * j] = dense_q[j], dense_[2 * j + 1] = dense_slope[j];
  // Plane mode reads K = 1 + cos^2 ti q: a q or slope below kNegligibleQ changes no bit of K, and
  // such values (down to subnormals where the outside fraction underflows: l_c/lambda = 40 has
  // K = 1 exactly up to ~45 deg) make the lookups' arithmetic take microcode assists. They are
  // stored as 0. K span lookups, 256-query blocks, one CPU: 10.8 -> 4.2 ns per query at sigma_s =
  // 0.005 um, l_c = 20 um, lambda = 0.5 um (5.3 -> 4.2 at l_c/lambda = 500), as fast as at l_c = 2
  // um; mbk there 27.3 -> 19.9 ns (`brdf eval --timing` minus g, same run). K bit-identical (8
  // surfaces, direct and table, both modes); mbk md5-identical.
  if (mode_ == KMode::plane)
    for (double& value : dense_)
      if (std::abs(value) < kNegligibleQ) value = 0.0;
  for (int i = 0; i < nodes; ++i) k_[i] = (*this)(angles_[i]);
}

namespace {
// -expm1(-y) / y, -> 1 as y -> 0: the factor (1 - e^-g) / g of a g that vanishes at grazing.
double one_minus_exp_ratio(double y) { return y == 0.0 ? 1.0 : -std::expm1(-y) / y; }
}  // namespace

double RenormalizationTable::q_from_smooth_factors(double u) const {
  const double x = u * scale_;
  const double disk = std::exp(hermite(log_disk_, log_disk_slope_, x));
  const double ci2 = (1.0 - u) * (1.0 - u) * (1.0 - u) * (1.0 - u);  // cos^2 theta_i
  const double k2 = roughness_g(surface_.sigma_over_lambda(), 1.0, 0.0);  // (2 pi sigma_s/lambda)^2, eq. 12
  // tis: K = (1 - e^-g(ti, ti)) / D, g(ti, ti) = 4 k2 cos^2 ti.
  if (mode_ == KMode::tis) return 4.0 * k2 * one_minus_exp_ratio(4.0 * k2 * ci2) / disk;
  // plane: K - 1 = (1 - e^-g1) r / D, g1 = k2 cos^2 ti. r >= 0 by definition; at the foot of its
  // rise (narrow lobes, far from grazing, r ~ 0) the cubic can dip below 0 by its interpolation
  // error, which must not turn into K < 1 (eq. 13: K >= 1).
  const double outside = std::max(0.0, hermite(outside_fraction_, outside_fraction_slope_, x));
  return k2 * one_minus_exp_ratio(k2 * ci2) * outside / disk;
}

double RenormalizationTable::operator()(double theta_i) const {
  if (surface_.sigma_s_um == 0.0) return 1.0;
  const double ci = std::clamp(std::cos(theta_i), 0.0, 1.0);
  const double u = 1.0 - std::sqrt(ci);  // the node coordinate
  if (linear_only_) {
    const double x = u * scale_;
    const int i = std::min(static_cast<int>(x), static_cast<int>(k_.size()) - 2);
    return k_[i] + (x - i) * (k_[i + 1] - k_[i]);
  }
  const double x = u * dense_scale_;
  const int j = std::min(static_cast<int>(x), dense_nodes_ - 2);
  const double* cell = &dense_[2 * static_cast<std::size_t>(j)];  // (q, q') of nodes j, j + 1
  const double q = std::max(0.0, hermite_cell(cell[0], cell[1], cell[2], cell[3], x - j));
  return (mode_ == KMode::plane ? 1.0 : 0.0) + ci * ci * q;
}

void RenormalizationTable::at_geometries(const ScatterGeometry* geos, std::size_t count, double* k) const {
  if (surface_.sigma_s_um == 0.0 || linear_only_) {  // the rare tables without the smooth factors
    for (std::size_t j = 0; j < count; ++j) k[j] = (*this)(std::atan2(geos[j].sin_theta_i, geos[j].cos_theta_i));
    return;
  }
  const detail::KTableView view{dense_.data(), dense_nodes_, dense_scale_, mode_ == KMode::plane ? 1.0 : 0.0};
  detail::renormalization_span(view, geos, count, k);
}

std::shared_ptr<const RenormalizationTable> cached_renormalization_table(const Surface& surface, KMode mode) {
  using Key = std::tuple<double, double, int>;
  static std::mutex mutex;
  static std::map<Key, std::shared_ptr<const RenormalizationTable>> cache;
  const Key key{k_surface(surface).sigma_over_lambda(), surface.lc_over_lambda(), static_cast<int>(mode)};
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto it = cache.find(key);
    if (it != cache.end()) return it->second;
  }
  auto table = std::make_shared<const RenormalizationTable>(surface, mode);
  std::lock_guard<std::mutex> lock(mutex);
  return cache.emplace(key, std::move(table)).first->second;
}

}  // namespace libbrdf
