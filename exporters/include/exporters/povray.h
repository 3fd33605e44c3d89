#pragma once
// POV-Ray 3.7 export of a libbrdf model (issue #4). POV-Ray has no custom BRDFs, so the include
// `NAME.inc` carries two textures:
//
//  NAME_Exact  radiance L = f_r(w_i, w_s) cos(theta_i) E as emission, for ONE parallel light and an
//              orthographic (or distant) camera whose directions are fixed in the world. With L and
//              V fixed, f_r depends on the normal N only through two dot products (conventions.md,
//              eq. 5: cos 2theta_d = L.V fixes phi_s), so a 2D table over the normal is exact.
//  NAME_Fit    an averaged texture_map of native finishes (Blinn lobes with metallic tint, colour
//              following N.V, + variable reflection for the specular spike R_spec) fitted to the
//              model (fit.h), for scenes with any lights. Its measured error is written into the include.
//
// Table coordinates (HalfVectorSlice). POV-Ray can only look a table up through patterns of the
// normal; `slope { d }` gives s = 1/2 + asin(N.d)/pi for a unit direction d (measured with POV-Ray
// 3.7.0), and a pigment_map over one slope pattern whose entries are color_maps over another is a
// 2D table, interpolated linearly in the two slope values, with at most 256 entries per map (3.7.0).
// The table is over
//     a = N.H   (H = (L + V)/|L + V|, the half vector; s_H = 1 - theta_h/pi)   and   u = N.L.
// The MBK ASF (eq. 11), g (eq. 12) and eta_r^2 (eq. 10) depend on a alone, since
//     N.L + N.V = 2 cos(theta_d) a,   eta_r^2 = 4 cos^2(theta_d) (1 - a^2),
// so the sharp peak lies along one axis, and the rest (K, Q, Fresnel, G, 1/S, cos theta_i) varies
// slowly along u. Nodes are placed per axis by greedy refinement of the worst interval (in slope
// values, as POV-Ray interpolates), so 256 rows resolve a polished peak. The stored quantity is the
// radiance R = f_r cos(theta_i), and u = 0 is a node: the cut to black at the terminator is exact.
// Why not lut.h's `slice` (theta_h square map x phi_d, from bake()): mapped onto the same two
// nested maps (rows at its theta_h nodes, inner entries at N.D = -sin(theta_h) cos(phi_d)), its
// 256 x 128 table reproduced by POV-Ray's interpolation errs by up to 2.0% / 0.78% / 0.52% (Au mbk,
// sigma_s = 0.0011 / 0.0275 / 0.275 um, l_c = 2 um, theta_d = 27 deg; random normals, values above
// 1e-3 of the peak), limited by the fixed theta_h spacing at the polished lobe; these nodes reach
// 0.08% / 0.08% / 0.11% with the same 256-entry limit.
//
// Directions are POV-Ray world vectors (left-handed, x right, y up, z away from a default camera),
// from the surface towards the light and towards the camera. Handedness only flips the sign of
// phi_s, which an isotropic BRDF does not see.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "exporters/fit.h"
#include "libbrdf/lut.h"
#include "libbrdf/models.h"

namespace libbrdf::povray {

// POV-Ray 3.7.0 limit of entries in one pigment_map / color_map (lifted only in 3.7.1/3.8).
inline constexpr int kMaxMapEntries = 256;

// Light, view and the derived half vector of one slice (unit vectors, world space).
struct SliceGeometry {
  std::array<double, 3> light{}, view{}, half{};
  double cos_2theta_d = 1.0;  // L.V (eq. 5)
  double cos_theta_d = 1.0;   // |L + V| / 2
  double sin_theta_d = 0.0;   // |L - V| / 2
};
// Normalizes and checks the two directions. Throws InvalidArgument naming light-dir or view-dir for a
// zero/NaN vector, and light-dir for opposite directions (no surface point is both lit and seen).
SliceGeometry make_slice_geometry(const Direction& light, const Direction& view);

// Scattering angles of the normal with N.H = a, N.L = u (the view-side cosine is N.V = 2 cos(theta_d) a - u).
// Defined for 0 < u, 0 < N.V; phi_s from eq. 5, clamped onto [0, pi] on the boundary of feasibility.
ScatterAngles angles_at(const SliceGeometry& geometry, double n_dot_h, double n_dot_l);

// The value of POV-Ray's `slope { d }` pattern for N.d = x, and its inverse.
double slope_value(double n_dot_direction);
double slope_inverse(double slope);

struct SliceRequest {
  ModelKind model = ModelKind::mbk;        // must be a BRDF (is_brdf)
  std::vector<ModelParameters> channels;   // one per colour channel (R, G, B)
  Direction light, view;                   // world space, towards the light / the camera
  int entries = kMaxMapEntries;            // nodes per axis, 8..256
  double error_floor_fraction = 1e-3;      // relative errors are measured above this x the peak
  int error_samples = 20000;
  std::uint64_t seed = 1;
  double fit_target_error = fit::kDefaultTargetError;  // NAME_Fit: p95 per-pixel error (fit.h)
};

// Radiance per unit irradiance, R = f_r cos(theta_i) (1/sr), on a tensor grid over (a = N.H, u = N.L).
// Node values are the model's at feasible nodes; infeasible nodes (no unit N has that (a, u)) hold a
// linear continuation along u from the feasible interval, so that interpolation near its ends stays
// accurate; they are never looked up by a real normal.
struct HalfVectorSlice {
  SliceGeometry geometry;
  std::vector<double> half_nodes;    // a, ascending, first 0, last 1
  std::vector<double> light_nodes;   // u, ascending, first 0, last 1
  std::vector<double> half_slopes, light_slopes;  // the same nodes as POV-Ray slope values (map positions)
  std::vector<double> values;        // [channel][i_a][j_u], 1/sr
  std::vector<double> wavelengths_um;
  std::vector<double> peak;          // per channel: R at N = H
  LutError error;                    // measured against the model at random normals

  int channels() const { return static_cast<int>(wavelengths_um.size()); }
  double value(int channel, std::size_t i_a, std::size_t j_u) const {
    return values[(static_cast<std::size_t>(channel) * half_nodes.size() + i_a) * light_nodes.size() + j_u];
  }
  // POV-Ray's lookup: bilinear in the slope values of a and u, clamped to the end entries.
  double lookup(int channel, double n_dot_h, double n_dot_l) const;
};

// Places the nodes (greedy refinement of the worst interval, both axes), fills the table (threaded)
// and measures its error at random normals (half of them uniform in the angle from H, to sample the peak).
HalfVectorSlice bake_half_vector_slice(const SliceRequest& request);

// NAME_Fit: a mixture of POV-Ray Blinn lobes fitted to the model (fit.h, shape blinn), each a
// texture of its own (specular S_j, roughness 1/n_j, metallic 1, pigment c_j(N.V) as a
// slope { view } colour_map), averaged by a texture_map (weights equal, S_j scaled by the lobe
// count), plus the mirror reflection min + (max - min)(1 - cos theta)^falloff fitted to
// R_spec(theta) = F exp(-g) in every lobe (so the average keeps it). Per light of colour E:
//   L = E sum_j S_j (N.H)^n_j (F_m(N.L) + (1 - F_m(N.L)) c_j(N.V)),  N.L > 0.
struct FinishFit {
  fit::NativeFit lobes;                // the Blinn lobes and their measured error (fit.h)
  std::array<double, 3> reflection_min{}, reflection_max{};
  double reflection_falloff = 1.0;
  std::array<double, 3> peak_ratio{};  // fit / exact at N = H for the include's sun and view
  double reflection_rms_error = 0.0;   // RMS of (fit - R_spec) over theta, absolute reflectance
};
FinishFit fit_finish(const HalfVectorSlice& slice, const std::vector<Model>& models,
                     double target_error = fit::kDefaultTargetError);
// POV-Ray 3.7's radiance of the fitted lobes for one parallel light of unit colour (no reflection).
double fit_radiance(const FinishFit& fit, int channel, double n_dot_l, double n_dot_v, double n_dot_h);

// Throws InvalidArgument("name", ...) unless `name` is a usable POV-Ray identifier prefix
// (a letter, then letters, digits or '_', at most 24 characters so that NAME_... stays within
// POV-Ray's 40).
void validate_include_name(const std::string& name);

// The include text (see the file header for what it declares).
std::string include_text(const std::string& name, ModelKind model, const std::vector<ModelParameters>& channels,
                         const HalfVectorSlice& slice, const FinishFit& fit);

struct ExportResult {
  std::string include_path;
  HalfVectorSlice slice;
  FinishFit fit;
};
// Bakes, fits and writes directory/NAME.inc (temporary + rename; the directory is created).
ExportResult export_povray(const SliceRequest& request, const std::string& name, const std::string& directory);

}  // namespace libbrdf::povray
