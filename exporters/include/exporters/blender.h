#pragma once
// Blender export of a baked rusinkiewicz table (`brdf export blender`), read by the add-on in
// blender_addon/libbrdf_materials/ and by the OSL shader generated beside it.
//
// Three artefacts per material, one stem:
//   STEM.exr   the atlas: the 3D table (theta_h, theta_d, phi_d) x RGB packed into one float RGB
//              image, plus one row with R_spec(theta) (the specular spike's reflectance).
//   STEM.json  the description the add-on builds its node group from: atlas geometry, axis
//              mapping, the table's measured error; in FIT mode the fitted GGX lobes (fit.h) and
//              their measured error; always the specular spike's parameters.
//   STEM.osl   (mode osl) an OSL shader doing the same lookup with texture() on STEM.exr.
//
// Atlas layout (also written into the EXR header and the JSON):
//   Tile k (k = phi_d index, 0..N2-1) sits at column k % C, tile row k / C; inside a tile the
//   texel x is the theta_h index i0 (0..N0-1) and y the theta_d index i1 (0..N1-1):
//       x = (k % C) N0 + i0,   y = (k / C) N1 + i1,
//   with y counted from the BOTTOM row of the image (Blender's and OpenGL's v = 0). The texel of
//   node (i0, i1, k) has its centre at u = (x + 0.5)/W, v = (y + 0.5)/H; OSL's t runs from the
//   top, t = 1 - v. Row y = R N1 (R = tile rows) holds R_spec at theta_i = 90 deg j/(M-1),
//   j = 0..M-1 (texels x = j). Unused texels are 0.
//   Readers sample with Closest interpolation at texel centres and interpolate between nodes
//   themselves (trilinear; linear for R_spec): a Linear-filtered, mip-mapped GPU lookup (EEVEE)
//   would blend across tile edges, a Closest one at a texel centre never does, so tiles need no
//   padding. The node angles are the rusinkiewicz layout's (lut.h):
//       theta_h = (pi/2) (i0/(N0-1))^2,  theta_d = (pi/2) i1/(N1-1),  phi_d = pi k/(N2-1),
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
  int specular_nodes = 0;             // M (R_spec nodes over theta in [0, 90] deg)
  int specular_row = 0;               // y of the R_spec row (= R N1)
  int width = 0, height = 0;          // W, H in texels
};

// The atlas geometry of a table of this shape with an M-node R_spec row: C chosen so that the
// image is about square and at least M texels wide.
BlenderAtlas blender_atlas_layout(const std::array<int, 3>& shape, int specular_nodes);

// RGB float texels of the atlas, [y][x][3] with y = 0 the bottom row. Throws InvalidArgument
// ("wavelength") unless the table has 1 or 3 channels or ("layout") if it is not rusinkiewicz.
std::vector<float> blender_atlas_texels(const Lut& lut, const BlenderAtlas& atlas);

// Writes the atlas as a float32 RGB OpenEXR (temporary + rename), the layout above in its header.
void write_blender_atlas_exr(const Lut& lut, const BlenderAtlas& atlas, const std::string& path);

// The specular spike's mirror lobe in FIT mode (and its parameters in every description):
// R_spec(theta_v) = F(theta_v) exp(-g0 cos^2 theta_v) exactly (conventions.md), with F taken as
// Schlick's from the exact F(0) (node graphs have no complex Fresnel).
struct SpikeFit {
  std::vector<double> f0;   // exact Fresnel reflectance at normal incidence, F(0), per channel
  std::vector<double> g0;   // g(0, 0) = (4 pi sigma_s / lambda)^2 per channel
  bool has_spike = false;   // the model has a specular spike (MBK and BK families)
};
SpikeFit spike_fit(ModelKind kind, const std::vector<ModelParameters>& channels);

// What the add-on needs to build the material (see blender_addon/libbrdf_materials/nodegraph.py).
struct BlenderExport {
  std::string name;                    // material / shader name
  std::string mode;                    // lut | osl | fit
  ModelKind model = ModelKind::mbk;
  std::vector<ModelParameters> channels;
  const Lut* lut = nullptr;            // lut, osl
  BlenderAtlas atlas;                  // lut, osl
  std::string atlas_file;              // file name of the atlas, relative to the description
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

// The OSL shader source for the atlas (osl.cpp). `atlas_path` is the default of its Atlas
// parameter (absolute, so that texture() finds it from any working directory).
std::string osl_shader_source(const BlenderAtlas& atlas, const std::string& shader_name,
                              const std::string& atlas_path, const std::string& header_comment);

// An OSL identifier from any text: [A-Za-z0-9_], not starting with a digit, "libbrdf_" prefixed.
std::string osl_identifier(const std::string& text);


}  // namespace libbrdf::blender
