#pragma once
// Blender export (`brdf export blender`), read by the add-on in blender_addon/libbrdf_materials/
// and by the OSL shader generated beside it. Two table forms, chosen by the model:
//
// kernel (the ASF models mbk, mbk-fg, bk, bk-modified: kernel_export_model), the factored form of
// the kernel layout (lut.h, kernel_table.h), per channel (wavelength lambda):
//     f = K(theta_i) F(theta_d) P~(theta_h, theta_d, phi_d) C (pi l_c^2/lambda^2) Sigma(g, c)
//     g = (2 pi sigma_s/lambda)^2 (N.L + N.V)^2                               (eq. 12)
//     c = pi^2 (l_c/lambda)^2 eta_r^2,  eta_r^2 = |N x (L + V)|^2             (eq. 10; = |L+V|^2 - (N.L+N.V)^2)
//   C = 1 (mbk, mbk-fg), F_bk^2 = (L.H)^2 / ((N.L)^2 (N.H)^2) (bk, eq. 27),
//   1/S = (L.H)^2 / ((N.L)(N.V)(N.H)^2) (bk-modified, eq. 28), evaluated by the reader.
//   Three images:
//     STEM.exr                   side rows, per material: width M = kThetaINodes, y = 0 R_spec(theta),
//                                y = 1 K(theta), y = 2 F(theta), theta = 90 deg j/(M-1) (theta_i for
//                                R_spec and K, theta_d for F), linear between nodes.
//     libbrdf_angular_KEY.exr    the angular factor P~ of the kernel layout as an atlas (below, no side
//                                row): theta_h = (pi/2) i0/(N0-1) (uniform), theta_d, phi_d as below.
//                                KEY hashes what P~ depends on (angular_cache_key: not sigma_s, l_c
//                                except for mbk-fg): a roughness change reuses it.
//     libbrdf_sigma_KEY.exr      the universal Sigma image (SigmaImage), the same for every material.
//   Files named by a KEY are written only when absent (complete by the atomic rename).
//
// rusinkiewicz (every other model): one atlas STEM.exr: the 3D table (theta_h, theta_d, phi_d) x
//   RGB packed into one float RGB image, plus one row with R_spec(theta).
//
// STEM.json is the description the add-on builds its node group from (blender_description_json);
// STEM.osl (mode osl) an OSL shader doing the same lookup with texture().
//
// Atlas layout (also written into the EXR header and the JSON):
//   Tile k (k = phi_d index, 0..N2-1) sits at column k % C, tile row k / C; inside a tile the
//   texel x is the theta_h index i0 (0..N0-1) and y the theta_d index i1 (0..N1-1):
//       x = (k % C) N0 + i0,   y = (k / C) N1 + i1,
//   with y counted from the BOTTOM row of the image (Blender's and OpenGL's v = 0). The texel of
//   node (i0, i1, k) has its centre at u = (x + 0.5)/W, v = (y + 0.5)/H; OSL's t runs from the
//   top, t = 1 - v. rusinkiewicz only: row y = R N1 (R = tile rows) holds R_spec at
//   theta_i = 90 deg j/(M-1), j = 0..M-1 (texels x = j). Unused texels are 0.
//   Readers sample with Closest interpolation at texel centres and interpolate between nodes
//   themselves (trilinear; linear for the rows, bilinear for Sigma): a Linear-filtered, mip-mapped
//   GPU lookup (EEVEE) would blend across tile edges, a Closest one at a texel centre never does,
//   so tiles need no padding. The node angles are the layout's (lut.h):
//       theta_h = (pi/2) (i0/(N0-1))^2 (rusinkiewicz) or (pi/2) i0/(N0-1) (kernel),
//       theta_d = (pi/2) i1/(N1-1),  phi_d = pi k/(N2-1),
//   phi_d measured as in MERL's reader (lut.h), which gives, by spherical trigonometry in the
//   triangle (N, H, L) of the half-vector frame where N = (-sin th, 0, cos th) and
//   L = (sin td cos pd, sin td sin pd, cos td):
//       cos phi_d = (cos theta_h cos theta_d - N.L) / (sin theta_h sin theta_d)
//   (cos theta_h = N.H, cos theta_d = L.H, H = normalize(L + V)).
// Channels: R, G, B are the table's channels 0, 1, 2 (a one-channel table is repeated).
#include <array>
#include <string>
#include <vector>

#include "exporters/fit.h"
#include "libbrdf/lut.h"
#include "libbrdf/models.h"

namespace libbrdf::blender {

struct BlenderAtlas {
  std::array<int, 3> shape{0, 0, 0};  // table nodes (N0 theta_h, N1 theta_d, N2 phi_d)
  int columns = 0;                    // tiles per atlas row (C)
  int tile_rows = 0;                  // R
  int specular_nodes = 0;             // M (R_spec nodes over theta in [0, 90] deg); 0: no R_spec row
  int specular_row = 0;               // y of the R_spec row (= R N1)
  int width = 0, height = 0;          // W, H in texels
};

// The atlas geometry of a table of this shape with an M-node R_spec row (M = 0: none, the kernel
// form's angular atlas): C chosen so that the image is about square and at least M texels wide.
BlenderAtlas blender_atlas_layout(const std::array<int, 3>& shape, int specular_nodes);

// RGB float texels of the atlas, [y][x][3] with y = 0 the bottom row. Throws InvalidArgument
// ("wavelength") unless the table has 1 or 3 channels or ("layout") if it is not rusinkiewicz or kernel.
std::vector<float> blender_atlas_texels(const Lut& lut, const BlenderAtlas& atlas);

// Writes the atlas as a float32 RGB OpenEXR (temporary + rename), the layout above in its header.
void write_blender_atlas_exr(const Lut& lut, const BlenderAtlas& atlas, const std::string& path);

// ---- The kernel (factored) form --------------------------------------------------------------

// True for the models exported in the factored form (those the kernel layout factors).
bool kernel_export_model(ModelKind kind);

// The universal Sigma image: one float per texel (written as R = G = B),
//   S(x, z) = ln Sigma(g, c) - ln(g / (1 + g^2)) + z^2,   g = e^x, c = (g + 1) z^2,
// on nodes x_i = x_min + i dx (texel column i), z_j = j dz (texel row j from the bottom). ln g/(1+g^2)
// and -z^2 are ln Sigma's two ends (g e^-c for g << 1, e^-c/g / g for g >> 1), so S is nearly flat
// and bilinear interpolation of S is accurate where the two-ended Sigma bends: readers take
//   ln Sigma = S(clamp(x), min(z, z_max)) + x - ln(1 + g^2) - z^2
// (outside the nodes the image's edge continues both ends: Sigma -> g e^-c below x_min,
// e^-(c/g) / g above x_max, Gaussian in eta_r beyond z_max, where Sigma < e^-43 of Sigma(g, 0)).
// Node values are the library's Sigma (asf_auto at the kernel table's certified error: the
// kernel table's spline inside its domain, the closed forms outside).
struct SigmaImage {
  double x_min = 0.0, dx = 0.0, dz = 0.0;
  int width = 0, height = 0;
  double x_max() const { return x_min + (width - 1) * dx; }
  double z_max() const { return (height - 1) * dz; }
};
// x from ln kKernelGMin to >= ln kKernelGMax, z from 0 to kSigmaImageZMax.
SigmaImage sigma_image_layout();
// Bilinear error of S (= of ln Sigma) measured against an independent series at random (g, c) within
// e^-10 of Sigma(g, 0), 1e-5 <= g <= 1e3: max 2.1e-4 (tests/blender/test_nodegraph.py asserts 5e-4).
// dx is set by S's bend near g ~ 1 (dx = 0.06: 4.7e-4), dz by the switches of the dominant term m
// at small g (z ~ 3-5; dz = 0.03: 3.8e-4), both measured on a dense series grid.
// Blender roughness band where EEVEE 3.4's sun-lit GGX departs from analytic GGX (a white Glossy
// sphere against GGX, median / 5th-percentile ratio 0.78 / 0.00 at 0.5, 0.81 / 0.06 at 0.6, 0.98 /
// 0.49 at 0.75; 1.01 / 0.97 at 0.3, 1.04 / 0.97 at 1.0: docs/renderers.md, tools/calibrate/eevee_ggx_span.py).
// EEVEE's FIT lobes stay out of it (fit::FitRequest::excluded_alpha_*), so that the error the fit
// states is the one EEVEE renders.
inline constexpr double kEeveeGgxBandLow = 0.375, kEeveeGgxBandHigh = 0.875;

inline constexpr double kSigmaImageDx = 0.03;
inline constexpr double kSigmaImageDz = 0.02;
inline constexpr double kSigmaImageZMax = 12.0;
// S at every node, [row j][column i].
std::vector<float> sigma_image_values(const SigmaImage& image);
// File name (no directory) of the Sigma image of this libbrdf version and grid.
std::string sigma_image_file_name(const SigmaImage& image);
void write_sigma_image_exr(const SigmaImage& image, const std::string& path);

// What the angular factor P~ of a kernel bake depends on (model, channels' wavelength and index,
// resolution or target error; sigma_s and l_c only for mbk-fg, whose G uses sigma_g), as text, and
// the file name libbrdf_angular_<hash>.exr of its atlas.
std::string angular_cache_key(const std::vector<Model>& models, const std::string& table_request);
std::string angular_file_name(const std::string& key);

// Side rows of one material: width kThetaINodes, RGB, [row][x][3], rows R_spec(theta_i),
// K(theta_i), F(theta_d) (the exact Fresnel reflectance of the channel's index).
inline constexpr int kSideRows = 3;
std::vector<float> side_row_texels(const std::vector<Model>& models);
void write_side_rows_exr(const std::vector<Model>& models, const std::string& path);

// A kernel-layout Lut (for its error measurement) from a cached angular atlas and fresh models:
// P~ and the shape read back from the atlas at `angular_path`, K and R_spec from the models (no
// error, no attributes). Throws LutFileError if the file is not an angular atlas.
Lut kernel_lut_from_angular_atlas(const std::string& angular_path, const std::vector<Model>& models);

// ---- Description -----------------------------------------------------------------------------

// The specular spike's mirror lobe in FIT mode (and its parameters in every description):
// R_spec(theta_v) = F(theta_v) exp(-g0 cos^2 theta_v) exactly (conventions.md), with F taken as
// Schlick's from the exact F(0) (node graphs have no complex Fresnel).
struct SpikeFit {
  std::vector<double> f0;   // exact Fresnel reflectance at normal incidence, F(0), per channel
  std::vector<double> g0;   // g(0, 0) = (4 pi sigma_s / lambda)^2 per channel
  bool has_spike = false;   // the model has a specular spike (MBK and BK families)
};
SpikeFit spike_fit(ModelKind kind, const std::vector<ModelParameters>& channels);

// The kernel form's files and measured error (lut, osl modes of the ASF models).
struct KernelFiles {
  std::string side_file, angular_file, sigma_file;  // file names, relative to the description
  BlenderAtlas angular;                              // P~ atlas geometry (no R_spec row)
  SigmaImage sigma;
  bool angular_reused = false, sigma_reused = false;  // found beside the description, not rewritten
};

// What the add-on needs to build the material (see blender_addon/libbrdf_materials/nodegraph.py).
struct BlenderExport {
  std::string name;                    // material / shader name
  std::string mode;                    // lut | osl | fit
  ModelKind model = ModelKind::mbk;
  std::vector<ModelParameters> channels;
  const Lut* lut = nullptr;            // lut, osl: the rusinkiewicz table, or the kernel Lut (error, shape)
  BlenderAtlas atlas;                  // lut, osl (rusinkiewicz)
  std::string atlas_file;              // file name of the atlas, relative to the description (rusinkiewicz)
  const KernelFiles* kernel = nullptr; // lut, osl of the ASF models: the factored form instead of the atlas
  std::string osl_file;                // osl only
  std::string osl_shader_name;         // osl only
  SpikeFit spike;
  // fit mode (fit.h): Cycles renders Beckmann lobes exactly as fitted; EEVEE renders every
  // distribution as GGX (seen in Blender 3.4), so it gets GGX lobes of its own, through a second
  // Material Output with target EEVEE.
  const fit::NativeFit* lobes = nullptr;        // Beckmann (Cycles)
  const fit::NativeFit* lobes_eevee = nullptr;  // GGX (EEVEE)
};
// The JSON description (text, 2-space indent).
std::string blender_description_json(const BlenderExport& e);

// The OSL shader source for the rusinkiewicz atlas (osl.cpp). `atlas_path` is the default of its
// Atlas parameter (absolute, so that texture() finds it from any working directory).
std::string osl_shader_source(const BlenderAtlas& atlas, const std::string& shader_name,
                              const std::string& atlas_path, const std::string& header_comment);
// The OSL shader source of the kernel form (osl.cpp): parameters Side, Angular, SigmaImage (absolute
// paths of the three images, in `directory`), then the light inputs.
std::string osl_kernel_shader_source(const BlenderExport& e, const std::string& directory,
                                     const std::string& header_comment);

// An OSL identifier from any text: [A-Za-z0-9_], not starting with a digit, "libbrdf_" prefixed.
std::string osl_identifier(const std::string& text);

// Per channel (R, G, B; a one-channel material repeated) the kernel form's constants:
// g_scale = (2 pi sigma_s/lambda)^2, c_scale = pi^2 (l_c/lambda)^2, prefactor = pi (l_c/lambda)^2.
struct KernelChannel {
  double g_scale = 0.0, c_scale = 0.0, prefactor = 0.0;
};
std::array<KernelChannel, 3> kernel_channels(const std::vector<ModelParameters>& channels);
// "none", "bk_eq27" or "bk_modified_eq28": the closed-form factor C the reader multiplies.
std::string kernel_closed_form_name(ModelKind kind);

}  // namespace libbrdf::blender
