#pragma once
// Internal: the kernel tables' node file (kernel_table.h). libbrdf_generate_kernel_table writes it
// at build time; kernel_table_data.S assembles it into the library; KernelTable::instance(tier)
// checks its tier's header against kernel_table.h's grid and reads the nodes in place. The file is
// one section per tier, in KernelTable::Tier's order: a header, then its nodes.
#include <cstddef>
#include <cstdint>

#include "libbrdf/kernel_table.h"

namespace libbrdf::detail {

// 64 bytes, so that the nodes after it keep the 64-byte alignment of the embedded data.
struct KernelTableFileHeader {
  char magic[8];
  std::int32_t nx, nz;
  double x_min, dx, dz;
  std::uint64_t values;  // doubles that follow: node_doubles nx (nz + nw)
  double dw;
  std::int32_t nw, node_doubles;  // doubles per node slot (KernelTable::nodes())
};
static_assert(sizeof(KernelTableFileHeader) == 64);
inline constexpr char kKernelTableMagic[8] = {'L', 'B', 'K', 'T', 'A', 'B', '0', '4'};

// The grid of a tier (kernel_table.h's constants).
struct KernelGrid {
  int nx, nz, nw;
  double x_min, dx, dz, dw;
  int node_doubles;  // KernelTableSpec::node_doubles()
  std::size_t values() const { return static_cast<std::size_t>(nx) * (nz + nw) * node_doubles; }
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
