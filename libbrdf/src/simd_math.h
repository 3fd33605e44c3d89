#pragma once
// Internal: vector math over arrays (simd_math.cpp).
#include <cstddef>

namespace libbrdf::detail {
// out[k] = atan(in[k]) for k < count (in and out may alias).
void atan_array(const double* in, double* out, std::size_t count);
}  // namespace libbrdf::detail
