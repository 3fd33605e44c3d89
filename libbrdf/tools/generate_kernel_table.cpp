// libbrdf_generate_kernel_table OUT: computes the universal kernel table's nodes (kernel_table.h)
// from the series and writes them as kernel_table_file.h's file, which the build assembles into
// the library (kernel_table_data.S). Linked from every libbrdf source but the embedded data, so
// KernelTable::instance() here computes the table itself. Writes OUT.tmp, then renames it: an
// interrupted build leaves no half-written table.
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernel_table_file.h"
#include "libbrdf/kernel_table.h"

namespace libbrdf::detail {
EmbeddedKernelTable embedded_kernel_table() { return {nullptr, 0}; }
}  // namespace libbrdf::detail

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: libbrdf_generate_kernel_table OUT\n");
    return 2;
  }
  try {
    const libbrdf::KernelTable& table = libbrdf::KernelTable::instance();
    libbrdf::detail::KernelTableFileHeader header{};
    std::memcpy(header.magic, libbrdf::detail::kKernelTableMagic, sizeof header.magic);
    header.nx = table.nx(), header.nz = table.nz();
    header.x_min = table.x_min(), header.dx = table.dx(), header.dz = table.dz();
    header.values = table.value_count();
    const std::string out = argv[1], temporary = out + ".tmp";
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (!file) throw std::runtime_error("cannot write " + temporary);
    const bool written = std::fwrite(&header, sizeof header, 1, file) == 1 &&
                         std::fwrite(table.nodes(), sizeof(double), table.value_count(), file) == table.value_count();
    if (std::fclose(file) != 0 || !written || std::rename(temporary.c_str(), out.c_str()) != 0) {
      std::remove(temporary.c_str());
      throw std::runtime_error("cannot write " + out);
    }
    std::printf("kernel table: %d x %d nodes, %.1f MB, computed in %.3f s -> %s\n", table.nx(), table.nz(), static_cast<double>(table.bytes()) / 1e6,
                table.build_seconds(), out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "libbrdf_generate_kernel_table: %s\n", e.what());
    return 1;
  }
  return 0;
}
