#pragma once
// Internal: the kernel tables' node file (kernel_table.h). libbrdf_generate_kernel_table writes it
// at build time; kernel_table_data.S assembles it into the library; KernelTable::instance(tier)
// checks its tier's header against kernel_table.h's grid and reads the coefficients in place. The
// file is one section per tier, in KernelTable::Tier's order: a header, then its spline coefficients.
#include <cstddef>
#include <cstdint>

#include "libbrdf/kernel_table.h"

namespace libbrdf::detail {

// 64 bytes, so that the coefficients after it keep the 64-byte alignment of the embedded data.
struct KernelTableFileHeader {
  char magic[8];
  std::int32_t nx, nz;
  double x_min, dx, dz;
  std::uint64_t values;  // doubles that follow: (nx + 2) ((nz + 2) + (nw + 2)) (KernelTable::coefficients())
  double dw;
  std::int32_t nw, spline_border;  // coefficients beyond each end of a row or column: 1 (clamped cubic)
};
static_assert(sizeof(KernelTableFileHeader) == 64);
inline constexpr char kKernelTableMagic[8] = {'L', 'B', 'K', 'T', 'A', 'B', '0', '5'};

// The grid of a tier (kernel_table.h's constants).
struct KernelGrid {
  int nx, nz, nw;
  double x_min, dx, dz, dw;
  static constexpr int kSplineBorder = 1;  // coefficients beyond each end of an axis (clamped cubic)
  std::size_t near_row() const { return static_cast<std::size_t>(nz + 2 * kSplineBorder); }
  std::size_t far_row() const { return static_cast<std::size_t>(nw + 2 * kSplineBorder); }
  std::size_t rows() const { return static_cast<std::size_t>(nx + 2 * kSplineBorder); }
  std::size_t values() const { return rows() * (near_row() + far_row()); }
};
KernelGrid kernel_grid(const KernelTableSpec& spec);
inline constexpr KernelTable::Tier kKernelTableTiers[] = {KernelTable::Tier::fine, KernelTable::Tier::coarse};

// The embedded file's bytes (every tier); {nullptr, 0} in the generator, which links none.
struct EmbeddedKernelTable {
  const unsigned char* data;
  std::size_t size;
};
EmbeddedKernelTable embedded_kernel_table();

}  // namespace libbrdf::detail
