#pragma once
// The universal MBK kernel table: Sigma(g, c) of eq. 11 (mbk_series.h),
//
//   Sigma(g, c) = sum_{m >= 1} e^-g g^m / (m! m) e^(-c/m),
//   g = (2 pi sigma_s / lambda)^2 (cos ti + cos ts)^2        (eq. 12)
//   c = pi^2 (l_c / lambda)^2 eta_r^2                         (eq. 10, 11)
//
// depends on no material, wavelength or surface: every ASF model (asf, mbk, mbk-fg, bk,
// bk-modified) is (K) x (angular factor) x (pi l_c^2/lambda^2) x Sigma(g, c), so one table serves
// them all. Its coefficients (two tiers below) are computed once, at build time, from the series'
// moments (tools/generate_kernel_table.cpp, ~0.5 s of CPU) and assembled into the library
// (kernel_table_data.S): a process pays nothing to start it. compute_coefficients() recomputes them;
// a test asserts that the embedded tables are that result bit for bit.
//
// Grid (described in kernel-layout LUT files' metadata): a near section, uniform in z, and a far
// section, uniform in w = ln(z / kKernelZNear), each a block of rows (KernelGrid below):
//   x = ln g                 nodes x_i = ln kKernelGMin + i dx,              i = 0 .. nx - 1
//   z = sqrt(c / (g + 1))    near: z_j = j dz,                                j = 0 .. nz - 1
//                            far:  z_k = kKernelZNear e^(k dw),               k = 0 .. nw - 1
// z makes both ends smooth: for g >> 1, ln Sigma ~ -ln g - z^2 (a Gaussian in eta_r); for g << 1
// the dominant term index m changes where c ~ m(m+1) ln(1/g), evenly spaced in sqrt(c). ln Sigma is
// even in z (c = (g+1) z^2), so z = 0 is a symmetry line, not an edge. Beyond kKernelZNear the
// switches of m spread over ~z / (2 ln 1/g) in z (a width growing with z), so the far section's
// nodes are spaced evenly in ln z.
//
// Representation: per section, the clamped bicubic spline of F = ln Sigma in (x, v) (v = z near,
// w far): the tensor-product cubic B-spline that takes the node values of F, with the exact
// derivatives of the series (moments, not finite differences) at the section's edges: F_v at both
// ends of every row, F_x at the first and last rows, F_xv at the corners. A lookup is 4 x 4
// coefficients times the B-spline weights of its cell, then exp. It stores one double per node
// where bicubic Hermite (until stop 28) stored four (F, F_x, F_v, F_xv), which it needs at every node
// for the same O(h^4) error: the spline's slopes at the nodes are themselves O(h^4) accurate, so its
// error has Hermite's leading term. Measured on the fine grid, same sweep (every sixth row of near
// cells, 159468 points): max 2.71e-7 both, per decade of g the two within 1.5% of each other.
// 8x fewer bytes than Hermite's paired nodes: a polished surface's band of the fine table
// (sigma_s/lambda = 0.01: g < 0.016, z < 25, ~148 x 750 nodes) was ~7 MB and is now ~0.9 MB, and
// the pages a process first touches go down as much (docs/performance.md, "Fast core").
#include <cstddef>
#include <cstdint>
#include <vector>

namespace libbrdf {

inline constexpr double kKernelGMin = 1e-5;    // table domain in g (outside: closed forms or series)
inline constexpr double kKernelGMax = 1e7;
inline constexpr double kKernelZNear = 30.0;   // end of the near section (uniform in z)
// End of the far section. Beyond it Sigma < e^-745 for every g of the table (the largest z where
// ln Sigma = -745 is ~153, at g ~ 0.2; test_kernel_table.cpp asserts ln Sigma < -745 at kKernelZFar
// over the g range), and Sigma decreases with c (every term does): lookups there return 0, as the
// series does below e^-745. Before the far section (z <= 30 only), surfaces with l_c >> sigma_s
// sent most of their queries to the series (`brdf eval --timing`, asf minus g, 1e6 queries, same
// run, before -> after): sigma_s = 0.005 um, l_c = 20 um, lambda = 0.5 um: 44.2 -> 13.6 ns;
// 0.05, 5, 0.5: 21.5 -> 10.8 ns; 0.3, 10, 0.6: 14.1 -> 10.6 ns. The three surfaces, which
// do not reach it, pay ~0-0.5 ns per query for the test (within this machine's noise).
inline constexpr double kKernelZFar = 170.0;
// Two tables of Sigma on that grid, at two certified errors (tolerance tiers): the fine one for the
// default tolerance, 1e-6, and a coarse one, 6x fewer nodes, for tolerances >= 1e-4
// (`bench/bench_eval`, asf minus g, p10, two runs: 3.9-4.2 ns at 1e-6, 3.7-3.9 ns at 1e-4; with
// Hermite nodes it was 5.4-6.0 against 4.1-4.4, the fine tier's band then past L2). The bicubic
// error goes as h^4. In z it is largest at small g, where the dominant term m -> m + 1
// switches within ~(m + 1/2) / (2 sqrt(ln 1/g)) in z (0.15 at g = 1e-5); in x at large g and z.
// Measured max (the sweep below): dz = dx = 1/10: 2.1e-5 (at g = 1.3e-5, z = 5.05); 1/20, 1/25:
// 4.6e-7 (g ~ 1e-5); 1/20, 1/30: 2.7e-7. 1/10 x 1/8 would be ~5e-5 (h^4), without the margin of 2.
// Far section: dw = 1/150 with dx = 1/20: 3.0e-7 (at g = 0.19, z = 142); 1/50 with 1/10: 1.8e-5
// (g = 1.05e-5, z = 32). These were measured with Hermite nodes. The spline, landed grids: fine
// 2.7e-7 near, 3.0e-7 far; coarse 2.4e-5 near (g = 1.3e-5, z = 5.05), 2.4e-5 far.
// Sizes: fine 555 x (902 + 263) nodes, 5.2 MB of coefficients (41.4 MB of paired Hermite nodes
// before); coarse 279 x (302 + 89), 0.9 MB (3.5 MB).
struct KernelTableSpec {
  int nodes_per_unit_x;    // dx = 1 / this, in ln g
  int nodes_per_unit_z;    // dz = 1 / this (near section)
  int nodes_per_unit_w;    // dw = 1 / this, in w = ln(z / kKernelZNear) (far section)
  // The largest relative error of KernelTable::sigma against the series over the domain, measured
  // by a dense sweep (tests/cpp/test_kernel_table.cpp asserts it with a margin of 2; `brdf bench`
  // reports it). The automatic method choice (asf_auto) uses a table only where the caller's
  // tolerance is >= this.
  double certified_error;
};
inline constexpr KernelTableSpec kKernelTableFine{20, 30, 150, 1e-6};
inline constexpr KernelTableSpec kKernelTableCoarse{10, 10, 50, 1e-4};
inline constexpr double kKernelTableCertifiedError = kKernelTableFine.certified_error;

// A tier's grid (the constants above with its KernelTableSpec's spacings) and the layout of its
// spline coefficients (KernelTable::coefficients()): per section, rows() rows of row_length(far)
// coefficients, one per node (nx rows; nz near, nw far per row) and kSplineBorder beyond each end
// of both axes (the clamped spline's); coefficient (r, q) belongs to node (r - 1, q - 1), so the stencil of cell (i, j) is rows i .. i + 3, columns
// j .. j + 3. The near section first, its coefficient (r, q) at r row_length(false) + q; then the
// far section's at far_section_offset() + r row_length(true) + q. Two blocks rather than rows of
// both: the near rows, where most surfaces' queries fall, keep their stride (rows of 1165 nodes:
// asf minus g 9.2 ns on the rough surface, against 7.9 ns in two blocks and 7.7 ns before the far
// section; `brdf eval --timing`, 6 rounds, same run, with Hermite nodes).
struct KernelGrid {
  int nx = 0, nz = 0, nw = 0;  // nodes along x; near and far section nodes per row
  double x_min = 0.0, dx = 0.0, dz = 0.0, dw = 0.0;
  static constexpr int kSplineBorder = 1;  // coefficients beyond each end of an axis (clamped cubic)
  static KernelGrid of(const KernelTableSpec& spec);
  std::size_t rows() const { return static_cast<std::size_t>(nx) + 2 * kSplineBorder; }
  std::size_t row_length(bool far) const { return static_cast<std::size_t>(far ? nw : nz) + 2 * kSplineBorder; }
  std::size_t far_section_offset() const { return rows() * row_length(false); }
  std::size_t values() const { return far_section_offset() + rows() * row_length(true); }
};

class KernelTable {
 public:
  enum class Tier { fine, coarse };
  // The process-wide tables: the ones embedded at build time, or (in the generator, which has
  // none) computed on first use. Thread-safe.
  static const KernelTable& instance(Tier tier = Tier::fine);
  // The table asf_auto uses at this tolerance: the coarsest whose certified error is <= it;
  // nullptr below the fine table's.
  static const KernelTable* for_tolerance(double tolerance);
  // A tier's spline coefficients from the series (multi-threaded), laid out as coefficients().
  static std::vector<double> compute_coefficients(Tier tier);

  // True when (g, c) lies inside the tables' domain: kKernelGMin <= g <= kKernelGMax, c >= 0 (up to
  // +Inf: beyond kKernelZFar the value is 0).
  bool contains(double g, double c) const {  // inline: asf_regime asks it for every scalar query
    return g >= kKernelGMin && g <= kKernelGMax && c >= 0.0;
  }
  // Sigma(g, c) by the bicubic spline of ln Sigma (0 beyond kKernelZFar); only for contains(g, c).
  double sigma(double g, double c) const;
  // scale Sigma(g, c) as e^(ln Sigma + ln scale), scale > 0 (asf_auto: the prefactor of eq. 11):
  // where Sigma alone is subnormal (ln Sigma < -708) but scale Sigma is not, it keeps full
  // precision, where sigma() times scale would keep only the subnormal's bits (a relative error of
  // 2.2e-6 seen at Sigma ~ 1e-313). The sum's rounding, <= |ln Sigma| eps ~ 1e-13 relative, is
  // below the interpolation's own rounding.
  double scaled_sigma(double g, double c, double scale) const;
  // sigma[k] = sigma(g[k], c[k]) for k < count, one query per SIMD lane (cell rows loaded per lane
  // and transposed); the same interpolation up to rounding. NaN where not contains(g[k], c[k]).
  void sigma_many(const double* g, const double* c, std::size_t count, double* sigma) const;
  // The same lookup for the queries inside, times `scale` as scaled_sigma (asf_auto_batch: the
  // prefactor of eq. 11): out[k] = scaled_sigma(g[k], c[k], scale) up to rounding where
  // contains(g[k], c[k]). Returns the number of queries
  // outside and their indices in outside[] (room for count; out[k] is unspecified there).
  // ln_g, if given: ln g[k], which the table's x coordinate is then read from instead of a
  // logarithm per query (callers with several wavelengths of one geometry share ln(cos ti + cos ts):
  // ln g = 2 ln(g_scale |cos ti + cos ts|), eq. 12). An error e in ln g moves ln Sigma by e times
  // d ln Sigma / d ln g, the index of the largest term: 1e-12 relative at most seen (rounding of
  // ln g ~1e-14, c <= 160; test_kernel_table.cpp), far below either tier's certified error.
  std::size_t scaled_sigma_inside(const double* g, const double* c, std::size_t count, double scale, double* out,
                                  std::uint32_t* outside, const double* ln_g = nullptr) const;

  Tier tier() const { return tier_; }
  const KernelTableSpec& spec() const { return spec_; }
  double certified_error() const { return spec_.certified_error; }
  const KernelGrid& grid() const { return grid_; }
  int nx() const { return grid_.nx; }
  int nz() const { return grid_.nz; }  // near section's nodes per row
  int nw() const { return grid_.nw; }  // far section's nodes per row
  double x_min() const { return grid_.x_min; }
  double dx() const { return grid_.dx; }
  double dz() const { return grid_.dz; }
  double dw() const { return grid_.dw; }
  // Spline coefficients, laid out as KernelGrid says.
  const double* coefficients() const { return coefficients_; }
  std::size_t value_count() const { return grid_.values(); }
  std::size_t bytes() const { return value_count() * sizeof(double); }
  // True when the coefficients are the library's embedded ones (no computation in this process).
  bool embedded() const { return computed_.empty(); }
  // Wall time this process spent on the table (s): ~0 when embedded.
  double build_seconds() const { return build_seconds_; }

 private:
  explicit KernelTable(Tier tier);
  // ln Sigma(g, c), the bicubic spline that sigma and scaled_sigma exponentiate
  // (-inf beyond kKernelZFar); only for contains(g, c).
  double log_sigma(double g, double c) const;
  Tier tier_;
  KernelTableSpec spec_;
  KernelGrid grid_;
  const double* coefficients_ = nullptr;
  std::vector<double> computed_;  // empty when embedded
  double build_seconds_ = 0.0;
};

}  // namespace libbrdf
