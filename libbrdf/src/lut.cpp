// LUT layouts: axis mappings (node index <-> angles), lookup by interpolation, 1D side tables.
// The mappings are documented in libbrdf/lut.h and written into every file (lut_metadata.cpp).
#include "libbrdf/lut.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "libbrdf/error.h"
#include "libbrdf/beckmann_kirchhoff.h"
#include "libbrdf/kernel_table.h"
#include "lut_internal.h"
#include "simd_math.h"

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

namespace {
// (y, x) pairs whose atan2 are theta_h, theta_d and phi_d (folded), from the dot products of one
// geometry: the half-vector frame of MERL's reference reader (lut.h). One computation for
// half_difference_angles() and the table lookups' trig-free coordinates.
struct HalfVectorFrame {
  double h_xy, hz;  // theta_h = atan2(h_xy, hz)
  double d_xy, dz;  // theta_d = atan2(d_xy, dz)
  double ty, dx;    // phi_d = |atan2(ty, dx)|
};

HalfVectorFrame half_vector_frame(const ScatterGeometry& geo) {
  // Incident i = (sin ti, 0, cos ti), scattered s = (sin ts cos phi_s, sin ts sin phi_s, cos ts);
  // half vector along i + s.
  const double hx = geo.sin_theta_i + geo.sin_theta_s * geo.cos_phi_s;
  const double hy = geo.sin_theta_s * geo.sin_phi_s;
  const double hz = geo.cos_theta_i + geo.cos_theta_s;
  // Components are O(1) (sums of unit vectors): plain square roots, no std::hypot (slow, and its
  // overflow guard is not needed here).
  const double h_xy = std::sqrt(hx * hx + hy * hy);
  const double h_norm = std::sqrt(h_xy * h_xy + hz * hz);
  // phi_h is undefined at theta_h = 0; any choice gives the same value for an isotropic BRDF.
  const double cos_phi_h = h_xy > 0.0 ? hx / h_xy : 1.0;
  const double sin_phi_h = h_xy > 0.0 ? hy / h_xy : 0.0;
  const double cos_theta_h = hz / h_norm, sin_theta_h = h_xy / h_norm;
  // d = R_y(-theta_h) R_z(-phi_h) i: the incident direction in the half-vector frame.
  const double tx = geo.sin_theta_i * cos_phi_h, ty = -geo.sin_theta_i * sin_phi_h;
  const double dx = tx * cos_theta_h - geo.cos_theta_i * sin_theta_h;
  const double dz = tx * sin_theta_h + geo.cos_theta_i * cos_theta_h;
  return {h_xy, hz, std::sqrt(dx * dx + ty * ty), dz, ty, dx};
}
}  // namespace

HalfDifferenceAngles half_difference_angles(const ScatterGeometry& geo) {
  const HalfVectorFrame f = half_vector_frame(geo);
  HalfDifferenceAngles hd;
  hd.theta_h = std::atan2(f.h_xy, f.hz);
  hd.theta_d = std::atan2(f.d_xy, f.dz);
  hd.phi_d = std::abs(std::atan2(f.ty, f.dx));  // mirror symmetry: phi_d and -phi_d are equal
  return hd;
}

ScatterAngles scatter_angles_from_half_difference(const HalfDifferenceAngles& hd) {
  const double sin_h = std::sin(hd.theta_h), cos_h = std::cos(hd.theta_h);
  const double sin_d = std::sin(hd.theta_d), cos_d = std::cos(hd.theta_d);
  const double dx = sin_d * std::cos(hd.phi_d), dy = sin_d * std::sin(hd.phi_d), dz = cos_d;
  // i = R_y(theta_h) d (phi_h = 0); s = 2 (i.h) h - i with i.h = cos theta_d.
  const double ix = dx * cos_h + dz * sin_h, iy = dy, iz = -dx * sin_h + dz * cos_h;
  const double sx = 2.0 * cos_d * sin_h - ix, sy = -iy, sz = 2.0 * cos_d * cos_h - iz;
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

double slice_theta_d(const Direction& light, const Direction& view) {
  const Direction l = detail::normalized(light), v = detail::normalized(view);
  return 0.5 * std::acos(std::clamp(l.x * v.x + l.y * v.y + l.z * v.z, -1.0, 1.0));  // eq. 5
}

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

inline double linear_1d(const std::vector<float>& table, double theta_i) {
  if (!(theta_i >= 0.0 && theta_i <= 0.5 * kPi))
    throw InvalidArgument("theta_i", "must be in [0, 90] degrees for the R_spec/K tables");
  const int n = static_cast<int>(table.size());
  int i = 0;
  double t = 0.0;
  split_index(theta_i / (0.5 * kPi) * (n - 1), n, i, t);
  return lerp(table[i], table[i + 1], t);
}

}  // namespace

// Table coordinates without acos/atan2 calls. Every angle the tables need lies in [0, pi]:
// angle(y, x) = atan2(y, x) for y >= 0 is written through one arctangent of a ratio in [-1, 1]
// (ratio_of), and the arctangents of a whole batch come from one vector call (simd_math.h).
namespace {

struct PendingAngle {
  double ratio;   // argument of the arctangent, in [-1, 1]
  double offset;  // angle = offset + sign * atan(ratio)
  double sign;
};

// atan2(y, x) for y >= 0 (angles in [0, pi]).
inline PendingAngle ratio_of(double y, double x) {
  if (x >= y) return {x > 0.0 ? y / x : 0.0, 0.0, 1.0};    // [0, pi/4]
  if (-x >= y) return {y / -x, kPi, -1.0};                   // [3pi/4, pi]
  return {x / y, 0.5 * kPi, -1.0};                           // (pi/4, 3pi/4)
}

// The four angles a lookup needs: theta_h, theta_d, phi_d (half/difference frame of
// half_difference_angles, from the same dot products) and theta_i (for R_spec/K).
inline void pending_angles(const ScatterGeometry& geo, PendingAngle* out) {
  const HalfVectorFrame f = half_vector_frame(geo);
  out[0] = ratio_of(f.h_xy, f.hz);
  out[1] = ratio_of(f.d_xy, f.dz);
  out[2] = ratio_of(std::abs(f.ty), f.dx);  // phi_d folded by the mirror symmetry
  out[3] = ratio_of(geo.sin_theta_i, geo.cos_theta_i);
}

inline double resolve(const PendingAngle& p, double atan_ratio) { return p.offset + p.sign * atan_ratio; }

}  // namespace

void detail::table_angles(const ScatterGeometry* geos, std::size_t count, TableAngles* out) {
  constexpr std::size_t kChunk = 256;
  PendingAngle pending[4 * kChunk];
  double ratios[4 * kChunk];
  for (std::size_t begin = 0; begin < count; begin += kChunk) {
    const std::size_t n = std::min(kChunk, count - begin);
    for (std::size_t k = 0; k < n; ++k) {
      pending_angles(geos[begin + k], pending + 4 * k);
      for (int a = 0; a < 4; ++a) ratios[4 * k + a] = pending[4 * k + a].ratio;
    }
    atan_array(ratios, ratios, 4 * n);
    for (std::size_t k = 0; k < n; ++k) {
      TableAngles& t = out[begin + k];
      t.theta_h = resolve(pending[4 * k], ratios[4 * k]);
      t.theta_d = resolve(pending[4 * k + 1], ratios[4 * k + 1]);
      t.phi_d = resolve(pending[4 * k + 2], ratios[4 * k + 2]);
      t.theta_i = resolve(pending[4 * k + 3], ratios[4 * k + 3]);
    }
  }
}

void detail::lookup_channels(const Lut& lut, const ScatterGeometry& geo, const TableAngles& angles, int first_channel,
                             int channel_count, double* values) {
  const std::array<double, 3> span = lut_axis_spans(lut.layout, lut.shape);
  const std::size_t nodes = lut.nodes_per_channel();
  if (lut.layout == LutLayout::slice) {  // (theta_h, phi_d) at the slice's theta_d
    int i0, i1;
    double t0, t1;
    split_index(std::sqrt(angles.theta_h / (0.5 * kPi)) * span[0], lut.shape[0], i0, t0);  // square map
    split_index(angles.phi_d / kPi * span[1], lut.shape[1], i1, t1);
    const std::size_t n1 = lut.shape[1];
    for (int c = 0; c < channel_count; ++c) {
      const float* row0 = lut.values.data() + static_cast<std::size_t>(first_channel + c) * nodes + i0 * n1;
      const float* row1 = row0 + n1;
      values[c] = (1.0 - t0) * lerp(row0[i1], row0[i1 + 1], t1) + t0 * lerp(row1[i1], row1[i1 + 1], t1);
    }
    return;
  }
  int i0, i1, i2;
  double t0, t1, t2;
  const double theta_h_fraction = angles.theta_h / (0.5 * kPi);
  split_index((lut.layout == LutLayout::kernel ? theta_h_fraction : std::sqrt(theta_h_fraction)) * span[0], lut.shape[0], i0, t0);
  split_index(angles.theta_d / (0.5 * kPi) * span[1], lut.shape[1], i1, t1);
  split_index(angles.phi_d / kPi * span[2], lut.shape[2], i2, t2);
  const std::size_t n2 = lut.shape[2], n12 = static_cast<std::size_t>(lut.shape[1]) * n2;
  const std::size_t corner = i0 * n12 + i1 * n2 + i2;
  // The factored form's parts that do not depend on the channel's table (kernel layout).
  const bool kernel = lut.layout == LutLayout::kernel;
  const double cos_sum = geo.cos_theta_i + geo.cos_theta_s;
  for (int c = 0; c < channel_count; ++c) {
    const int channel = first_channel + c;
    const float* c00 = lut.values.data() + static_cast<std::size_t>(channel) * nodes + corner;
    const float* c01 = c00 + n2;
    const float* c10 = c00 + n12;
    const float* c11 = c10 + n2;
    auto lerp2 = [t2](const float* p) { return lerp(p[0], p[1], t2); };
    const double table = (1.0 - t0) * ((1.0 - t1) * lerp2(c00) + t1 * lerp2(c01)) + t0 * ((1.0 - t1) * lerp2(c10) + t1 * lerp2(c11));
    if (!kernel) {
      values[c] = table;
      continue;
    }
    // f = K(theta_i) P (pi l_c^2/lambda^2) Sigma(g, c) (lut.h, layout kernel), eqs 10-12.
    const double s = lut.kernel_sigma_over_lambda[channel], l = lut.kernel_lc_over_lambda[channel];
    const double k_wave = 2.0 * kPi * s * cos_sum;
    AsfArguments args;
    args.g = k_wave * k_wave;
    args.prefactor = kPi * l * l;
    args.c = kPi * args.prefactor * geo.eta_r2;
    const double asf = asf_auto(args, kKernelTableCertifiedError);
    const double fresnel = fresnel_reflectance(lut.kernel_index[channel].permittivity(), geo.cos_theta_d);
    values[c] = linear_1d(lut.renormalization[channel], angles.theta_i) * fresnel * kernel_closed_form_factor(lut.kernel_model, geo) *
                table * asf;
  }
}

double detail::kernel_closed_form_factor(ModelKind model, const ScatterGeometry& geo) {
  switch (model) {
    case ModelKind::bk: return bk_geometric_factor_eq26(geo);
    case ModelKind::bk_modified: return inverse_s_term_eq28(geo);
    default: return 1.0;
  }
}

double Lut::lookup(int channel, const ScatterGeometry& geo) const {
  if (channel < 0 || channel >= channels())
    throw InvalidArgument("channel", "must be in [0, " + std::to_string(channels() - 1) + "] (got " + std::to_string(channel) + ")");
  detail::TableAngles angles;
  detail::table_angles(&geo, 1, &angles);
  double value = 0.0;
  detail::lookup_channels(*this, geo, angles, channel, 1, &value);
  return value;
}

void Lut::lookup_all(const ScatterGeometry& geo, double* out) const {
  detail::TableAngles angles;
  detail::table_angles(&geo, 1, &angles);
  detail::lookup_channels(*this, geo, angles, 0, channels(), out);
}

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
