#pragma once
// The universal MBK kernel table: Sigma(g, c) of eq. 11 (mbk_series.h),
//
//   Sigma(g, c) = sum_{m >= 1} e^-g g^m / (m! m) e^(-c/m),
//   g = (2 pi sigma_s / lambda)^2 (cos ti + cos ts)^2        (eq. 12)
//   c = pi^2 (l_c / lambda)^2 eta_r^2                         (eq. 10, 11)
//
// depends on no material, wavelength or surface: every ASF model (asf, mbk, mbk-fg, bk,
// bk-modified) is (K) x (angular factor) x (pi l_c^2/lambda^2) x Sigma(g, c), so one table serves
// them all. It is generated once per process at first use (multi-threaded; 84k nodes by the SIMD
// series' moments: ~42 ms of CPU, build_seconds() reports the wall time) -- not shipped as a file.
//
// Grid (also written into kernel-layout LUT files):
//   x = ln g                 nodes x_i = kKernelXMin + i dx, i = 0 .. kKernelNx - 1
//   z = sqrt(c / (g + 1))    nodes z_j = j dz,               j = 0 .. kKernelNz - 1
// z makes both ends smooth: for g >> 1, ln Sigma ~ -ln g - z^2 (a Gaussian in eta_r); for g << 1
// the dominant term index m changes where c ~ m(m+1) ln(1/g), evenly spaced in sqrt(c). ln Sigma is
// even in z (c = (g+1) z^2), so z = 0 is a symmetry line, not an edge.
// Each node holds F = ln Sigma and its exact derivatives F_x, F_z, F_xz (from moments of the
// series, not finite differences); lookups are bicubic Hermite in (x, z), then exp.
#include <cstddef>
#include <vector>

namespace libbrdf {

inline constexpr double kKernelGMin = 1e-5;    // table domain in g (outside: closed forms or series)
inline constexpr double kKernelGMax = 1e7;
inline constexpr double kKernelZMax = 30.0;    // c / (g + 1) <= 900: values down to ~e^-900 of the peak
inline constexpr int kKernelNodesPerUnitX = 10;  // dx = 1/10 in ln g
inline constexpr int kKernelNodesPerUnitZ = 10;  // dz = 1/10

// The largest relative error of KernelTable::sigma against the series over its domain, measured
// by a dense sweep (tests/cpp/test_kernel_table.cpp asserts it; `brdf bench` reports it). The
// automatic method choice (asf_auto) uses the table only where the caller's tolerance is >= this.
inline constexpr double kKernelTableCertifiedError = 1e-4;

class KernelTable {
 public:
  // The process-wide table, built on first use (thread-safe).
  static const KernelTable& instance();

  // True when (g, c) lies inside the table: kKernelGMin <= g <= kKernelGMax, z <= kKernelZMax.
  bool contains(double g, double c) const {  // inline: asf_auto_batch asks it for every query
    return g >= kKernelGMin && g <= kKernelGMax && c >= 0.0 && c <= kKernelZMax * kKernelZMax * (g + 1.0);
  }
  // Sigma(g, c) by bicubic Hermite interpolation of ln Sigma; only for contains(g, c).
  double sigma(double g, double c) const;
  // sigma[k] = sigma(g[k], c[k]) for k < count, one query per SIMD lane (gathers); the same
  // interpolation up to rounding. Every (g[k], c[k]) must be inside (contains).
  void sigma_many(const double* g, const double* c, std::size_t count, double* sigma) const;

  int nx() const { return nx_; }
  int nz() const { return nz_; }
  double x_min() const { return x_min_; }
  double dx() const { return dx_; }
  double dz() const { return dz_; }
  // Node data: 4 doubles per node (F, F_x, F_z, F_xz), node (i, j) at index 4 (i nz + j).
  const std::vector<double>& nodes() const { return nodes_; }
  std::size_t bytes() const { return nodes_.size() * sizeof(double); }
  // Wall time the build took in this process (s).
  double build_seconds() const { return build_seconds_; }

 private:
  KernelTable();
  int nx_ = 0, nz_ = 0;
  double x_min_ = 0.0, dx_ = 0.0, dz_ = 0.0;
  std::vector<double> nodes_;
  double build_seconds_ = 0.0;
};

}  // namespace libbrdf
