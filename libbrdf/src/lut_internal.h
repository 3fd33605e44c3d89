#pragma once
// Internal helpers shared by the LUT sources (lut.cpp, bake.cpp, lut_exr.cpp, merl_binary.cpp,
// lut_metadata.cpp). Not installed.
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <string>

#include "libbrdf/lut.h"

namespace libbrdf::detail {

// Index-space length of each axis: node i sits at fraction i / span of the axis range.
// rusinkiewicz, slice: span = N - 1 (nodes on both range ends); merl: span = N (no node on the
// upper end). Slice has span 1 on its unused third axis.
std::array<double, 3> lut_axis_spans(LutLayout layout, const std::array<int, 3>& shape);

// The angles a table lookup needs, for a batch of geometries: theta_h, theta_d, phi_d of
// half_difference_angles() and theta_i, from dot products with one vector arctangent each and no
// acos/atan2 (SIMD, table_angles_simd.cpp).
struct TableAngles {
  double theta_h, theta_d, phi_d, theta_i;
};
// Returns the index of the first geometry that is not finite (geometry_finite) where a sine or
// cosine it reads is not (out is then incomplete), or count.
std::size_t table_angles(const ScatterGeometry* geos, std::size_t count, TableAngles* out);
// The index of the first geometry of the span with a non-finite field, or count (SIMD).
std::size_t first_non_finite(const ScatterGeometry* geos, std::size_t count);
// Every field of a ScatterGeometry is finite (so it is from make_scatter_geometry; a hand-filled
// record may hold anything).
inline bool geometry_finite(const ScatterGeometry& g) {
  return std::isfinite(g.cos_theta_i) && std::isfinite(g.sin_theta_i) && std::isfinite(g.cos_theta_s) &&
         std::isfinite(g.sin_theta_s) && std::isfinite(g.cos_phi_s) && std::isfinite(g.sin_phi_s) &&
         std::isfinite(g.cos_2theta_d) && std::isfinite(g.cos_theta_d) && std::isfinite(g.cos_theta_h) && std::isfinite(g.eta_r2);
}
// The angles a lookup of `lut` reads (lut.cpp): all four, or none (out is not written) for the
// kernel layout's closed form, whose K position comes from the geometry (k_positions_span):
// 3-channel kernel lookups spent ~15% of their time on the other three angles, then ~2% on
// theta_i's own pass.
// Throws InvalidQuery (batch.h; index first_index + k, parameter "geometry") at the first geometry
// with a non-finite field the lookup reads (the kernel layout reads them all), instead of looking
// up a wrong node or value.
void table_angles_for(const Lut& lut, const ScatterGeometry* geos, std::size_t count, TableAngles* out,
                      std::size_t first_index = 0);
// A rusinkiewicz or MERL table as its trilinear lookups see it (lut.cpp builds it from the Lut):
// channel c's node (i0, i1, i2) is values[c * nodes + i0 * n12 + i1 * n2 + i2]; index positions
// are sqrt(theta_h / (pi/2)) scale0 (the square map, lut.h), theta_d scale1, phi_d scale2.
// Or, channel-interleaved (LutSampler): node (i0, i1, i2)'s channel c is
// interleaved[node_floats * (i0 * n12 + i1 * n2 + i2) + c], its channels side by side (node_floats
// = the table's channels, 2 to kInterleavedNodeFloats), followed by kInterleavedNodeFloats floats
// of padding.
struct TrilinearView {
  const float* values;
  std::size_t nodes, n12;  // nodes per channel; stride of the theta_h axis
  int n0, n1, n2;          // nodes per axis (n2: the phi_d axis, stride 1)
  double scale0, scale1, scale2;
  const float* interleaved = nullptr;  // when set, values is not read
  int node_floats = 0;
};
inline constexpr int kInterleavedNodeFloats = 4;  // channels of an interleaved table, at most
// Trilinear values of channels [first, first + channel_count) at `count` queries:
// values[k * channel_count + c] (SIMD, one query per lane: trilinear_simd.cpp).
void trilinear_span(const TrilinearView& table, const TableAngles* angles, std::size_t count, int first_channel, int channel_count,
                    double* values);
// Kernel layout (kernel_k_simd.cpp): K(theta_i) linearly interpolated in a table of `nodes` (>= 2)
// floats over [0, pi/2] in SIMD lanes, bit for bit lut.cpp's scalar linear_at. k_positions_span:
// the node index and offset of each geos[k]'s theta_i (atan2 of sin and cos theta_i by table_angles'
// UpperHalfAngle), false (the arrays unspecified) if some theta_i lies outside [0, pi/2];
// k_factors_span: factor[k] = K closed[k] asf[k] from them.
bool k_positions_span(int nodes, const ScatterGeometry* geos, std::size_t count, double* node, double* offset);
void k_factors_span(const float* k_table, const double* node, const double* offset, const double* closed, const double* asf, std::size_t count,
                    double* factor);
// Kernel layout, the P~ table (kernel_angular_simd.cpp): channel c's node (i0, i1, i2) at
// values[c channel_stride + node_floats ((i0 nodes[1] + i1) nodes[2] + i2)]: planar (the Lut's
// values: node_floats 1, channel_stride the nodes per channel) or channel-interleaved (LutSampler:
// node_floats = the channels, 2 to kInterleavedNodeFloats, channel_stride 1, followed by
// kKernelInterleavedPadding floats). The node position of an axis is its table angle (theta_h,
// theta_d, phi_d) times nodes_per_radian.
inline constexpr std::size_t kKernelInterleavedPadding = 64;  // a row's last vector reads past the row
struct KernelAngularView {
  const float* values;
  std::size_t channel_stride;
  int node_floats;
  int nodes[3];
  double nodes_per_radian[3];
};
// P~ of channels [first, first + channel_count) at `count` queries, out[k channel_count + c]
// (interleaved: every channel, first_channel 0):
// Catmull-Rom on each axis (4 x 4 x 4 nodes, end nodes repeated), summed in single precision
// (~1e-7 relative, the table's own floats; the layout promises 1e-3).
void kernel_angular_span(const KernelAngularView& table, const TableAngles* angles, std::size_t count, int first_channel,
                         int channel_count, double* out);
// Kernel layout: the closed-form part of the angular factor P of a channel (lut.h), evaluated at
// lookup; the table holds P~ = P / K / that. F(theta_d) times F_bk^2 of eq. 26 (bk), 1/S of eq. 28
// (bk-modified), G/S (mbk-fg in the closed form), 1 (mbk-fg and mbk with the table form); Stover's
// Qbar for mbk in the closed form.
// Over a span of geometries (SIMD Fresnel and Qbar): out[c channel_stride + k] for geos[k] and
// channel first_channel + c, c < channel_count (the channels' Qbar from one read of the geometries).
void kernel_closed_form_span(const Lut& lut, int first_channel, int channel_count, const ScatterGeometry* geos, std::size_t count,
                             double* out, std::size_t channel_stride);
// True when the closed-form part is all of P (the table holds 1).
bool kernel_angular_all_closed(ModelKind model, KernelAngular angular);
// The kernel layout's closed-form P reads sigma_g and the G term per channel (stored in the table):
// an ASF model whose row reads sigma_g (mbk-fg's G / S, eq. 31), in the closed form.
inline bool kernel_closed_form_reads_slopes(ModelKind model, KernelAngular angular) {
  const ModelTraits& row = model_traits(model);
  return row.asf_based && row.reads(kSigmaG) && angular == KernelAngular::closed_form;
}
// The models the kernel layout takes (their rows' asf_based), for messages: "mbk, mbk-fg, bk, bk-modified".
inline std::string asf_model_names() {
  return model_names_where([](const ModelTraits& row) { return row.asf_based; });
}
// Interpolated values of channels [first, first + channel_count) at `count` geometries with their
// TableAngles: values[k * channel_count + c]. interleaved: LutSampler's channel-interleaved copy of
// a trilinear table's or a P~ table's values (every channel: first_channel 0), or null.
void lookup_span(const Lut& lut, const ScatterGeometry* geos, const TableAngles* angles, std::size_t count, int first_channel,
                 int channel_count, double* values, const float* interleaved = nullptr);
inline void lookup_channels(const Lut& lut, const ScatterGeometry& geo, const TableAngles& angles, int first_channel,
                            int channel_count, double* values) {
  lookup_span(lut, &geo, &angles, 1, first_channel, channel_count, values);
}
// Every channel at `count` geometries (table angles computed here in blocks): values[k * channels + c].
void lookup_all_span(const Lut& lut, const ScatterGeometry* geos, std::size_t count, double* values);

Direction normalized(const Direction& d);
// L.V of the unit directions of a slice table: the cos 2theta_d every geometry of the slice has
// (eq. 5), clamped to [-1, 1].
double slice_cos_2theta_d(const Direction& light, const Direction& view);

// Incident i and scattered s of a half/difference triple (phi_h = 0), from the sines and cosines
// of theta_h, theta_d, phi_d: i = R_y(theta_h) d with d = (sin td cos pd, sin td sin pd, cos td),
// s = 2 (i.h) h - i with i.h = cos theta_d. Unit up to rounding; z <= 0 below the horizon.
// (scatter_angles_from_half_difference, and the bake's rows in Cartesian form.)
struct HalfDifferenceDirections {
  double ix, iy, iz, sx, sy, sz;
};
inline HalfDifferenceDirections directions_from_half_difference(double sin_h, double cos_h, double sin_d, double cos_d,
                                                                double cos_phi_d, double sin_phi_d) {
  const double dx = sin_d * cos_phi_d, dy = sin_d * sin_phi_d;
  HalfDifferenceDirections v;
  v.ix = dx * cos_h + cos_d * sin_h;
  v.iy = dy;
  v.iz = -dx * sin_h + cos_d * cos_h;
  v.sx = 2.0 * cos_d * sin_h - v.ix;
  v.sy = -v.iy;
  v.sz = 2.0 * cos_d * cos_h - v.iz;
  return v;
}

// Angles at a (possibly fractional) index position; `feasible` = both directions strictly above
// the horizon. No horizon limit applied.
ScatterAngles angles_at_index(LutLayout layout, const std::array<int, 3>& shape, double x0, double x1, double x2,
                              const Direction& light, const Direction& view, bool* feasible);

// Polar angles limited to kHorizonThetaLimitDeg (the fill rule of lut.h for nodes at or below
// the horizon).
ScatterAngles limit_to_horizon(ScatterAngles angles);

// Checks that a table is self-consistent (shape, sizes, finite values); throws
// LutFileError("<label>: <problem>").
void check_lut_consistency(const Lut& lut, const std::string& label);

// Text written into file headers: the axis mapping and the texel convention of a layout.
std::string axis_mapping_text(const Lut& lut);
std::string texel_convention_text(LutLayout layout);

// Metadata common to every file format (keys without prefix), from the table's fields plus its
// `attributes`; and back: restores layout, wavelengths, shape, directions and error from it.
std::map<std::string, std::string> lut_metadata(const Lut& lut);
// Throws LutFileError("<label>: <problem>").
void restore_from_metadata(Lut& lut, const std::map<std::string, std::string>& metadata, const std::string& label);

// Model parameters as JSON text (for file headers) and a one-line description.
std::string parameters_json(ModelKind kind, const std::vector<ModelParameters>& channels);

}  // namespace libbrdf::detail
