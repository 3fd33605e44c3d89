#pragma once
// Internal: the SIMD block summation of the MBK series (series_simd.cpp). The plan (where the
// window of terms is, its stride, the truncation tolerance) is made by mbk_series.cpp.
#include <cstddef>

namespace libbrdf::detail {

struct SeriesPlan {
  double g = 0.0, c = 0.0;          // Sigma(g, c), g > 0 finite, c >= 0 finite
  double mode = 1.0;                // an integer m >= 1 at (or within a few terms of) the largest term
  double stride = 1.0;              // integer >= 1: every stride-th term, times stride
  double relative_tolerance = 1e-14;  // geometric tail bound: dropped tail <= tol * sum
};

// The stride rule of the plan (mbk_series.cpp): windows whose largest term lies above
// kStrideMinMode are summed every d-th term, d = floor(width / widths_per_stride) (width: the
// terms' standard deviation in m), where d >= 2 and the window clears m = 1 by clearance_widths.
// Aliasing <= tol/10, the tail cut at tol/20 of the peak at m = 1.
inline constexpr double kStrideMinMode = 16.0;
struct StrideRule {
  double widths_per_stride, clearance_widths;
};
StrideRule stride_rule(double relative_tolerance);

// asf_auto's series truncation (mbk_series.h), also used by asf_auto_batch: a tenth of the
// tolerance the caller allows (the rigorous tail bound), never tighter than the options ask for;
// tolerance 0: the options' own.
inline double auto_series_truncation(double tolerance, double options_tolerance) {
  return tolerance > 0.0 && 0.1 * tolerance > options_tolerance ? 0.1 * tolerance : options_tolerance;
}

struct SeriesBlockStats {
  long long blocks = 0;  // SIMD blocks evaluated (each series_lanes() terms)
};

// Moments of the terms (poisson.h's SeriesMoments): sums relative to exp(log_scale).
struct SeriesMomentSums {
  double log_scale = 0.0, a = 0.0, b = 0.0, c = 0.0, d = 0.0, e = 0.0;
};

// Sigma(g, c) of eq. 11 (mbk_series.h) by SIMD blocks; 0 when every term underflows. With
// `moments`, also the sums a..e of series_moments (for the kernel table's derivatives).
double sum_series_blocks(const SeriesPlan& plan, SeriesBlockStats* stats = nullptr, SeriesMomentSums* moments = nullptr);
// Doubles per vector of the dispatched target (2 SSE, 4 AVX2, 8 AVX-512) and its name.
std::size_t series_lanes();
const char* series_target_name();

}  // namespace libbrdf::detail
