#pragma once
// Internal: the angular factors of the models over spans of geometries, in SIMD (Google Highway,
// run-time dispatch; angular_simd.cpp). Each value depends only on its own geometry (no lane
// mixes with another), so results do not depend on the span's length, split or position.
// Accuracy against the scalar functions: a few ulp of Highway's Sin/Cos (1-4 ulp; the spans use no
// other transcendental function) propagated through the formulas; <= 1e-13 relative (tests/cpp/test_fresnel.cpp,
// test_renormalization.cpp, test_geometry.cpp), except Qbar at grazing for |eps| ~ 1e6, where the
// scalar formula itself is good to ~1e-10 only (both agree to 3e-10 there).
#include <cmath>
#include <cstddef>

#include "libbrdf/geometry.h"

namespace libbrdf::detail {

// sin and cos of the three angles of each query: trig[6 k + 0..5] = cos ti, sin ti, cos ts, sin ts,
// cos phi_s, sin phi_s. |phi_s| beyond Highway's range (39000 rad) goes through std::sin/cos.
void scatter_trig(const ScatterAngles* angles, std::size_t count, double* trig);
// The derived quantities of ScatterGeometry (eqs 5, 6, 10) from such sines and cosines: geos[k]
// from trig[6 k .. 6 k + 5]. The one implementation behind make_scatter_geometries and
// scatter_geometry_from_trig, so that every path gives a query the same bits.
void geometries_from_trig(const double* trig, std::size_t count, ScatterGeometry* geos);
// Both in one pass (make_scatter_geometries): geos[k] from angles[k], the same values as
// scatter_trig then geometries_from_trig.
void scatter_geometries(const ScatterAngles* angles, std::size_t count, ScatterGeometry* geos);

// The arithmetic of stover_q_bar_span. double: within 1e-13 of stover_q (the model paths). single:
// float lanes from the double geometry, for the kernel layout's lookups, whose error budget is 1e-3
// (lut.h); their error grows with |eps| (the pp term's cancellation, angular_simd.cpp), so they
// serve only permittivities inside qbar_single_precision_range.
enum class QBarPrecision { double_, single };
// 1e-3 <= |eps| <= 100 and |eps - 1| >= 1e-3: single-precision Qbar within 3e-5 of the double one
// there (Fresnel.SinglePrecisionQbarWithinItsBoundOnEveryTarget: 6e-6 to 8e-6 measured). Every
// built-in material (materials.h) lies inside over its whole table: |eps| <= 79 (Al, 0.775 um).
inline bool qbar_single_precision_range(double eps_re, double eps_im) {
  const double magnitude = std::hypot(eps_re, eps_im);
  return magnitude >= 1e-3 && magnitude <= 100.0 && std::hypot(eps_re - 1.0, eps_im) >= 1e-3;
}
// Qbar = (Q_s + Q_p)/2 of Stover (fresnel.h, stover_q) at each geometry for each of `channels`
// permittivities eps_re[c] + i eps_im[c]: out[c channel_stride + k] for geos[k]. A channel's
// values are the same bits whatever the other channels are.
void stover_q_bar_span(const double* eps_re, const double* eps_im, int channels, const ScatterGeometry* geos, std::size_t count,
                       double* out, std::size_t channel_stride, QBarPrecision precision = QBarPrecision::double_);
// One permittivity.
inline void stover_q_bar_span(double eps_re, double eps_im, const ScatterGeometry* geos, std::size_t count, double* out) {
  stover_q_bar_span(&eps_re, &eps_im, 1, geos, count, out, 0);
}

// F(theta_d) (fresnel.h, fresnel_reflectance at geos[k].cos_theta_d).
void fresnel_d_span(double eps_re, double eps_im, const ScatterGeometry* geos, std::size_t count, double* out);

// The dense grid of RenormalizationTable (renormalization.h): (q, dq per node index) interleaved
// per node, uniform in u = 1 - sqrt(cos theta_i); K = base + cos^2 ti max(0, q). A lookup reads
// the 4 doubles of its cell's two nodes (LoadColumns), never past the grid.
struct KTableView {
  const double* dense;
  int nodes;
  double scale;  // node index per unit of u
  double base;   // 1 in plane mode, 0 in tis mode
};
// K(theta_i) at each geometry, as RenormalizationTable::operator() (the node coordinate from cos theta_i).
void renormalization_span(const KTableView& table, const ScatterGeometry* geos, std::size_t count, double* out);

}  // namespace libbrdf::detail
