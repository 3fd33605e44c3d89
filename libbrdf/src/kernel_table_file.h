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
  std::uint64_t values;  // doubles that follow: KernelGrid::values() (KernelTable::coefficients())
  double dw;
  std::int32_t nw, spline_border;  // coefficients beyond each end of a row or column: 1 (clamped cubic)
};
static_assert(sizeof(KernelTableFileHeader) == 64);
inline constexpr char kKernelTableMagic[8] = {'L', 'B', 'K', 'T', 'A', 'B', '0', '5'};

inline constexpr KernelTable::Tier kKernelTableTiers[] = {KernelTable::Tier::fine, KernelTable::Tier::coarse};

// The embedded file's bytes (every tier); {nullptr, 0} in the generator, which links none.
struct EmbeddedKernelTable {
  const unsigned char* data;
  std::size_t size;
};
EmbeddedKernelTable embedded_kernel_table();

}  // namespace libbrdf::detail
