// OpenEXR files of baked tables (read and written through image_file.h, i.e. OpenEXR itself).
//
// File layout (also written into the header as libbrdf:storage):
//   subimage 0 "brdf": the table as a 2D float32 image, one channel per wavelength.
//     rusinkiewicz / merl: width N2, height N0*N1; pixel (x, y) = node (i0, i1, i2) with
//       y = i0 * N1 + i1 (row 0 at the top), x = i2.
//     slice: width N1 (phi_d), height N0 (theta_h); pixel (x, y) = node (i0 = y, i1 = x).
//     Channel names: "R","G","B" for three channels (in the wavelengths' order), "Y" for one,
//     "C00","C01",... otherwise; libbrdf:wavelengths_um lists the wavelengths in channel order.
//   subimage 1 "side_tables": width kThetaINodes, height 2, same channels: row 0 R_spec(theta_i),
//     row 1 K(theta_i), x = m at theta_i = 90 deg * m / (width - 1).
//   Every libbrdf header attribute is a string named "libbrdf:<key>" (numbers at 17 digits).
// Storage is float32 throughout: half (11-bit significand: 4.9e-4 relative rounding, maximum
// 65504) would take half of a 1e-3 error budget and overflow the peaks of polished surfaces
// (an mbk-polished peak reaches ~1e5 1/sr at l_c/lambda = 100). Compression: ZIP (lossless).
#include <algorithm>
#include <cstdio>

#include "libbrdf/image_file.h"
#include "libbrdf/lut.h"
#include "lut_internal.h"

namespace libbrdf {
namespace {

constexpr const char* kPrefix = "libbrdf:";

std::vector<std::string> channel_names(int channels) {
  if (channels == 3) return {"R", "G", "B"};
  if (channels == 1) return {"Y"};
  std::vector<std::string> names;
  for (int c = 0; c < channels; ++c) {
    char name[16];
    std::snprintf(name, sizeof name, "C%02d", c);
    names.push_back(name);
  }
  return names;
}

std::string storage_text() {
  return "subimage 0 'brdf': float32, one channel per wavelength; rusinkiewicz/merl: width N2, height N0*N1, pixel "
         "(x, y) = node (i0 = y / N1, i1 = y % N1, i2 = x), row 0 at the top; slice: width N1, height N0, pixel (x, y) "
         "= node (theta_h index y, phi_d index x). subimage 1 'side_tables': width theta_i_nodes, height 2, row 0 R_spec(theta_i), "
         "row 1 K(theta_i).";
}

// Index of each wanted channel in a part read back (OpenEXR stores channels sorted by name).
std::vector<std::size_t> channel_order(const ExrPart& part, const std::vector<std::string>& names, const std::string& path,
                                       const char* what) {
  std::vector<std::size_t> order;
  for (const std::string& name : names) {
    const auto it = std::find(part.channel_names.begin(), part.channel_names.end(), name);
    if (it == part.channel_names.end()) throw LutFileError(path + ": channel '" + name + "' missing in the " + what);
    order.push_back(static_cast<std::size_t>(it - part.channel_names.begin()));
  }
  return order;
}

}  // namespace

void write_lut_exr(const Lut& lut, const std::string& path) {
  detail::check_lut_consistency(lut, path);
  std::map<std::string, std::string> metadata = detail::lut_metadata(lut);
  metadata["storage"] = storage_text();
  const int channels = lut.channels();
  const bool slice = lut.layout == LutLayout::slice;
  const int side_width = static_cast<int>(lut.specular_reflectance[0].size());

  ExrPart table{"brdf", slice ? lut.shape[1] : lut.shape[2], slice ? lut.shape[0] : lut.shape[0] * lut.shape[1],
                channel_names(channels), {}, {}};
  ExrPart side{"side_tables", side_width, 2, channel_names(channels), {}, {}};
  for (const auto& [key, value] : metadata) table.attributes[kPrefix + key] = value;
  side.attributes[std::string(kPrefix) + "rows"] = "row 0 R_spec(theta_i), row 1 K(theta_i)";

  // Interleave [channel][node] into pixels.
  const std::size_t nodes = lut.nodes_per_channel();
  table.pixels.resize(nodes * channels);
  side.pixels.resize(static_cast<std::size_t>(side_width) * 2 * channels);
  for (int c = 0; c < channels; ++c) {
    for (std::size_t i = 0; i < nodes; ++i) table.pixels[i * channels + c] = lut.values[c * nodes + i];
    for (int m = 0; m < side_width; ++m) {
      side.pixels[static_cast<std::size_t>(m) * channels + c] = lut.specular_reflectance[c][m];
      side.pixels[static_cast<std::size_t>(side_width + m) * channels + c] = lut.renormalization[c][m];
    }
  }
  write_exr(path, {table, side});
}

Lut read_lut_exr(const std::string& path) {
  const std::vector<ExrPart> parts = read_exr(path);
  const ExrPart& table = parts[0];
  std::map<std::string, std::string> metadata;
  const std::string prefix = kPrefix;
  for (const auto& [name, value] : table.attributes)
    if (name.compare(0, prefix.size(), prefix) == 0) metadata[name.substr(prefix.size())] = value;
  if (metadata.find("format") == metadata.end())
    throw LutFileError(path + ": not a libbrdf table (no libbrdf:format header attribute)");

  Lut lut;
  detail::restore_from_metadata(lut, metadata, path);
  const int channels = lut.channels();
  const bool slice = lut.layout == LutLayout::slice;
  const long long width = slice ? lut.shape[1] : lut.shape[2];
  const long long height = slice ? static_cast<long long>(lut.shape[0]) : static_cast<long long>(lut.shape[0]) * lut.shape[1];
  if (table.width != width || table.height != height || static_cast<int>(table.channel_names.size()) != channels)
    throw LutFileError(path + ": image size " + std::to_string(table.width) + "x" + std::to_string(table.height) + "x" +
                       std::to_string(table.channel_names.size()) + " does not match the header's shape and channels");
  const std::vector<std::string> names = channel_names(channels);
  const std::vector<std::size_t> order = channel_order(table, names, path, "table");
  const std::size_t stored = table.channel_names.size();
  const std::size_t nodes = lut.nodes_per_channel();
  lut.values.resize(nodes * channels);
  for (int c = 0; c < channels; ++c)
    for (std::size_t i = 0; i < nodes; ++i) lut.values[c * nodes + i] = table.pixels[i * stored + order[c]];

  if (parts.size() < 2) throw LutFileError(path + ": the R_spec/K subimage is missing");
  const ExrPart& side = parts[1];
  if (side.width < 2 || side.height != 2 || static_cast<int>(side.channel_names.size()) != channels)
    throw LutFileError(path + ": the R_spec/K subimage has the wrong size");
  const std::vector<std::size_t> side_order = channel_order(side, names, path, "R_spec/K subimage");
  lut.specular_reflectance.assign(channels, std::vector<float>(side.width));
  lut.renormalization.assign(channels, std::vector<float>(side.width));
  for (int c = 0; c < channels; ++c) {
    for (int m = 0; m < side.width; ++m) {
      lut.specular_reflectance[c][m] = side.pixels[static_cast<std::size_t>(m) * stored + side_order[c]];
      lut.renormalization[c][m] = side.pixels[static_cast<std::size_t>(side.width + m) * stored + side_order[c]];
    }
  }
  detail::check_lut_consistency(lut, path);
  return lut;
}

}  // namespace libbrdf
