// LUT layouts: axis mappings (node index <-> angles), lookup by interpolation, 1D side tables.
// The mappings are documented in libbrdf/lut.h and written into every file (lut_metadata.cpp).
#include "libbrdf/lut.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "libbrdf/batch.h"
#include "libbrdf/error.h"
#include "libbrdf/beckmann_kirchhoff.h"
#include "libbrdf/mbk_series.h"
#include "libbrdf/microfacet.h"
#include "angular_simd.h"
#include "asf_lanes.h"  // log_span
#include "lut_internal.h"

namespace libbrdf {

std::string_view layout_name(LutLayout layout) {
  switch (layout) {
    case LutLayout::rusinkiewicz: return "rusinkiewicz";
    case LutLayout::merl: return "merl";
    case LutLayout::slice: return "slice";
    case LutLayout::kernel: return "kernel";
  }
  return "?";
}

LutLayout layout_from_name(std::string_view name) {
  for (LutLayout layout : {LutLayout::rusinkiewicz, LutLayout::merl, LutLayout::slice, LutLayout::kernel})
    if (layout_name(layout) == name) return layout;
  throw InvalidArgument("layout", "must be one of rusinkiewicz|merl|slice|kernel (got '" + std::string(name) + "')");
}

std::array<int, 3> default_resolution(LutLayout layout) {
  switch (layout) {
    case LutLayout::rusinkiewicz: return {90, 90, 90};
    case LutLayout::merl: return kMerlShape;
    case LutLayout::slice: return {256, 128, 1};
    case LutLayout::kernel: return {54, 54, 54};  // 1.9 MB for 3 channels (float32)
  }
  return {0, 0, 0};
}

std::array<int, 3> target_error_start_resolution(LutLayout layout) {
  switch (layout) {
    case LutLayout::rusinkiewicz: return {16, 16, 16};
    case LutLayout::slice: return {16, 16, 1};
    case LutLayout::kernel: return {12, 12, 12};
    case LutLayout::merl: break;
  }
  return kMerlShape;
}

HalfDifferenceAngles half_difference_angles(const ScatterGeometry& geo) {
  detail::TableAngles angles;  // MERL's half-vector frame, computed once for lookups and this (table_angles_simd.cpp)
  if (detail::table_angles(&geo, 1, &angles) == 0)
    throw InvalidArgument("geometry", "a field of the ScatterGeometry is not finite");
  return {angles.theta_h, angles.theta_d, angles.phi_d};
}

ScatterAngles scatter_angles_from_half_difference(const HalfDifferenceAngles& hd) {
  const detail::HalfDifferenceDirections v = detail::directions_from_half_difference(
      std::sin(hd.theta_h), std::cos(hd.theta_h), std::sin(hd.theta_d), std::cos(hd.theta_d), std::cos(hd.phi_d), std::sin(hd.phi_d));
  const double ix = v.ix, iy = v.iy, iz = v.iz, sx = v.sx, sy = v.sy, sz = v.sz;
  ScatterAngles a;
  a.theta_i = std::atan2(std::sqrt(ix * ix + iy * iy), iz);  // unit vectors: no std::hypot needed
  a.theta_s = std::atan2(std::sqrt(sx * sx + sy * sy), sz);
  const double phi_i = std::atan2(iy, ix), phi_s = std::atan2(sy, sx);
  a.phi_s = std::remainder(phi_s - phi_i, 2.0 * kPi);
  return a;
}

namespace detail {

std::array<double, 3> lut_axis_spans(LutLayout layout, const std::array<int, 3>& shape) {
  // MERL has no node on the upper range ends (index N would be the end); the others do (N - 1).
  if (layout == LutLayout::merl) return {double(shape[0]), double(shape[1]), double(shape[2])};
  return {double(shape[0] - 1), double(shape[1] - 1), double(std::max(shape[2] - 1, 1))};
}

Direction normalized(const Direction& d) {
  const double length = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  return {d.x / length, d.y / length, d.z / length};
}

ScatterAngles limit_to_horizon(ScatterAngles a) {
  const double limit = degrees_to_radians(kHorizonThetaLimitDeg);
  a.theta_i = std::min(a.theta_i, limit);
  a.theta_s = std::min(a.theta_s, limit);
  return a;
}

ScatterAngles angles_at_index(LutLayout layout, const std::array<int, 3>& shape, double x0, double x1, double x2,
                              const Direction& light, const Direction& view, bool* feasible) {
  const std::array<double, 3> span = lut_axis_spans(layout, shape);
  const double t0 = x0 / span[0];
  HalfDifferenceAngles hd;
  // Square map, except for the kernel layout's smooth angular factor (uniform: the lobe's
  // sharpness is in Sigma, not in the table).
  hd.theta_h = layout == LutLayout::kernel ? 0.5 * kPi * t0 : 0.5 * kPi * t0 * t0;
  if (layout == LutLayout::slice) {
    hd.theta_d = slice_theta_d(light, view);
    hd.phi_d = kPi * x1 / span[1];
  } else {
    hd.theta_d = 0.5 * kPi * x1 / span[1];
    hd.phi_d = kPi * x2 / span[2];
  }
  const ScatterAngles a = scatter_angles_from_half_difference(hd);
  if (feasible) *feasible = a.theta_i < 0.5 * kPi && a.theta_s < 0.5 * kPi;
  return a;
}

}  // namespace detail

double detail::slice_cos_2theta_d(const Direction& light, const Direction& view) {
  const Direction l = normalized(light), v = normalized(view);
  return std::clamp(l.x * v.x + l.y * v.y + l.z * v.z, -1.0, 1.0);  // eq. 5
}

double slice_theta_d(const Direction& light, const Direction& view) { return 0.5 * std::acos(detail::slice_cos_2theta_d(light, view)); }

ScatterAngles lut_node_angles(LutLayout layout, const std::array<int, 3>& shape, int i0, int i1, int i2,
                              const Direction& light, const Direction& view) {
  return detail::limit_to_horizon(detail::angles_at_index(layout, shape, i0, i1, i2, light, view, nullptr));
}

namespace {

inline double lerp(float a, float b, double t) { return (1.0 - t) * double(a) + t * double(b); }

// Index coordinate on one axis from its fraction of the span, beyond the last node holding it.
// (Only the MERL layout has a range beyond its last node; the other layouts end on a node.)
inline void split_index(double x, int nodes, int& i, double& t) {
  x = std::clamp(x, 0.0, double(nodes - 1));
  i = std::min(static_cast<int>(x), std::max(nodes - 2, 0));
  t = x - i;
}

// Where theta_i (radians) falls in a 1D table of `nodes` nodes over [0, pi/2] (R_spec, K).
struct LinearPosition {
  int i = 0;
  double t = 0.0;
};
inline LinearPosition linear_position(int nodes, double theta_i) {
  if (!(theta_i >= 0.0 && theta_i <= 0.5 * kPi))
    throw InvalidArgument("theta_i", "must be in [0, 90] degrees for the R_spec/K tables");
  LinearPosition p;
  split_index(theta_i / (0.5 * kPi) * (nodes - 1), nodes, p.i, p.t);
  return p;
}
inline double linear_at(const std::vector<float>& table, const LinearPosition& p) { return lerp(table[p.i], table[p.i + 1], p.t); }
inline double linear_1d(const std::vector<float>& table, double theta_i) {
  return linear_at(table, linear_position(static_cast<int>(table.size()), theta_i));
}

}  // namespace

// The trilinear layouts (rusinkiewicz, merl) as their lookups in lanes see them (trilinear_simd.cpp).
namespace {
detail::TrilinearView trilinear_view(const Lut& lut) {
  const std::array<double, 3> span = detail::lut_axis_spans(lut.layout, lut.shape);
  detail::TrilinearView view;
  view.values = lut.values.data();
  view.nodes = lut.nodes_per_channel();
  view.n0 = lut.shape[0], view.n1 = lut.shape[1], view.n2 = lut.shape[2];
  view.n12 = static_cast<std::size_t>(view.n1) * view.n2;
  view.scale0 = span[0], view.scale1 = span[1] / (0.5 * kPi), view.scale2 = span[2] / kPi;
  return view;
}

// Slice layout: (theta_h, phi_d) at the slice's theta_d, bilinear.
double slice_value(const Lut& lut, const detail::TableAngles& angles, int channel) {
  const std::array<double, 3> span = detail::lut_axis_spans(lut.layout, lut.shape);
  int i0, i1;
  double t0, t1;
  split_index(std::sqrt(angles.theta_h / (0.5 * kPi)) * span[0], lut.shape[0], i0, t0);  // square map
  split_index(angles.phi_d / kPi * span[1], lut.shape[1], i1, t1);
  const std::size_t n1 = lut.shape[1];
  const float* row0 = lut.values.data() + static_cast<std::size_t>(channel) * lut.nodes_per_channel() + i0 * n1;
  const float* row1 = row0 + n1;
  return (1.0 - t0) * lerp(row0[i1], row0[i1 + 1], t1) + t0 * lerp(row1[i1], row1[i1 + 1], t1);
}

// Channels whose closed-form factors are evaluated together (kernel_closed_form_span: Qbar reads
// the geometries once for all of them): RGB in one group.
constexpr int kKernelChannelGroup = 4;

// Kernel layout: f = K(theta_i) F(theta_d) [closed-form factor] P~ (pi l_c^2/lambda^2) Sigma(g, c)
// (lut.h), eqs 10-12, for a span of queries; Sigma of each channel through the batch ASF
// (mbk_series.h) at kKernelLayoutSigmaTolerance (lut.h). angles: the table angles of the P~ table
// form (table_angles_for); the closed form reads none.
void kernel_span(const Lut& lut, const ScatterGeometry* geos, const detail::TableAngles* angles, std::size_t count,
                 int first_channel, int channel_count, double* values, const float* interleaved) {
  // Blocks of 256: 3-channel closed-form lookups 44-47 -> 42-44 ns against blocks of 64
  // (bench_lookup, three alternated runs).
  constexpr std::size_t kBlock = 256;
  double asf[kBlock], g[kBlock], c[kBlock];
  // The closed-form factors of up to kGroup channels at a time, from one read of the geometries;
  // their products written to the interleaved values once the group is done, not by a pass per
  // channel with stride channel_count: 3-channel closed-form lookups 24.1-24.4 -> 22.9-23.5 ns
  // (cached, measured as below).
  constexpr int kGroup = kKernelChannelGroup;
  double closed[kGroup][kBlock], factor[kGroup][kBlock];
  // What g and c (eq. 12, eq. 10) depend on, read from the geometries once for every channel
  // (asf_auto_geometries per channel read them three times: 27.7-28.2 -> 27.2-27.7 ns per 3-channel
  // closed-form lookup, cached, six alternated runs; the same bits).
  double cos_sum[kBlock], eta_r2[kBlock];
  // ... and ln g = 2 ln(g_scale |cos ti + cos ts|) (eq. 12) from one logarithm per query for every
  // channel, where the kernel table took one per channel: 3-channel closed-form lookups
  // 25.1-25.6 -> 24.6-25.4 ns (gold, sigma_s = 0.02 um, 8000 cached geometries, best of 2000
  // passes, four alternated runs); values within 6e-14 of those with the table's own logarithm
  // there (20000 queries), 1.0e-12 at most over test_kernel_table.cpp's sweep.
  double ln_cos_sum[kBlock], ln_g[kBlock];
  double k_node[kBlock], k_offset[kBlock];  // K's position (k_positions_span) for tables of k_nodes nodes
  // The closed form's table holds P~ = 1 at every node (checked when read: check_lut_consistency):
  // nothing to interpolate, and the product of the other factors is the value (1 x it, bit for bit).
  const bool ones = lut.kernel_angular == KernelAngular::closed_form;
  const std::array<double, 3> span = detail::lut_axis_spans(lut.layout, lut.shape);  // theta_h, theta_d over [0, pi/2]; phi_d over [0, pi]
  detail::KernelAngularView p_tilde{lut.values.data(), lut.nodes_per_channel(), 1, {lut.shape[0], lut.shape[1], lut.shape[2]},
                                    {span[0] / (0.5 * kPi), span[1] / (0.5 * kPi), span[2] / kPi}};
  if (interleaved) p_tilde.values = interleaved, p_tilde.channel_stride = 1, p_tilde.node_floats = channel_count;
  for (std::size_t begin = 0; begin < count; begin += kBlock) {
    const std::size_t n = std::min(kBlock, count - begin);
    const ScatterGeometry* block = geos + begin;
    if (!ones) detail::kernel_angular_span(p_tilde, angles + begin, n, first_channel, channel_count, values + begin * channel_count);
    for (std::size_t k = 0; k < n; ++k) cos_sum[k] = block[k].cos_theta_i + block[k].cos_theta_s, eta_r2[k] = block[k].eta_r2;
    // |cos ti + cos ts| (g is its square); where it is 0, so is g, outside the table: its ln g is not read.
    for (std::size_t k = 0; k < n; ++k) ln_cos_sum[k] = std::abs(cos_sum[k]);
    detail::log_span(ln_cos_sum, n, ln_cos_sum);
    int k_nodes = -1;  // the K table size k_node, k_offset were found for
    for (int ch = 0; ch < channel_count; ++ch) {
      const int channel = first_channel + ch;
      // The surface in units of the wavelength: what g (eq. 12) and c depend on.
      const AsfScales scales = asf_scales(Surface{lut.kernel_sigma_over_lambda[channel], lut.kernel_lc_over_lambda[channel], 1.0});
      const double ln_g_scale = std::log(scales.g_scale);
      for (std::size_t k = 0; k < n; ++k) {
        const AsfArguments a = asf_arguments(scales, cos_sum[k], eta_r2[k]);
        g[k] = a.g, c[k] = a.c;
        ln_g[k] = 2.0 * (ln_g_scale + ln_cos_sum[k]);
      }
      asf_auto_batch(g, c, n, scales.prefactor, kKernelLayoutSigmaTolerance, SeriesOptions{}, asf, ln_g);
      if (ch % kGroup == 0) detail::kernel_closed_form_span(lut, channel, std::min(kGroup, channel_count - ch), block, n, closed[0], kBlock);
      const std::vector<float>& k_table = lut.renormalization[channel];
      if (static_cast<int>(k_table.size()) != k_nodes) {  // once per block (every channel's table has as many nodes from bake)
        k_nodes = static_cast<int>(k_table.size());
        if (!detail::k_positions_span(k_nodes, block, n, k_node, k_offset))  // a theta_i beyond [0, 90] deg:
          for (std::size_t k = 0; k < n; ++k) {  // the scalar formula, which names it
            const LinearPosition p = linear_position(k_nodes, std::atan2(block[k].sin_theta_i, block[k].cos_theta_i));
            k_node[k] = p.i, k_offset[k] = p.t;
          }
      }
      detail::k_factors_span(k_table.data(), k_node, k_offset, closed[ch % kGroup], asf, n, factor[ch % kGroup]);
      if (ch % kGroup != kGroup - 1 && ch != channel_count - 1) continue;
      const int group = ch - ch % kGroup, size = ch % kGroup + 1;
      double* out = values + begin * channel_count + group;
      for (std::size_t k = 0; k < n; ++k, out += channel_count)
        for (int m = 0; m < size; ++m) out[m] = ones ? factor[m][k] : out[m] * factor[m][k];
    }
  }
}
}  // namespace

void detail::table_angles_for(const Lut& lut, const ScatterGeometry* geos, std::size_t count, TableAngles* out,
                              std::size_t first_index) {
  // The closed form's table holds 1 (kernel_span): no table angle is read (K's position comes from
  // the geometry: k_positions_span), and none is computed.
  const bool no_angles = lut.layout == LutLayout::kernel && lut.kernel_angular == KernelAngular::closed_form;
  std::size_t bad = no_angles ? count : table_angles(geos, count, out);
  if (lut.layout == LutLayout::kernel) bad = first_non_finite(geos, bad);  // Sigma, Qbar and F read every field
  if (bad < count) throw InvalidQuery(InvalidArgument("geometry", "a field of the ScatterGeometry is not finite"), first_index + bad);
}

void detail::lookup_span(const Lut& lut, const ScatterGeometry* geos, const TableAngles* angles, std::size_t count,
                         int first_channel, int channel_count, double* values, const float* interleaved) {
  if (lut.layout == LutLayout::slice) {
    for (std::size_t k = 0; k < count; ++k)
      for (int c = 0; c < channel_count; ++c) values[k * channel_count + c] = slice_value(lut, angles[k], first_channel + c);
    return;
  }
  if (lut.layout == LutLayout::kernel) {
    kernel_span(lut, geos, angles, count, first_channel, channel_count, values, interleaved);
    return;
  }
  detail::TrilinearView view = trilinear_view(lut);
  if (interleaved) view.interleaved = interleaved, view.node_floats = channel_count;
  detail::trilinear_span(view, angles, count, first_channel, channel_count, values);
}

namespace {
// Every channel at `count` geometries, a block at a time: the block's table coordinates, then its
// lookups (from `interleaved` where given: LutSampler).
void lookup_all_blocks(const Lut& lut, const float* interleaved, const ScatterGeometry* geos, std::size_t count, double* values) {
  constexpr std::size_t kBlock = 256;
  detail::TableAngles angles[kBlock];
  const int channels = lut.channels();
  for (std::size_t begin = 0; begin < count; begin += kBlock) {
    const std::size_t n = std::min(kBlock, count - begin);
    detail::table_angles_for(lut, geos + begin, n, angles, begin);
    detail::lookup_span(lut, geos + begin, angles, n, 0, channels, values + begin * channels, interleaved);
  }
}
}  // namespace

void detail::lookup_all_span(const Lut& lut, const ScatterGeometry* geos, std::size_t count, double* values) {
  lookup_all_blocks(lut, nullptr, geos, count, values);
}

LutSampler::LutSampler(Lut lut) : lut_(std::move(lut)) {
  detail::check_lut_consistency(lut_, "LutSampler");
  const int channels = lut_.channels();
  const bool trilinear = lut_.layout == LutLayout::rusinkiewicz || lut_.layout == LutLayout::merl;
  const bool p_tilde_table = lut_.layout == LutLayout::kernel && lut_.kernel_angular == KernelAngular::table;
  if (!(trilinear || p_tilde_table) || channels < 2 || channels > detail::kInterleavedNodeFloats) return;
  const std::size_t nodes = lut_.nodes_per_channel(), stride = static_cast<std::size_t>(channels);
  // Padding: a trilinear lookup loads kInterleavedNodeFloats floats from a node's first channel; a
  // P~ row's last vector reads past the row.
  interleaved_.assign(nodes * stride + (trilinear ? detail::kInterleavedNodeFloats : detail::kKernelInterleavedPadding), 0.0f);
  for (int c = 0; c < channels; ++c)
    for (std::size_t i = 0; i < nodes; ++i) interleaved_[stride * i + c] = lut_.values[c * nodes + i];
}

void LutSampler::lookup_all(const ScatterGeometry* geometries, std::size_t count, double* values) const {
  lookup_all_blocks(lut_, interleaved_.empty() ? nullptr : interleaved_.data(), geometries, count, values);
}

bool detail::kernel_angular_all_closed(ModelKind model, KernelAngular angular) {
  // An ASF model's P is all closed form where its row has one (bk, bk-modified), or when asked for.
  const ModelTraits& row = model_traits(model);
  return row.asf_based && (row.closed_angular != ClosedAngularForm::none || angular == KernelAngular::closed_form);
}

void detail::kernel_closed_form_span(const Lut& lut, int first_channel, int channel_count, const ScatterGeometry* geos,
                                     std::size_t count, double* out, std::size_t channel_stride) {
  if (lut.kernel_model == ModelKind::mbk && lut.kernel_angular == KernelAngular::closed_form) {  // P = Qbar (conventions.md)
    constexpr int kGroup = kKernelChannelGroup;
    for (int group = 0; group < channel_count; group += kGroup) {
      double eps_re[kGroup], eps_im[kGroup];
      const int size = std::min(kGroup, channel_count - group);
      // Single-precision Qbar where every channel of the group allows it: its error (<= 3e-5,
      // angular_simd.h) is small against the layout's 1e-3; 3-channel lookups ~2.5 ns faster.
      bool single = true;
      for (int c = 0; c < size; ++c) {
        const Complex eps = lut.kernel_index[first_channel + group + c].permittivity();
        eps_re[c] = eps.real(), eps_im[c] = eps.imag();
        single = single && detail::qbar_single_precision_range(eps_re[c], eps_im[c]);
      }
      detail::stover_q_bar_span(eps_re, eps_im, size, geos, count, out + group * channel_stride, channel_stride,
                                single ? detail::QBarPrecision::single : detail::QBarPrecision::double_);
    }
    return;
  }
  for (int c = 0; c < channel_count; ++c) {
    const int channel = first_channel + c;
    const Complex eps = lut.kernel_index[channel].permittivity();
    double* row = out + c * channel_stride;
    detail::fresnel_d_span(eps.real(), eps.imag(), geos, count, row);  // F(theta_d)
    switch (model_traits(lut.kernel_model).closed_angular) {  // the rest of P in closed form (the row's)
      case ClosedAngularForm::bk_eq26:
        for (std::size_t k = 0; k < count; ++k) row[k] *= bk_geometric_factor_eq26(geos[k]);
        break;
      case ClosedAngularForm::bk_modified_eq28:
        for (std::size_t k = 0; k < count; ++k) row[k] *= inverse_s_term_eq28(geos[k]);
        break;
      case ClosedAngularForm::none:
        if (detail::kernel_closed_form_reads_slopes(lut.kernel_model, lut.kernel_angular))
          for (std::size_t k = 0; k < count; ++k)  // eq. 31's G / S (Model::combine_span)
            row[k] *= geometric_term(lut.kernel_g_term[channel], geos[k], lut.kernel_sigma_g[channel]) / s_term(geos[k]);
        break;
    }
  }
}

double Lut::lookup(int channel, const ScatterGeometry& geo) const {
  if (channel < 0 || channel >= channels())
    throw InvalidArgument("channel", "must be in [0, " + std::to_string(channels() - 1) + "] (got " + std::to_string(channel) + ")");
  detail::TableAngles angles;
  detail::table_angles_for(*this, &geo, 1, &angles);
  double value = 0.0;
  detail::lookup_span(*this, &geo, &angles, 1, channel, 1, &value);
  return value;
}

void Lut::lookup_all(const ScatterGeometry& geo, double* out) const { detail::lookup_all_span(*this, &geo, 1, out); }

double Lut::specular_at(int channel, double theta_i) const {
  if (channel < 0 || channel >= static_cast<int>(specular_reflectance.size()))
    throw InvalidArgument("channel", "no R_spec table for channel " + std::to_string(channel));
  return linear_1d(specular_reflectance[channel], theta_i);
}

double Lut::renormalization_at(int channel, double theta_i) const {
  if (channel < 0 || channel >= static_cast<int>(renormalization.size()))
    throw InvalidArgument("channel", "no K table for channel " + std::to_string(channel));
  return linear_1d(renormalization[channel], theta_i);
}

}  // namespace libbrdf
