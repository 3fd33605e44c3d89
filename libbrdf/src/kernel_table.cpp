// The universal kernel table of Sigma(g, c) (kernel_table.h): built from the reference series'
// moments, looked up by bicubic Hermite interpolation of ln Sigma.
#include "libbrdf/kernel_table.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "asf_lanes.h"
#include "poisson.h"

namespace libbrdf {
namespace {

// ln Sigma and its derivatives in (x = ln g, z = sqrt(c/(g+1))) at one node, from the moments
// a..e of the series (poisson.h). With S = sum t_m, dt_m/dg = t_m (m/g - 1), dt_m/dc = -t_m/m and
// c = (g + 1) z^2 (so dc/dx at fixed z = g z^2, dc/dz at fixed x = 2 (g + 1) z):
//   F_x  = (b - g z^2 c) / a
//   F_z  = -2 (g + 1) z c / a
//   F_xz = 2 z [ -g c / a + (g + 1) ( (-d + g z^2 e) / a + c (b - g z^2 c) / a^2 ) ]
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

}  // namespace

const KernelTable& KernelTable::instance() {
  static const KernelTable table;  // C++11: thread-safe initialisation
  return table;
}

KernelTable::KernelTable() {
  const auto start = std::chrono::steady_clock::now();
  x_min_ = std::log(kKernelGMin);
  dx_ = 1.0 / kKernelNodesPerUnitX;
  dz_ = 1.0 / kKernelNodesPerUnitZ;
  // One cell beyond each end so that every in-domain query has a full cell.
  nx_ = static_cast<int>(std::ceil((std::log(kKernelGMax) - x_min_) / dx_)) + 2;
  nz_ = static_cast<int>(std::ceil(kKernelZMax / dz_)) + 2;
  nodes_.assign(static_cast<std::size_t>(nx_) * nz_ * 4, 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, nx_), [&](const tbb::blocked_range<int>& rows) {
    for (int i = rows.begin(); i != rows.end(); ++i)
      for (int j = 0; j < nz_; ++j)
        node_values(x_min_ + i * dx_, j * dz_, &nodes_[4 * (static_cast<std::size_t>(i) * nz_ + j)]);
  });
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double KernelTable::sigma(double g, double c) const {
  const double u_x = (std::log(g) - x_min_) / dx_;
  const double u_z = std::sqrt(c / (g + 1.0)) / dz_;
  const int i = std::min(static_cast<int>(u_x), nx_ - 2);
  const int j = std::min(static_cast<int>(u_z), nz_ - 2);
  const double s = u_x - i, t = u_z - j;
  // Cubic Hermite basis: value weights h0 (left), h1 (right); derivative weights d0, d1 (times
  // the cell size, applied below).
  const double s2 = s * s, s3 = s2 * s, t2 = t * t, t3 = t2 * t;
  const double hx[2] = {2 * s3 - 3 * s2 + 1, -2 * s3 + 3 * s2};
  const double gx[2] = {(s3 - 2 * s2 + s) * dx_, (s3 - s2) * dx_};
  const double hz[2] = {2 * t3 - 3 * t2 + 1, -2 * t3 + 3 * t2};
  const double gz[2] = {(t3 - 2 * t2 + t) * dz_, (t3 - t2) * dz_};
  double f = 0.0;
  for (int a = 0; a < 2; ++a) {
    const double* row = &nodes_[4 * (static_cast<std::size_t>(i + a) * nz_ + j)];
    for (int b = 0; b < 2; ++b) {
      const double* n = row + 4 * b;
      f += hx[a] * (hz[b] * n[0] + gz[b] * n[2]) + gx[a] * (hz[b] * n[1] + gz[b] * n[3]);
    }
  }
  return std::exp(f);
}

void KernelTable::sigma_many(const double* g, const double* c, std::size_t count, double* sigma) const {
  detail::kernel_table_lanes(nodes_.data(), nx_, nz_, x_min_, dx_, dz_, g, c, count, sigma);
}

}  // namespace libbrdf
