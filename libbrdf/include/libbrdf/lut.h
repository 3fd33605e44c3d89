#pragma once
// Baked tables (LUTs) of a BRDF model, their bake (error-bounded), lookup, and files.
// OpenEXR / OpenImageIO stay in the sources; this header uses the standard library only.
//
// Layouts (axis mapping and texel convention are also written into every file's header):
//  rusinkiewicz  3D over (theta_h, theta_d, phi_d) (S. Rusinkiewicz, EGWR 1998), isotropic.
//                Node grid: values sit on the nodes, first/last node on the range ends, trilinear.
//                theta_h = (pi/2) (i/(N0-1))^2   square map: nodes dense at the specular peak
//                theta_d = (pi/2) i/(N1-1)
//                phi_d   = pi i/(N2-1)           phi_d and -phi_d are equal for isotropic BRDFs
//  merl          The MERL binary layout (Matusik et al., ACM TOG 22, 759, 2003): 90 x 90 x 180,
//                theta_h = (pi/2)(i/90)^2, theta_d = (pi/2) i/90, phi_d = pi i/180 (the angles
//                MERL's reference reader floors back to index i), channel scales 1/1500,
//                1.15/1500, 1.66/1500, doubles. In memory it is the same node grid (no node on
//                the upper range ends; lookups beyond the last node hold its value).
//  slice         2D, for a scene lit by a sun and seen by a distant (orthographic) camera:
//                the light and view directions are fixed in the WORLD, the normal varies.
//                For fixed L, V the BRDF depends on the normal only through
//                (cos ti, cos ts) = (N.L, N.V), since cos 2theta_d = L.V fixes phi_s (eq. 5).
//                Axes u = N.L in [0, 1], v = N.V in [0, 1], uniform node grids, bilinear.
//                Infeasible (u, v) (no unit N gives them) hold the nearest feasible value so
//                that interpolation near the edge stays smooth; they are never looked up by a
//                real normal.
// Always alongside, per channel: R_spec(theta_i) (the specular spike's reflectance) and K(theta_i)
// on a uniform theta_i node grid over [0, 90] deg.
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "libbrdf/geometry.h"
#include "libbrdf/models.h"

namespace libbrdf {

enum class LutLayout { rusinkiewicz, merl, slice };
std::string_view layout_name(LutLayout layout);
LutLayout layout_from_name(std::string_view name);  // throws InvalidArgument("layout", ...)

// A unit direction in world space (slice layout). x, y, z; normalized on use.
struct Direction {
  double x = 0.0, y = 0.0, z = 1.0;
};

// Relative error statistics of a table against direct evaluation of its model.
struct LutError {
  double max_relative = 0.0;   // max over samples of |lut - model| / model
  double rms_relative = 0.0;
  double floor = 0.0;          // samples whose model value is below this (1/sr) are ignored
  int samples = 0;             // random off-grid points used
};

class Lut {
 public:
  LutLayout layout = LutLayout::rusinkiewicz;
  std::vector<double> wavelengths_um;       // one per channel
  std::array<int, 3> shape{0, 0, 0};        // nodes per axis (slice: {N_u, N_v, 1})
  std::vector<float> values;                // [channel][i0][i1][i2], 1/sr
  std::vector<std::vector<float>> specular_reflectance;  // [channel][theta_i node], dimensionless
  std::vector<std::vector<float>> renormalization;       // [channel][theta_i node], K
  Direction light, view;                    // slice layout only (world space, towards light/camera)
  LutError error;                           // measured at bake time, stored in the file
  std::map<std::string, std::string> attributes;  // model name, parameters, version, ... (file metadata)

  int channels() const { return static_cast<int>(wavelengths_um.size()); }
  // Interpolated BRDF value (1/sr) of one channel at one geometry. For the slice layout only
  // (cos ti, cos ts) are used (see above).
  double lookup(int channel, const ScatterGeometry& geo) const;
  // Interpolated R_spec and K of one channel at theta_i (radians).
  double specular_at(int channel, double theta_i) const;
  double renormalization_at(int channel, double theta_i) const;
};

// What to bake.
struct BakeRequest {
  ModelKind model = ModelKind::mbk;           // must be a BRDF (is_brdf)
  std::vector<ModelParameters> channels;      // one per wavelength
  LutLayout layout = LutLayout::rusinkiewicz;
  std::optional<std::array<int, 3>> resolution;  // nodes per axis; absent = default or target_error
  std::optional<double> target_error;         // smallest table whose measured max relative error meets it
  Direction light, view;                      // slice layout
  double error_floor_fraction = 1e-3;         // floor = fraction x the table's max value
  int error_samples = 20000;
  std::uint64_t seed = 1;
  std::function<void(double fraction_done)> progress;  // optional, called from the calling thread
  const std::atomic<bool>* cancel = nullptr;           // optional: set to abort (throws BakeCancelled)
};

struct BakeCancelled : std::runtime_error {
  BakeCancelled() : std::runtime_error("bake cancelled") {}
};

// Bakes (multi-threaded) and measures the error at random off-grid points.
Lut bake(const BakeRequest& request);

// Measures a table's error against direct evaluation of `model` (one Model per channel).
LutError measure_lut_error(const Lut& lut, const std::vector<Model>& models, int samples, double floor_fraction,
                           std::uint64_t seed);

// Thrown for unreadable, truncated, corrupt or foreign files: one line naming the file and the problem.
struct LutFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// OpenEXR through OpenImageIO (float32, or half where stated), metadata as header attributes.
// Written to a temporary beside `path` and renamed: a failed write leaves no partial file.
void write_lut_exr(const Lut& lut, const std::string& path);
Lut read_lut_exr(const std::string& path);

// MERL binary (layout merl, exactly 3 channels). Same temporary + rename rule.
void write_merl_binary(const Lut& lut, const std::string& path);
Lut read_merl_binary(const std::string& path);

}  // namespace libbrdf
