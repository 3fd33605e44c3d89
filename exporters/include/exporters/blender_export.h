#pragma once
// One Blender material export, as `brdf export blender` and the Python module's export_blender
// run it (formats: blender.h): validates the request, bakes (or reuses the shared images beside the
// output), fits FIT lobes, and publishes NAME.json with its NAME.exr / NAME.osl / shared images
// together (image_file.h: all or none, even when interrupted).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "libbrdf/models.h"

namespace libbrdf::blender {

struct MaterialExportRequest {
  ModelKind model = ModelKind::mbk;
  std::vector<ModelParameters> channels;  // 1 or 3 (R, G, B)
  std::string mode = "lut";               // lut | osl | fit
  std::string output;                     // DIR/NAME.json; DIR is created when missing
  std::optional<std::array<int, 3>> resolution;  // table nodes (lut/osl)
  std::optional<double> target_error;     // lut/osl: the table's; fit: the lobes' p95 (fit.h)
  std::string name;                       // material name (default: NAME of output)
};

struct MaterialExport {
  std::vector<std::string> written;  // the files this export wrote (shared images reused are not listed)
  std::string log;                   // what the CLI prints on stderr (the fit's measured error)
};

// Throws InvalidArgument naming the parameter (mode, output, model, wavelength, resolution,
// target-error) for a request outside its domain; errors of the bake as they come.
MaterialExport export_material(const MaterialExportRequest& request);

}  // namespace libbrdf::blender
