#pragma once
// Internal: the kernel table's node file (kernel_table.h). libbrdf_generate_kernel_table writes it
// at build time; kernel_table_data.S assembles it into the library; KernelTable::instance() checks
// its header against kernel_table.h's grid and reads the nodes in place.
#include <cstddef>
#include <cstdint>

namespace libbrdf::detail {

// 64 bytes, so that the nodes after it keep the 64-byte alignment of the embedded data.
struct KernelTableFileHeader {
  char magic[8];
  std::int32_t nx, nz;
  double x_min, dx, dz;
  std::uint64_t values;  // doubles that follow: 4 nx nz
  std::uint64_t reserved[2];
};
static_assert(sizeof(KernelTableFileHeader) == 64);
inline constexpr char kKernelTableMagic[8] = {'L', 'B', 'K', 'T', 'A', 'B', '0', '1'};

// The grid of kernel_table.h's constants.
struct KernelGrid {
  int nx, nz;
  double x_min, dx, dz;
};
KernelGrid kernel_grid();

// The embedded file's bytes; {nullptr, 0} in the generator, which links none.
struct EmbeddedKernelTable {
  const unsigned char* data;
  std::size_t size;
};
EmbeddedKernelTable embedded_kernel_table();

}  // namespace libbrdf::detail
