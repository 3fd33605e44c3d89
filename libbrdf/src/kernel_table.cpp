// The universal kernel table of Sigma(g, c) (kernel_table.h): node values of ln Sigma and its
// edge derivatives from the reference series' moments, turned into clamped bicubic spline
// coefficients (at build time, into the library: kernel_table_file.h), looked up as a B-spline.
#include "libbrdf/kernel_table.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "asf_lanes.h"
#include "kernel_table_file.h"
#include "poisson.h"

namespace libbrdf {
namespace {

// ln Sigma and its derivatives in (x = ln g, z = sqrt(c/(g+1))) at one node, from the moments
// a..e of the series (poisson.h). With S = sum t_m, dt_m/dg = t_m (m/g - 1), dt_m/dc = -t_m/m and
// c = (g + 1) z^2 (so dc/dx at fixed z = g z^2, dc/dz at fixed x = 2 (g + 1) z):
//   F_x  = (b - g z^2 c) / a
//   F_z  = -2 (g + 1) z c / a
//   F_xz = 2 z [ -g c / a + (g + 1) ( (-d + g z^2 e) / a + c (b - g z^2 c) / a^2 ) ]
// (a far node's w = ln(z / kKernelZNear) has dz/dw = z: F_w = z F_z, F_xw = z F_xz).
void node_values(double x, double z, double* out) {
  const double g = std::exp(x), c = (g + 1.0) * z * z;
  const detail::SeriesMoments m = detail::series_moments(g, c);
  const double inv_a = 1.0 / m.a;
  const double gz2 = g * z * z;
  const double fx_num = m.b - gz2 * m.c;
  out[0] = m.log_scale + std::log(m.a);
  out[1] = fx_num * inv_a;
  out[2] = -2.0 * (g + 1.0) * z * m.c * inv_a;
  out[3] = 2.0 * z * (-g * m.c * inv_a + (g + 1.0) * ((-m.d + gz2 * m.e) * inv_a + m.c * fx_num * inv_a * inv_a));
}

// The clamped cubic spline through f[0 .. n) on unit-spaced nodes, as cubic B-spline coefficients
// c[0 .. n + 2) (c[k] multiplies the B-spline centred on node k - 1), with end slopes slope0,
// slope1 (per node spacing). Interpolation: f_j = (c_j + 4 c_{j+1} + c_{j+2}) / 6; the slopes:
// slope = (c_{j+2} - c_j) / 2 at j = 0 and n - 1. Eliminating c_0 and c_{n+1} leaves a tridiagonal
// system in c_1 .. c_n, strictly diagonally dominant (4 against 1 + 1, or 2 at the ends), solved by
// elimination without pivoting. n >= 2.
void clamped_cubic_spline(const double* f, int n, double slope0, double slope1, double* c) {
  // Off the diagonal 1/6, but 2/6 above it in the first row and below it in the last.
  auto above = [](int j) { return j == 0 ? 2.0 / 6.0 : 1.0 / 6.0; };
  auto below = [n](int j) { return j == n - 1 ? 2.0 / 6.0 : 1.0 / 6.0; };
  std::vector<double> diagonal(n, 4.0 / 6.0), rhs(f, f + n);
  rhs[0] += slope0 / 3.0;
  rhs[n - 1] -= slope1 / 3.0;
  for (int j = 1; j < n; ++j) {
    const double factor = below(j) / diagonal[j - 1];
    diagonal[j] -= factor * above(j - 1);
    rhs[j] -= factor * rhs[j - 1];
  }
  c[n] = rhs[n - 1] / diagonal[n - 1];
  for (int j = n - 2; j >= 0; --j) c[j + 1] = (rhs[j] - above(j) * c[j + 2]) / diagonal[j];
  c[0] = c[2] - 2.0 * slope0;
  c[n + 1] = c[n - 1] + 2.0 * slope1;
}

// The uniform cubic B-spline's weights at offset t in [0, 1) of a cell, for the coefficients of
// the nodes one before, at, after and two after the cell's first node.
void cubic_bspline_weights(double t, double* w) {
  const double u = 1.0 - t, t2 = t * t, t3 = t2 * t;
  w[0] = u * u * u / 6.0;
  w[1] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
  w[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
  w[3] = t3 / 6.0;
}

const KernelTableSpec& spec_of(KernelTable::Tier tier) {
  return tier == KernelTable::Tier::fine ? kKernelTableFine : kKernelTableCoarse;
}

}  // namespace

KernelGrid KernelGrid::of(const KernelTableSpec& spec) {
  KernelGrid grid;
  grid.x_min = std::log(kKernelGMin);
  grid.dx = 1.0 / spec.nodes_per_unit_x;
  grid.dz = 1.0 / spec.nodes_per_unit_z;
  grid.dw = 1.0 / spec.nodes_per_unit_w;
  // One cell beyond each end so that every in-domain query has a full cell.
  grid.nx = static_cast<int>(std::ceil((std::log(kKernelGMax) - grid.x_min) / grid.dx)) + 2;
  grid.nz = static_cast<int>(std::ceil(kKernelZNear / grid.dz)) + 2;
  grid.nw = static_cast<int>(std::ceil(std::log(kKernelZFar / kKernelZNear) / grid.dw)) + 2;
  return grid;
}

std::vector<double> KernelTable::compute_coefficients(Tier tier) {
  const KernelGrid grid = KernelGrid::of(spec_of(tier));
  std::vector<double> coefficients(grid.values(), 0.0);
  // One section (near: v = z, far: v = w): node values (F, F_x, F_v, F_xv) in v, then the spline
  // along v in every row (F, with F_v at the row's ends; F_x too in the first and last rows, with
  // F_xv: the x-slopes of the column splines below), then along x in every column of those
  // coefficients. A tensor product of clamped splines is the clamped bicubic spline.
  auto section = [&](bool far, double* out) {
    const int n = far ? grid.nw : grid.nz;
    const double dv = far ? grid.dw : grid.dz;
    const std::size_t row = grid.row_length(far);
    std::vector<double> along_v(grid.nx * row), x_slope_first(row), x_slope_last(row);
    tbb::parallel_for(tbb::blocked_range<int>(0, grid.nx), [&](const tbb::blocked_range<int>& rows) {
      std::vector<double> f(n), node(4 * static_cast<std::size_t>(n));
      for (int i = rows.begin(); i != rows.end(); ++i) {
        double* const values = node.data();  // (F, F_x, F_v, F_xv) of the row's nodes
        for (int j = 0; j < n; ++j) {
          const double z = far ? kKernelZNear * std::exp(j * grid.dw) : j * grid.dz;
          node_values(grid.x_min + i * grid.dx, z, values + 4 * j);
          if (far) values[4 * j + 2] *= z, values[4 * j + 3] *= z;  // d/dw = z d/dz
        }
        for (int j = 0; j < n; ++j) f[j] = values[4 * j];
        clamped_cubic_spline(f.data(), n, dv * values[2], dv * values[4 * (n - 1) + 2], &along_v[i * row]);
        if (i == 0 || i == grid.nx - 1) {
          for (int j = 0; j < n; ++j) f[j] = values[4 * j + 1];
          clamped_cubic_spline(f.data(), n, dv * values[3], dv * values[4 * (n - 1) + 3],
                               i == 0 ? x_slope_first.data() : x_slope_last.data());
        }
      }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, row), [&](const tbb::blocked_range<std::size_t>& columns) {
      std::vector<double> f(grid.nx), c(grid.rows());
      for (std::size_t q = columns.begin(); q != columns.end(); ++q) {
        for (int i = 0; i < grid.nx; ++i) f[i] = along_v[i * row + q];
        clamped_cubic_spline(f.data(), grid.nx, grid.dx * x_slope_first[q], grid.dx * x_slope_last[q], c.data());
        for (std::size_t r = 0; r < grid.rows(); ++r) out[r * row + q] = c[r];
      }
    });
  };
  section(false, coefficients.data());
  section(true, coefficients.data() + grid.far_section_offset());
  return coefficients;
}

const KernelTable& KernelTable::instance(Tier tier) {
  static const KernelTable fine(Tier::fine), coarse(Tier::coarse);  // C++11: thread-safe initialisation
  return tier == Tier::fine ? fine : coarse;
}

const KernelTable* KernelTable::for_tolerance(double tolerance) {
  if (tolerance >= kKernelTableCoarse.certified_error) return &instance(Tier::coarse);
  if (tolerance >= kKernelTableFine.certified_error) return &instance(Tier::fine);
  return nullptr;
}

KernelTable::KernelTable(Tier tier) : tier_(tier), spec_(spec_of(tier)) {
  const auto start = std::chrono::steady_clock::now();
  grid_ = KernelGrid::of(spec_);
  const detail::EmbeddedKernelTable file = detail::embedded_kernel_table();
  if (file.data == nullptr) {  // the generator itself
    computed_ = compute_coefficients(tier);
    coefficients_ = computed_.data();
  } else {
    // The embedded file holds every tier's section in order; each must be its grid's: a mismatch
    // is a stale build, never a table to use.
    std::size_t offset = 0;
    bool matches = true;
    for (const Tier section : detail::kKernelTableTiers) {
      detail::KernelTableFileHeader header;
      const KernelGrid expected = KernelGrid::of(spec_of(section));
      const std::size_t values = expected.values();
      matches = matches && file.size >= offset + sizeof header;
      if (!matches) break;
      std::memcpy(&header, file.data + offset, sizeof header);
      matches = std::memcmp(header.magic, detail::kKernelTableMagic, sizeof header.magic) == 0 && header.nx == expected.nx &&
                header.nz == expected.nz && header.nw == expected.nw && header.x_min == expected.x_min &&
                header.dx == expected.dx && header.dz == expected.dz && header.dw == expected.dw &&
                header.spline_border == expected.kSplineBorder && header.values == values &&
                file.size >= offset + sizeof header + values * sizeof(double);
      if (!matches) break;
      if (section == tier) coefficients_ = reinterpret_cast<const double*>(file.data + offset + sizeof header);
      offset += sizeof header + values * sizeof(double);
    }
    if (!matches || offset != file.size)
      throw std::logic_error("libbrdf: the embedded kernel tables do not match kernel_table.h's grids (stale build: rebuild libbrdf)");
  }
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double KernelTable::sigma(double g, double c) const { return std::exp(log_sigma(g, c)); }

double KernelTable::scaled_sigma(double g, double c, double scale) const {
  return std::exp(log_sigma(g, c) + std::log(scale));
}

double KernelTable::log_sigma(double g, double c) const {
  const double z = std::sqrt(c / (g + 1.0));
  if (z > kKernelZFar) return -std::numeric_limits<double>::infinity();  // Sigma < e^-745 there (kernel_table.h)
  const bool far = z > kKernelZNear;
  const double u_x = (std::log(g) - grid_.x_min) / grid_.dx;
  // The cell's column j in its section and the offset t in it: near in z, far in w = ln(z / kKernelZNear).
  const double u_v = far ? std::log(z / kKernelZNear) / grid_.dw : z / grid_.dz;
  const int row_nodes = far ? grid_.nw : grid_.nz;
  const std::size_t row = grid_.row_length(far);
  const double* section = far ? coefficients_ + grid_.far_section_offset() : coefficients_;
  const int i = std::min(static_cast<int>(u_x), grid_.nx - 2);
  const int j = std::min(static_cast<int>(u_v), row_nodes - 2);
  double wx[4], wv[4];
  cubic_bspline_weights(u_x - i, wx);
  cubic_bspline_weights(u_v - j, wv);
  double f = 0.0;
  for (int a = 0; a < 4; ++a) {  // stencil rows i .. i + 3, columns j .. j + 3 (kernel_table.h)
    const double* r = section + (static_cast<std::size_t>(i) + a) * row + j;
    f += wx[a] * (wv[0] * r[0] + wv[1] * r[1] + wv[2] * r[2] + wv[3] * r[3]);
  }
  return f;
}

std::size_t KernelTable::scaled_sigma_inside(const double* g, const double* c, std::size_t count, double scale, double* out,
                                             std::uint32_t* outside, const double* ln_g) const {
  return detail::kernel_table_lanes(detail::KernelTableView{coefficients_, grid_}, g, c, ln_g, count, scale, out, outside);
}

void KernelTable::sigma_many(const double* g, const double* c, std::size_t count, double* sigma) const {
  constexpr std::size_t kChunk = 1024;
  std::uint32_t outside[kChunk];
  for (std::size_t begin = 0; begin < count; begin += kChunk) {
    const std::size_t n = std::min(kChunk, count - begin);
    const std::size_t left = scaled_sigma_inside(g + begin, c + begin, n, 1.0, sigma + begin, outside);
    for (std::size_t j = 0; j < left; ++j) sigma[begin + outside[j]] = std::numeric_limits<double>::quiet_NaN();
  }
}

}  // namespace libbrdf
