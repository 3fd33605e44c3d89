// libbrdf_generate_kernel_table OUT: computes the universal kernel tables' spline coefficients (kernel_table.h,
// every tier) from the series and writes them as kernel_table_file.h's file, which the build
// assembles into the library (kernel_table_data.S). Linked from every libbrdf source but the
// embedded data, so KernelTable::instance(tier) here computes the tables itself. Writes OUT.tmp, then renames it: an
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
    const std::string out = argv[1], temporary = out + ".tmp";
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (!file) throw std::runtime_error("cannot write " + temporary);
    bool written = true;
    std::string summary;
    for (const libbrdf::KernelTable::Tier tier : libbrdf::detail::kKernelTableTiers) {  // one section each, in order
      const libbrdf::KernelTable& table = libbrdf::KernelTable::instance(tier);
      const libbrdf::KernelGrid grid = libbrdf::KernelGrid::of(table.spec());
      libbrdf::detail::KernelTableFileHeader header{};
      std::memcpy(header.magic, libbrdf::detail::kKernelTableMagic, sizeof header.magic);
      header.nx = grid.nx, header.nz = grid.nz, header.nw = grid.nw;
      header.x_min = grid.x_min, header.dx = grid.dx, header.dz = grid.dz, header.dw = grid.dw;
      header.spline_border = grid.kSplineBorder;
      header.values = table.value_count();
      written = written && std::fwrite(&header, sizeof header, 1, file) == 1 &&
                std::fwrite(table.coefficients(), sizeof(double), table.value_count(), file) == table.value_count();
      char line[160];
      std::snprintf(line, sizeof line, "%s%d x (%d + %d) nodes, %.1f MB, certified %g, computed in %.3f s", summary.empty() ? "" : "; ",
                    table.nx(), table.nz(), table.nw(), static_cast<double>(table.bytes()) / 1e6, table.certified_error(), table.build_seconds());
      summary += line;
    }
    if (std::fclose(file) != 0 || !written || std::rename(temporary.c_str(), out.c_str()) != 0) {
      std::remove(temporary.c_str());
      throw std::runtime_error("cannot write " + out);
    }
    std::printf("kernel tables: %s -> %s\n", summary.c_str(), out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "libbrdf_generate_kernel_table: %s\n", e.what());
    return 1;
  }
  return 0;
}
