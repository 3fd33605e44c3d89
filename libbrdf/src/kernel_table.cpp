// The universal kernel table of Sigma(g, c) (kernel_table.h): computed from the reference series'
// moments (at build time, into the library: kernel_table_file.h), looked up by bicubic Hermite
// interpolation of ln Sigma.
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

const KernelTableSpec& spec_of(KernelTable::Tier tier) {
  return tier == KernelTable::Tier::fine ? kKernelTableFine : kKernelTableCoarse;
}

}  // namespace

namespace detail {
KernelGrid kernel_grid(const KernelTableSpec& spec) {
  KernelGrid grid;
  grid.x_min = std::log(kKernelGMin);
  grid.dx = 1.0 / spec.nodes_per_unit_x;
  grid.dz = 1.0 / spec.nodes_per_unit_z;
  grid.dw = 1.0 / spec.nodes_per_unit_w;
  // One cell beyond each end so that every in-domain query has a full cell.
  grid.nx = static_cast<int>(std::ceil((std::log(kKernelGMax) - grid.x_min) / grid.dx)) + 2;
  grid.nz = static_cast<int>(std::ceil(kKernelZNear / grid.dz)) + 2;
  grid.nw = static_cast<int>(std::ceil(std::log(kKernelZFar / kKernelZNear) / grid.dw)) + 2;
  grid.node_doubles = spec.node_doubles();
  return grid;
}
}  // namespace detail

std::vector<double> KernelTable::compute_nodes(Tier tier) {
  const detail::KernelGrid grid = detail::kernel_grid(spec_of(tier));
  const std::size_t slot = static_cast<std::size_t>(grid.node_doubles);
  std::vector<double> nodes(grid.values(), 0.0);
  double* const far_block = &nodes[slot * grid.nx * grid.nz];
  // Paired slots: each node's four values again at the end of its left neighbour's slot.
  auto pair_with_left = [&](double* row, int count) {
    if (slot == 8)
      for (int j = 1; j < count; ++j) std::copy(row + slot * j, row + slot * j + 4, row + slot * (j - 1) + 4);
  };
  tbb::parallel_for(tbb::blocked_range<int>(0, grid.nx), [&](const tbb::blocked_range<int>& rows) {
    for (int i = rows.begin(); i != rows.end(); ++i) {
      const double x = grid.x_min + i * grid.dx;
      double* near_row = &nodes[slot * i * grid.nz];
      for (int j = 0; j < grid.nz; ++j) node_values(x, j * grid.dz, near_row + slot * j);
      pair_with_left(near_row, grid.nz);
      double* far_row = far_block + slot * i * grid.nw;
      for (int k = 0; k < grid.nw; ++k) {
        double* node = far_row + slot * k;
        const double z = kKernelZNear * std::exp(k * grid.dw);
        node_values(x, z, node);
        node[2] *= z, node[3] *= z;  // d/dw = z d/dz
      }
      pair_with_left(far_row, grid.nw);
    }
  });
  return nodes;
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
  const detail::KernelGrid grid = detail::kernel_grid(spec_);
  nx_ = grid.nx, nz_ = grid.nz, nw_ = grid.nw, x_min_ = grid.x_min, dx_ = grid.dx, dz_ = grid.dz, dw_ = grid.dw;
  const detail::EmbeddedKernelTable file = detail::embedded_kernel_table();
  if (file.data == nullptr) {  // the generator itself
    computed_ = compute_nodes(tier);
    nodes_ = computed_.data();
  } else {
    // The embedded file holds every tier's section in order; each must be its grid's: a mismatch
    // is a stale build, never a table to use.
    std::size_t offset = 0;
    bool matches = true;
    for (const Tier section : detail::kKernelTableTiers) {
      detail::KernelTableFileHeader header;
      const detail::KernelGrid expected = detail::kernel_grid(spec_of(section));
      const std::size_t values = expected.values();
      matches = matches && file.size >= offset + sizeof header;
      if (!matches) break;
      std::memcpy(&header, file.data + offset, sizeof header);
      matches = std::memcmp(header.magic, detail::kKernelTableMagic, sizeof header.magic) == 0 && header.nx == expected.nx &&
                header.nz == expected.nz && header.nw == expected.nw && header.x_min == expected.x_min &&
                header.dx == expected.dx && header.dz == expected.dz && header.dw == expected.dw &&
                header.node_doubles == expected.node_doubles && header.values == values &&
                file.size >= offset + sizeof header + values * sizeof(double);
      if (!matches) break;
      if (section == tier) nodes_ = reinterpret_cast<const double*>(file.data + offset + sizeof header);
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
  const double u_x = (std::log(g) - x_min_) / dx_;
  // The cell's column j in its section and the offset t in it: near in z, far in w = ln(z / kKernelZNear).
  const double u_v = far ? std::log(z / kKernelZNear) / dw_ : z / dz_;
  const double dv = far ? dw_ : dz_;
  const int row_nodes = far ? nw_ : nz_;
  const std::size_t slot = static_cast<std::size_t>(spec_.node_doubles());
  const double* section = far ? nodes_ + slot * nx_ * nz_ : nodes_;
  const int i = std::min(static_cast<int>(u_x), nx_ - 2);
  const int j = std::min(static_cast<int>(u_v), row_nodes - 2);
  const double s = u_x - i, t = u_v - j;
  // Cubic Hermite basis: value weights h0 (left), h1 (right); derivative weights d0, d1 (times
  // the cell size, applied below).
  const double s2 = s * s, s3 = s2 * s, t2 = t * t, t3 = t2 * t;
  const double hx[2] = {2 * s3 - 3 * s2 + 1, -2 * s3 + 3 * s2};
  const double gx[2] = {(s3 - 2 * s2 + s) * dx_, (s3 - s2) * dx_};
  const double hz[2] = {2 * t3 - 3 * t2 + 1, -2 * t3 + 3 * t2};
  const double gz[2] = {(t3 - 2 * t2 + t) * dv, (t3 - t2) * dv};
  double f = 0.0;
  for (int a = 0; a < 2; ++a) {
    const double* row = section + slot * (static_cast<std::size_t>(i + a) * row_nodes + j);
    for (int b = 0; b < 2; ++b) {
      const double* n = row + 4 * b;  // node (i + a, j + b): the next 4 doubles in either layout
      f += hx[a] * (hz[b] * n[0] + gz[b] * n[2]) + gx[a] * (hz[b] * n[1] + gz[b] * n[3]);
    }
  }
  return f;
}

std::size_t KernelTable::scaled_sigma_inside(const double* g, const double* c, std::size_t count, double scale, double* out,
                                             std::uint32_t* outside, const double* ln_g) const {
  const detail::KernelTableView view{nodes_, nx_, nz_, nw_, x_min_, dx_, dz_, dw_, spec_.prefetch_rows, spec_.node_doubles()};
  return detail::kernel_table_lanes(view, g, c, ln_g, count, scale, out, outside);
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
