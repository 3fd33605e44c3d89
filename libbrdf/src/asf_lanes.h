#pragma once
// Internal: the batch kernels of asf_auto_batch (asf_batch.cpp), one query per SIMD lane.
#include <cstddef>
#include <cstdint>

#include "libbrdf/kernel_table.h"

namespace libbrdf::detail {

// The per-lane series handles truncation tolerances from this up (its recurrences lose ~(d + 10)
// eps per term; the rest goes to sum_series_blocks).
inline constexpr double kLaneMinTolerance = 1e-12;
// ... and g in [kLaneMinG, kLaneMaxG], c in [0, kLaneMaxC] (outside: sum_series_blocks).
inline constexpr double kLaneMinG = 1e-100;
inline constexpr double kLaneMaxG = 1e6;
inline constexpr double kLaneMaxC = 1e100;
// Widest stride summed in lanes: beyond, the d factors of the Poisson ratio per term cost more
// than sum_series_blocks' terms across lanes (windows of width >~ 32, g >~ 1000).
inline constexpr double kLaneMaxStride = 16.0;

// sigma[k] = Sigma(g[k], c[k]) of eq. 11 (mbk_series.h) truncated at relative_tolerance, with the
// plan (largest-term guess, stride rule) and geometric tail bound of sum_series_blocks. Returns the
// number of queries it leaves to the caller, their indices in rejected[] (stride above
// kLaneMaxStride, or a lane that did not converge): sigma[k] is not written for those.
// Preconditions: the domain above, relative_tolerance >= kLaneMinTolerance.
std::size_t series_query_lanes(const double* g, const double* c, std::size_t count, double relative_tolerance,
                               double* sigma, std::uint32_t* rejected);

// A kernel table's spline coefficients (KernelTable::coefficients()), laid out as its grid says.
struct KernelTableView {
  const double* coefficients;
  KernelGrid grid;
};

// The kernel table's bicubic spline lookup (KernelTable::sigma) in lanes: out[k] = scale exp(F(ln g, v))
// for every query inside the table (KernelTable::contains, the same test lane by lane; 0 beyond
// kKernelZFar). Returns the number of queries outside, their indices in outside[] (out[k] is
// unspecified there: the caller evaluates them otherwise). ln_g: ln g[k] as the caller has it
// (KernelTable::scaled_sigma_inside), or null for a logarithm per query.
std::size_t kernel_table_lanes(const KernelTableView& table, const double* g, const double* c, const double* ln_g, std::size_t count,
                               double scale, double* out, std::uint32_t* outside);

// out[k] = ln x[k] for k < count (Highway's Log, within 4 ulp) for x[k] > 0; 0 and negative x[k]
// give finite values that mean nothing (measured: -746.5 at 0, 1419.6 at -1). out may be x.
void log_span(const double* x, std::size_t count, double* out);

}  // namespace libbrdf::detail
