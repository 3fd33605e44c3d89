#pragma once
// Baked tables (LUTs) of a BRDF model, their bake (error-bounded), lookup, and files.
// OpenEXR stays in the sources; this header uses the standard library only.
//
// Layouts (axis mapping and texel convention are also written into every file's header):
//  rusinkiewicz  3D over (theta_h, theta_d, phi_d) (S. Rusinkiewicz, EGWR 1998), isotropic.
//                Node grid: values sit on the nodes, first/last node on the range ends, trilinear.
//                theta_h = (pi/2) (i/(N0-1))^2   square map: nodes dense at the specular peak
//                theta_d = (pi/2) i/(N1-1)
//                phi_d   = pi i/(N2-1)           phi_d and -phi_d are equal for isotropic BRDFs
//                phi_d is the azimuth of the incident direction in the half-vector frame (the
//                frame of MERL's reference reader: rotate by -phi_h about z, then by -theta_h
//                about y). Only the mirror symmetry phi_d -> -phi_d is used, not reciprocity
//                (phi_d -> phi_d + pi): mbk (K(theta_i)) and bk are not reciprocal.
//  merl          The MERL binary layout (Matusik et al., ACM TOG 22, 759, 2003): 90 x 90 x 180,
//                theta_h = (pi/2)(i/90)^2, theta_d = (pi/2) i/90, phi_d = pi i/180 (the angles
//                MERL's reference reader floors back to index i), channel scales 1/1500,
//                1.15/1500, 1.66/1500, doubles. In memory it is the same node grid (no node on
//                the upper range ends; lookups beyond the last node hold its value). The MERL
//                format folds phi_d by reciprocity: a MERL reader returns f(w_s, w_i) for
//                phi_d < 0, which differs from f(w_i, w_s) for non-reciprocal models.
//  slice         2D, for a scene lit by a sun and seen by a distant (orthographic) camera:
//                the light and view directions L, V are fixed in the WORLD, the normal N varies.
//                For fixed L, V the BRDF depends on N only through (N.L, N.V) = (cos ti, cos ts),
//                since cos 2theta_d = L.V fixes theta_d (eq. 5); equivalently through
//                  cos theta_h = (N.L + N.V) / (2 cos theta_d)       (= N.H, H the half vector)
//                  cos phi_d   = (N.V - N.L) / (2 sin theta_h sin theta_d).
//                The table is the rusinkiewicz table at that one theta_d: shape {N0, N1, 1},
//                theta_h = (pi/2) (i/(N0-1))^2 (square map), phi_d = pi j/(N1-1), bilinear.
//                (A uniform grid over (N.L, N.V) itself was tried and dropped: the specular peak
//                N = H lies on the boundary of the feasible (N.L, N.V) region, and at 512 x 512
//                its measured max relative error was still 0.24 / 0.11 / 0.32 for polished /
//                intermediate / rough Au (mbk, sigma_s = 0.01 / 0.1 / 0.5 um, l_c = 2 / 2 / 5 um),
//                against 0.013 / 0.0039 / 0.0052 for 256 x 128 nodes in (theta_h, phi_d).)
//                lookup() uses only (theta_h, phi_d) of the geometry: queries must have
//                cos 2theta_d = L.V (brdf eval --lut checks it).
//  kernel        The factored form of the ASF models (mbk, mbk-fg, bk, bk-modified), issue 9:
//                  f = K(theta_i) x P(theta_h, theta_d, phi_d) x (pi l_c^2/lambda^2) x Sigma(g, c)
//                K(theta_i) per channel in the side table; P = F(theta_d) P~ the angular
//                factor (Qbar for mbk, F G/S for mbk-fg, F F_bk^2 for bk, F/S for bk-modified:
//                the model with A = 1, divided by K), with the exact Fresnel F(theta_d) of the
//                channel's n + i kappa (libbrdf:kernel_index) evaluated at lookup and P~ = P/F,
//                smooth and ~1 near specular (for bk and bk-modified P~ = F_bk^2 of eq. 26 and
//                1/S of eq. 28 are closed forms of the geometry, evaluated at lookup: their
//                table holds P~ / that, i.e. 1), on a node grid over (theta_h uniform, theta_d,
//                phi_d) (default 54^3: 1.9 MB for 3 channels; read with Catmull-Rom cubic interpolation on
//                each axis, end nodes repeated: trilinear left 0.12-0.16% max error, cubic 1.4e-4);
//                Sigma(g, c) from the universal kernel table
//                (kernel_table.h, not stored in the file: the same for every material, computed
//                at libbrdf's build and carried by the library; other readers recompute it),
//                g = (2 pi sigma_s/lambda)^2 (N.L + N.V)^2 and
//                c = pi^2 (l_c/lambda)^2 eta_r^2 from the per-channel sigma_s/lambda and
//                l_c/lambda (Lut::kernel_sigma_over_lambda, kernel_lc_over_lambda; file header
//                attributes libbrdf:kernel_sigma_over_lambda and libbrdf:kernel_lc_over_lambda).
//                Sigma at kKernelLayoutSigmaTolerance (below): the kernel table's fine tier,
//                outside its domain closed forms or the series. All the sharpness of the lobe
//                is in Sigma, so a small P table holds polished surfaces as well as rough ones.
//                Lut::kernel_angular (header attribute libbrdf:kernel_angular, absent = table)
//                says which part of P is closed form: `table` as above; `closed-form` (the
//                default of `brdf bake --layout kernel`) evaluates all of P at lookup (mbk:
//                Stover's Qbar from kernel_index; bk, bk-modified as above; mbk-fg: F(theta_d) G/S,
//                S of eq. 22 and the G of microfacet.h with the channel's sigma_g and G term,
//                Lut::kernel_sigma_g and kernel_g_term, header attributes libbrdf:kernel_sigma_g and
//                libbrdf:kernel_g_term) and its table holds P~ = 1 on 2^3 nodes (checked when read
//                or written; lookups do not interpolate it). mbk's lookups take Qbar in single
//                precision where 1e-3 <= |eps| <= 100 and |eps - 1| >= 1e-3 (every built-in
//                material): within 3e-5 of the double Qbar, against the 1e-3 promised. Why: Qbar is not smooth everywhere. For n < 1 (k = 0) it and F(theta_d) have square-root kinks at
//                the critical angle (measured: n = 0.5 tabulated at 54^3, max relative error 0.78,
//                at theta_d = 30 deg), and for metals with large kappa at short l_c it is steep at
//                grazing (Al, sigma_s = 0.05 um, l_c = 1 um: 4.5e-3); closed form, only K (1D) and
//                Sigma are interpolated. mbk-fg's G/S is steep near grazing: tabulated at 54^3 it erred by
//                5.7e-3 on a polished surface (sigma_s = 0.02 um, l_c = 2 um, n = 1.5 + 1i, at
//                forward-specular geometries with both polar angles 80-85 deg, where Smith's G
//                falls to 0.96 at 85 deg for sigma_g = 0.073) and by 2e-2-1e-1 with the V-groove G's
//                kink or without G (1/S alone); closed form: <= 7.5e-5. Renderers that cannot
//                evaluate Qbar or Smith's G (the Blender node graph) bake the `table` form.
//                Readers before mbk-fg's closed form refuse its files (kernel_angular 'closed-form'
//                was not allowed for mbk-fg).
// Nodes whose incident or scattered direction lies on or below the horizon (theta >= 90 deg, e.g.
// theta_d = 90 deg, or theta_h + theta_d > 90 deg in the incidence plane) hold the model at those
// directions with the polar angles limited to kHorizonThetaLimitDeg (azimuths unchanged); for the
// models with the ASF A of eq. 11 (mbk, mbk-fg, bk, bk-modified) A is that of the node's own
// (theta_h, theta_d) -- it does not depend on phi_d (g and c depend on cos ti + cos ts =
// 2 cos td cos th and eta_r = 2 cos td sin th) and is real for every theta_h, theta_d < 90 deg.
// A continuous extension (equal to the model on the horizon), reached by real queries only
// through interpolation in the cells next to the horizon (whose error the measurement includes).
// Always alongside, per channel: R_spec(theta_i) (the specular spike's reflectance) and K(theta_i)
// on a uniform theta_i node grid over [0, 90] deg (kThetaINodes nodes, linear interpolation).
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "libbrdf/geometry.h"
#include "libbrdf/image_file.h"
#include "libbrdf/models.h"

namespace libbrdf {

enum class LutLayout { rusinkiewicz, merl, slice, kernel };
// The relative tolerance of the kernel layout's Sigma(g, c) at lookup (asf_auto): the kernel
// table's fine tier (certified 1e-6, 5.2 MB; kernel_table.h). Stops 24-28 read the coarse tier
// (1e-4), because the fine one was then 41 MB of Hermite nodes over which a lookup's queries spread
// (3-channel closed-form lookups 1.16x slower). With the spline tables (stop 29; bench_lookup, one
// CPU, three alternated runs, gold on the three surfaces) the fine tier costs 4-5%: closed form
// 4.26-4.41e7 -> 4.07-4.29e7 lookups/s, P~ table 1.70-1.73e7 -> 1.58-1.67e7; and the closed form's
// max error there 1.9e-6 / 8.9e-6 / 1.2e-5 -> 1.9e-6 / 1.9e-6 / 4.2e-6. kernel_layout_audit.py's 22
// materials: max 3.4e-5 -> 3.0e-5 (Si, rough, mbk-fg, tis: its K and P~, not Sigma), bk 8.7e-6 ->
// 1.4e-7, bk-modified 4.7e-6 -> 5.6e-8, mbk-fg 8.6e-6 -> 9.8e-7 (values above 1e-6 of the peak).
inline constexpr double kKernelLayoutSigmaTolerance = 1e-6;
// Kernel layout: which part of the angular factor P is tabulated (see "kernel" above).
enum class KernelAngular { table, closed_form };
std::string_view layout_name(LutLayout layout);
LutLayout layout_from_name(std::string_view name);  // throws InvalidArgument("layout", ...)
// "N0xN1xN2" ("N0xN1" for the 2D slice layout), for messages and reports.
std::string shape_text(const std::array<int, 3>& shape, LutLayout layout);

// Polar angle (deg) that stands in for directions on or below the horizon in table nodes (see above).
inline constexpr double kHorizonThetaLimitDeg = 89.9;
// Nodes of the 1D R_spec and K tables: theta_i = 90 deg * i / (kThetaINodes - 1), 1/16 deg apart
// (R_spec = F exp(-g(ti, ti)) of rough surfaces rises steeply near grazing: at 1/4 deg spacing its
// linear interpolation erred by 1% for sigma_s = 0.5 um at 0.45 um).
inline constexpr int kThetaINodes = 1441;
// The MERL binary grid.
inline constexpr std::array<int, 3> kMerlShape{90, 90, 180};

// A unit direction in world space (slice layout). x, y, z; normalized on use.
struct Direction {
  double x = 0.0, y = 0.0, z = 1.0;
};

// Rusinkiewicz half/difference angles (radians) of one geometry; phi_d folded into [0, pi] by the
// mirror symmetry of isotropic BRDFs.
struct HalfDifferenceAngles {
  double theta_h = 0.0, theta_d = 0.0, phi_d = 0.0;
};
HalfDifferenceAngles half_difference_angles(const ScatterGeometry& geo);
// Inverse: the (theta_i, theta_s, phi_s) of a half/difference triple (phi_h = 0). Polar angles of
// directions at or below the horizon come out >= pi/2 (callers decide what to do with them).
ScatterAngles scatter_angles_from_half_difference(const HalfDifferenceAngles& hd);

// The error a table claims is measured where both polar angles are <= this (deg). Within a few
// degrees of the horizon every MBK/BK value falls to 0 like (cos ti + cos ts)^2 (g of eq. 12), and
// linear interpolation of such a zero has O(1) relative error in the cells next to it at any
// resolution: the relative error there is reported apart (LutError::max_relative_all).
inline constexpr double kErrorThetaLimitDeg = 85.0;

// Relative error statistics of a table against direct evaluation of its model.
struct LutError {
  double max_relative = 0.0;   // max over samples of |lut - model| / model (polar angles <= theta_limit_deg)
  double rms_relative = 0.0;
  double floor = 0.0;          // samples whose model value is below this (1/sr) are ignored
  int samples = 0;             // values compared: random off-grid points x channels, above the floor
  double theta_limit_deg = kErrorThetaLimitDeg;  // domain of max_relative and rms_relative
  double max_relative_all = 0.0;  // max over every real geometry, up to the horizon (for information)
};

class Lut {
 public:
  LutLayout layout = LutLayout::rusinkiewicz;
  std::vector<double> wavelengths_um;       // one per channel
  std::array<int, 3> shape{0, 0, 0};        // nodes per axis (slice: {N_theta_h, N_phi_d, 1})
  std::vector<float> values;                // [channel][i0][i1][i2], 1/sr
  std::vector<std::vector<float>> specular_reflectance;  // [channel][theta_i node], dimensionless
  std::vector<std::vector<float>> renormalization;       // [channel][theta_i node], K
  Direction light, view;                    // slice layout only (world space, towards light/camera)
  std::vector<double> kernel_sigma_over_lambda, kernel_lc_over_lambda;  // kernel layout only, per channel
  std::vector<ComplexIndex> kernel_index;   // kernel layout only: n + i kappa per channel (F(theta_d))
  ModelKind kernel_model = ModelKind::mbk;  // kernel layout only: bk and bk-modified have closed-form P~
  KernelAngular kernel_angular = KernelAngular::table;  // kernel layout only: what the P table holds
  std::vector<double> kernel_sigma_g;        // kernel layout, mbk-fg closed form: sigma_g per channel (Model::sigma_g)
  std::vector<GeometricTerm> kernel_g_term;  // kernel layout, mbk-fg closed form: G per channel
  LutError error;                           // measured at bake time, stored in the file
  std::map<std::string, std::string> attributes;  // model name, parameters, version, ... (file metadata)

  int channels() const { return static_cast<int>(wavelengths_um.size()); }
  std::size_t nodes_per_channel() const {
    return static_cast<std::size_t>(shape[0]) * static_cast<std::size_t>(shape[1]) * static_cast<std::size_t>(shape[2]);
  }
  // Interpolated BRDF value (1/sr) of one channel at one geometry. For the slice layout only
  // (theta_h, phi_d) are used (see above).
  double lookup(int channel, const ScatterGeometry& geo) const;
  // All channels at one geometry (values[c], c < channels()): the table coordinates are computed
  // once, from dot products and a polynomial arctangent, no acos/atan2 calls (see lut.cpp).
  void lookup_all(const ScatterGeometry& geo, double* values) const;
  // Interpolated R_spec and K of one channel at theta_i (radians).
  double specular_at(int channel, double theta_i) const;
  double renormalization_at(int channel, double theta_i) const;
};

// A table prepared for many lookups of all its channels (a renderer's RGB, brdf bench): the
// trilinear layouts (rusinkiewicz, MERL) with 2 to 4 channels keep a channel-interleaved copy of
// the nodes (each node's channels side by side), so that a lookup reads its cell's four rows once
// for every channel -- ~5 cache lines where the planar `values` need 4 per channel. Values are
// those of lookup_all_batch, bit for bit (every Highway target). Measured (bench/bench_lookup, 3
// channels, 1e6 streaming queries, one CPU, against lookup_all_batch in the same run): MERL size
// 1.37-1.42x faster, 90^3 1.02-1.04x, 48^3 0.98-1.00x (docs/performance.md, "brdf bake"). The kernel layout's
// P~ table (kernel_angular table) with 2 to 4 channels is interleaved too: a stencil row of every
// channel is one run of floats (one vector of 16 floats on AVX-512 for RGB, where planar rows take
// one vector of 4 per channel): 3-channel lookups 1.10-1.32x faster than lookup_all_batch in the
// same run (docs/performance.md, stop 27). Other layouts and channel counts look up as lookup_all_batch does.
// Holds its own copy of the table plus the interleaved nodes (as many floats as `values`); move a
// Lut in to save one copy.
class LutSampler {
 public:
  // Throws LutFileError (image_file.h) if the table is not self-consistent (shape, sizes, finite values).
  explicit LutSampler(Lut lut);
  const Lut& lut() const { return lut_; }
  // values[k * lut().channels() + c] at geometries[k], on the calling thread; a geometry with a
  // non-finite field it reads is refused as by lookup_all_batch (batch.h: InvalidQuery). At
  // angles, validated and in parallel: lookup_all_batch(sampler, angles, ...).
  void lookup_all(const ScatterGeometry* geometries, std::size_t count, double* values) const;

 private:
  Lut lut_;
  std::vector<float> interleaved_;  // empty: lookups as lookup_all_batch
};

// The angles a node of a table of this layout/shape stands for (polar angles already limited to
// kHorizonThetaLimitDeg where the node lies at or below the horizon). Slice: i2 = 0.
// theta_d of a slice: half the angle between L and V (eq. 5: cos 2theta_d = L.V).
double slice_theta_d(const Direction& light, const Direction& view);
ScatterAngles lut_node_angles(LutLayout layout, const std::array<int, 3>& shape, int i0, int i1, int i2,
                              const Direction& light = {}, const Direction& view = {});

// What to bake.
struct BakeRequest {
  ModelKind model = ModelKind::mbk;           // must be a BRDF (is_brdf)
  std::vector<ModelParameters> channels;      // one per wavelength
  LutLayout layout = LutLayout::rusinkiewicz;
  // Kernel layout: closed_form (all of P evaluated at lookup, every ASF model) or table. The default
  // table shape of closed_form is 2^3 (P~ = 1).
  KernelAngular kernel_angular = KernelAngular::closed_form;
  std::optional<std::array<int, 3>> resolution;  // nodes per axis; absent = default or target_error
  std::optional<double> target_error;         // smallest table whose measured max relative error meets it
  Direction light, view;                      // slice layout
  double error_floor_fraction = 1e-3;         // floor = fraction x the table's max value (inside the domain)
  double error_theta_limit_deg = kErrorThetaLimitDeg;  // error domain: both polar angles <= this
  int error_samples = 20000;                  // values compared (see measure_lut_error)
  std::uint64_t seed = 1;
  std::function<void(double fraction_done)> progress;  // optional, called from the calling thread;
                                                       // restarts at 0 for each table of a target search
  // Optional, called from the calling thread after each table of a --target-error search.
  std::function<void(const std::array<int, 3>& shape, const LutError& error)> trial_done;
  const std::atomic<bool>* cancel = nullptr;           // optional: set to abort (throws BakeCancelled)
};

// Default node counts when neither resolution nor target_error is given.
std::array<int, 3> default_resolution(LutLayout layout);
// --target-error search: the first table is this, each next one grows every axis by
// kTargetGrowthFactor (rounded up), up to kMaxTargetNodes nodes per channel.
std::array<int, 3> target_error_start_resolution(LutLayout layout);
inline constexpr double kTargetGrowthFactor = 1.25;
inline constexpr std::size_t kMaxTargetNodes = std::size_t{1} << 24;

struct BakeCancelled : std::runtime_error {
  BakeCancelled() : std::runtime_error("bake cancelled") {}
};

// Bakes (multi-threaded) and measures the error at random off-grid points.
Lut bake(const BakeRequest& request);

// Measures a table's error against direct evaluation of `model` (one Model per channel). Samples
// are uniform in the table's own index space (every cell is tested alike), off the nodes, and
// restricted to real geometries (both directions above the horizon); max/rms count those with
// both polar angles <= theta_limit_deg, max_relative_all counts all. Points are drawn until
// `samples` values (points x channels) above the floor were compared inside that domain, or
// 50 x samples points were drawn. floor = floor_fraction x the largest value of the nodes inside
// the domain.
LutError measure_lut_error(const Lut& lut, const std::vector<Model>& models, int samples, double floor_fraction,
                           std::uint64_t seed, double theta_limit_deg = kErrorThetaLimitDeg);

// Random real geometries drawn uniformly in a layout's index space -- (sqrt(theta_h / (pi/2)),
// theta_d, phi_d) for rusinkiewicz and merl, (sqrt(theta_h / (pi/2)), phi_d) at the directions'
// theta_d for slice -- keeping those with both polar angles <= theta_limit_deg. The sampling of
// measure_lut_error, for comparisons outside a table (brdf bench).
std::vector<ScatterAngles> random_table_geometries(LutLayout layout, int count, double theta_limit_deg,
                                                   std::uint64_t seed, const Direction& light = {},
                                                   const Direction& view = {});

// LutFileError (unreadable, truncated, corrupt or foreign files) is declared in image_file.h.

// OpenEXR (through image_file.h), metadata as "libbrdf:<key>" string header attributes (layout,
// shape, axes, texel convention, model, parameters, wavelengths, measured error, version, ...).
// Subimage 0 "brdf": the table as a float32 image, one channel per wavelength (R,G,B for three);
// rusinkiewicz/merl: width N2, height N0*N1, pixel (x, y) = node (y / N1, y % N1, x); slice: width
// N1, height N0. Subimage 1 "side_tables": width kThetaINodes, row 0 R_spec, row 1 K. Always
// float32: half (4.9e-4 relative rounding, maximum 65504) would eat half of a 1e-3 error budget
// and overflow the peaks of polished surfaces.
// Written to a temporary beside `path` and renamed: a failed write leaves no partial file.
// read_lut_exr throws LutFileError for anything that is not a complete, consistent libbrdf table.
void write_lut_exr(const Lut& lut, const std::string& path);
Lut read_lut_exr(const std::string& path);

// MERL binary (layout merl, exactly 3 channels), plus a JSON sidecar "<path>.json" with the header
// attributes and the R_spec / K tables (the format has no room for them). Without a sidecar
// read_merl_binary assigns wavelengths 0.65, 0.55, 0.45 um, R_spec = 0, K = 1, and says so in
// Lut::attributes["side_tables"].
// The pair is one unit: both files are written to temporaries and renamed together, sidecar first,
// under an exclusive flock(2) on the directory (image_file.h, PublicationGroup), so concurrent
// bakes to one path publish whole pairs in turn, and SIGINT/SIGTERM (cli/interrupt.h) never
// separates them. The sidecar carries "binary_crc32" (zlib CRC-32) and "binary_bytes" of the
// binary; read_merl_binary opens both under a shared flock and refuses a pair whose checksum
// differs (LutFileError "CRC-32 mismatch"), which is all a SIGKILL between the two renames can
// leave: a reader never uses a binary with another bake's sidecar. The reader also refuses
// negative, non-finite or out-of-range values.
void write_merl_binary(const Lut& lut, const std::string& path);
Lut read_merl_binary(const std::string& path);

// Reads either format, chosen by content (EXR magic number, else MERL binary).
Lut read_lut_file(const std::string& path);

// What a scene needs baked (docs/scene.md): layout, directions and channels chosen from a small
// JSON scene description. Throws InvalidArgument("scene", ...) naming the file and the problem.
struct ScenePlan {
  LutLayout layout = LutLayout::rusinkiewicz;
  Direction light, view;               // slice layout
  std::vector<double> wavelengths_um;  // empty = the caller's default
  std::string reason;                  // one line: why this layout
};
ScenePlan plan_scene_bake(const std::string& scene_json_path);

}  // namespace libbrdf
