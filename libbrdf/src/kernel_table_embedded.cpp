// The kernel table's nodes as the library embeds them (kernel_table_data.S, kernel_table_file.h).
#include "kernel_table_file.h"

extern "C" const unsigned char libbrdf_kernel_table_data[];
extern "C" const unsigned char libbrdf_kernel_table_data_end[];

namespace libbrdf::detail {
EmbeddedKernelTable embedded_kernel_table() {
  return {libbrdf_kernel_table_data, static_cast<std::size_t>(libbrdf_kernel_table_data_end - libbrdf_kernel_table_data)};
}
}  // namespace libbrdf::detail
