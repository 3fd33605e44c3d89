#pragma once
// The Modified Beckmann-Kirchhoff angle spread function (ASF), eq. 11 of Butler, Nauyoks &
// Marciniak (2015), after Krywonos, Harvey & Choi, JOSA A 28, 1121 (2011), and its closed-form
// limits: polished (eq. 14, m = 1 term) and very rough (eq. 15).
//
//   A(ti, ts, phi_s) = (pi l_c^2 / lambda^2) * Sigma(g, c)                     [1/sr-equivalent:
//   Sigma(g, c)      = e^-g sum_{m>=1} g^m / (m! m) * exp(-c / m)               density in the
//   c                = v_xy^2 l_c^2 / 4 = pi^2 (l_c/lambda)^2 eta_r^2            direction-cosine
//                                                                               plane, d alpha d beta]
// K = 1 here (conventions.md); the renormalization lives in renormalization.h.
//
// The terms are a Poisson weight in m times a Gaussian in eta_r (conventions.md): they are summed
// in log space, outward from the largest term, until the remaining tail is below a relative
// tolerance; never a fixed count, never g^m or m! directly.
#include "libbrdf/geometry.h"
#include "libbrdf/surface.h"

#include <cstddef>

namespace libbrdf {

// How the series is summed.
enum class SeriesMethod {
  simd,        // the default: terms in SIMD blocks (Google Highway, run-time dispatch), Loader's
               // form per term, strided where the window is wide with the stride set by the
               // tolerance (aliasing <= tol/10); see series_plan in mbk_series.cpp.
  every_term,  // every integer m in the window: the reference.
  strided,     // for wide windows (g >~ 60) every d-th term times d: by the Poisson summation
               // formula this equals the full sum up to ~exp(-2 pi^2 (s/d)^2) relative, s the
               // window's standard deviation; d <= s/2 keeps that below 1e-30. Falls back to
               // every_term where the window touches m = 1.
};

struct SeriesOptions {
  double relative_tolerance = 1e-14;  // truncation: dropped tail < tol * sum
  SeriesMethod method = SeriesMethod::simd;
  // asf_auto may use the kernel table (kernel_table.h) where its certified error meets the
  // tolerance; false keeps it to the closed forms and the series (to measure the series itself).
  bool allow_kernel_table = true;
};

// Above this g every method returns the very-rough limit (eq. 15), whose relative error there is
// rough_error_estimate(g, c) ~ 1/g: bounded time for g up to the double range (and g = inf).
// From g = 1e10 it does so wherever rough_error_estimate < 1e-9: there the limit is more accurate
// than any double-precision sum (whose rounding grows like eps sqrt(g)).
inline constexpr double kSeriesRoughLimitG = 1e15;

// Diagnostics of one summation (for tests and benchmarks).
struct SeriesStats {
  long long terms_evaluated = 0;
  long long stride = 1;
  long long mode_m = 0;  // index of the largest term (64-bit: ~g, which may exceed 2^31)
};

// Sigma(g, c) above (dimensionless). g >= 0, c >= 0. Returns 0 when every term underflows
// (log of the largest term < -745), never NaN/Inf.
double mbk_series_sum(double g, double c, const SeriesOptions& options = {},
                      SeriesStats* stats = nullptr);

// Polished limit (eq. 14 without Q): the m = 1 term with e^-g = 1: g e^-c.
double mbk_series_polished(double g, double c);
// Very-rough limit (eq. 15 without Q and K): (1/g) exp(-c/g). Infinite at g = 0: callers must
// only use it for g > 0.
double mbk_series_rough(double g, double c);

// Leading-order relative error estimates of the closed forms against the series, used by the
// automatic regime choice (the measured errors are reported by tests and `brdf bench`):
//  polished: |e^-g (1 + (g/4) e^{c/2} + ...) - 1|  ~  g + (g/4) e^{c/2}
//  rough:    Poisson delta method, u = c/g:  |u^2 - 4u + 2| / (2g)  + O(u^4 / g^2)
double polished_error_estimate(double g, double c);
double rough_error_estimate(double g, double c);

// Which form evaluated the ASF (reported by the regime choice).
enum class AsfRegime { series, polished, rough, table };

// Inputs of the ASF at one geometry: computed once, reused by several models.
struct AsfArguments {
  double g;          // eq. 12
  double c;          // pi^2 (l_c/lambda)^2 eta_r^2
  double prefactor;  // pi (l_c/lambda)^2
};
// The surface's factors of AsfArguments, computed once per surface (two divisions) rather than
// per query.
struct AsfScales {
  double g_scale;    // 2 pi sigma_s / lambda: g = (g_scale (cos ti + cos ts))^2, eq. 12
  double c_scale;    // pi^2 (l_c/lambda)^2: c = c_scale eta_r^2
  double prefactor;  // pi (l_c/lambda)^2
};
inline AsfScales asf_scales(const Surface& surface) {
  const double lc_over_lambda = surface.lc_over_lambda();
  AsfScales s{};
  s.g_scale = 2.0 * kPi * surface.sigma_over_lambda();  // roughness_g's k, without the cosines
  s.prefactor = kPi * lc_over_lambda * lc_over_lambda;   // pi l_c^2 / lambda^2, eq. 11
  s.c_scale = kPi * s.prefactor;                         // v_xy^2 l_c^2 / 4 = pi^2 (l_c/lambda)^2 eta_r^2
  return s;
}
// Inline: the batch paths compute them per query. Bit for bit roughness_g's g (its k is
// (2 pi sigma/lambda) (cos ti + cos ts), multiplied in that order). From the geometry's two
// quantities that g and c depend on, cos_sum = cos ti + cos ts and eta_r^2 (the kernel layout's
// lookups derive them once for every channel), or from the geometry.
inline AsfArguments asf_arguments(const AsfScales& scales, double cos_sum, double eta_r2) {
  const double k = scales.g_scale * cos_sum;
  return AsfArguments{k * k, scales.c_scale * eta_r2, scales.prefactor};
}
inline AsfArguments asf_arguments(const AsfScales& scales, const ScatterGeometry& geo) {
  return asf_arguments(scales, geo.cos_theta_i + geo.cos_theta_s, geo.eta_r2);
}
inline AsfArguments asf_arguments(const Surface& surface, const ScatterGeometry& geo) {
  return asf_arguments(asf_scales(surface), geo);
}

// eq. 11 with K = 1, by the series.
double asf(const Surface& surface, const ScatterGeometry& geo, const SeriesOptions& options = {});

// eq. 11 with K = 1 by the fastest method whose error bound is below `tolerance` (relative; 0 =
// always the series at options' truncation): the universal kernel table (kernel_table.h) where its
// certified error is (from the default 1e-6 up; unless options.allow_kernel_table is false), else
// a closed form where its estimated error is below it, else the series truncated at tolerance/10.
// Reports the method used.
double asf_auto(const AsfArguments& args, double tolerance, AsfRegime* regime = nullptr,
                const SeriesOptions& options = {});
// The method asf_auto uses at (g, c) for `tolerance` (for callers that batch one method, e.g. the
// table through KernelTable::sigma_many). allow_table: SeriesOptions::allow_kernel_table.
AsfRegime asf_regime(const AsfArguments& args, double tolerance, bool allow_table = true);

// asf_auto over a batch of queries sharing one surface (one prefactor pi l_c^2/lambda^2):
// asf_out[k] = asf_auto({g[k], c[k], prefactor}, tolerance, nullptr, options) up to the tolerance:
// the same method choice per query, each value within `tolerance` (relative) of the exact series,
// never NaN/Inf for finite g, c >= 0, 0 where every term underflows. Queries run in SIMD lanes
// (Google Highway, run-time dispatch), each lane alone: asf_out[k] depends on g[k], c[k] only,
// bit for bit, whatever else is in the batch (count 1 included). asf_out may not alias g or c.
// ln_g, if given: ln g[k] for the kernel table's lookups (KernelTable::scaled_sigma_inside).
void asf_auto_batch(const double* g, const double* c, std::size_t count, double prefactor, double tolerance,
                    const SeriesOptions& options, double* asf_out, const double* ln_g = nullptr);
// The same at a span of geometries of one surface: asf_out[k] = asf_auto(asf_arguments(surface,
// geos[k]), tolerance, nullptr, options), g and c derived here block by block.
void asf_auto_geometries(const Surface& surface, const ScatterGeometry* geos, std::size_t count, double tolerance,
                         const SeriesOptions& options, double* asf_out);

// Specular spike reflectance (the m = 0 term, a delta): R_spec(ti) = F(ti) exp(-g(ti, ti)).
// Declared in models.h with the other Fresnel-weighted quantities.

}  // namespace libbrdf
