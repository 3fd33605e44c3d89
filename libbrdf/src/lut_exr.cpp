// OpenEXR files of baked tables, through OpenImageIO.
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
#include <OpenImageIO/imageio.h>

#include <cstring>
#include <fstream>

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

// First line of an OpenImageIO error message (they may span several lines).
std::string first_line(std::string text) {
  const auto end = text.find('\n');
  if (end != std::string::npos) text.resize(end);
  return text.empty() ? "unknown error" : text;
}

}  // namespace

void write_lut_exr(const Lut& lut, const std::string& path) {
  detail::check_lut_consistency(lut, path);
  std::map<std::string, std::string> metadata = detail::lut_metadata(lut);
  metadata["storage"] = storage_text();
  const int channels = lut.channels();
  const bool slice = lut.layout == LutLayout::slice;
  const int width = slice ? lut.shape[1] : lut.shape[2];
  const int height = slice ? lut.shape[0] : lut.shape[0] * lut.shape[1];
  const int side_width = static_cast<int>(lut.specular_reflectance[0].size());

  OIIO::ImageSpec specs[2] = {OIIO::ImageSpec(width, height, channels, OIIO::TypeDesc::FLOAT),
                              OIIO::ImageSpec(side_width, 2, channels, OIIO::TypeDesc::FLOAT)};
  for (OIIO::ImageSpec& spec : specs) {
    spec.channelnames = channel_names(channels);
    spec.attribute("compression", "zip");
  }
  // OpenEXR multi-part files share one display window: the side tables' part uses the table's.
  specs[1].full_x = specs[0].full_x;
  specs[1].full_y = specs[0].full_y;
  specs[1].full_width = specs[0].full_width;
  specs[1].full_height = specs[0].full_height;
  specs[0].attribute("oiio:subimagename", "brdf");
  specs[1].attribute("oiio:subimagename", "side_tables");
  for (const auto& [key, value] : metadata) specs[0].attribute(kPrefix + key, value);
  specs[1].attribute(std::string(kPrefix) + "rows", "row 0 R_spec(theta_i), row 1 K(theta_i)");

  // Interleave [channel][node] into pixels.
  const std::size_t nodes = lut.nodes_per_channel();
  std::vector<float> pixels(nodes * channels), side(static_cast<std::size_t>(side_width) * 2 * channels);
  for (int c = 0; c < channels; ++c) {
    for (std::size_t i = 0; i < nodes; ++i) pixels[i * channels + c] = lut.values[c * nodes + i];
    for (int m = 0; m < side_width; ++m) {
      side[static_cast<std::size_t>(m) * channels + c] = lut.specular_reflectance[c][m];
      side[static_cast<std::size_t>(side_width + m) * channels + c] = lut.renormalization[c][m];
    }
  }

  detail::write_atomically(path, ".exr", [&](const std::string& temporary) {
    auto out = OIIO::ImageOutput::create(temporary);
    if (!out) throw LutFileError(path + ": cannot create an OpenEXR writer (" + first_line(OIIO::geterror()) + ")");
    if (!out->open(temporary, 2, specs) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) ||
        !out->open(temporary, specs[1], OIIO::ImageOutput::AppendSubimage) ||
        !out->write_image(OIIO::TypeDesc::FLOAT, side.data()) || !out->close())
      throw LutFileError(path + ": write failed (" + first_line(out->geterror()) + ")");
  });
}

Lut read_lut_exr(const std::string& path) {
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw LutFileError(path + ": cannot open (" + std::strerror(errno) + ")");
    char magic[4] = {};
    probe.read(magic, 4);
    // OpenEXR magic number 20000630 (0x762f3101), little-endian.
    if (probe.gcount() != 4 || std::memcmp(magic, "\x76\x2f\x31\x01", 4) != 0)
      throw LutFileError(path + ": not an OpenEXR file (wrong magic number)");
  }
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw LutFileError(path + ": unreadable OpenEXR file (" + first_line(OIIO::geterror()) + ")");
  const OIIO::ImageSpec spec0 = in->spec();
  std::map<std::string, std::string> metadata;
  const std::string prefix = kPrefix;
  for (const OIIO::ParamValue& p : spec0.extra_attribs) {
    const std::string name = p.name().string();
    if (name.compare(0, prefix.size(), prefix) == 0 && p.type() == OIIO::TypeString)
      metadata[name.substr(prefix.size())] = p.get_string();
  }
  if (metadata.find("format") == metadata.end())
    throw LutFileError(path + ": not a libbrdf table (no libbrdf:format header attribute)");

  Lut lut;
  detail::restore_from_metadata(lut, metadata, path);
  const int channels = lut.channels();
  const bool slice = lut.layout == LutLayout::slice;
  const long long width = slice ? lut.shape[1] : lut.shape[2];
  const long long height = slice ? static_cast<long long>(lut.shape[0]) : static_cast<long long>(lut.shape[0]) * lut.shape[1];
  if (spec0.width != width || spec0.height != height || spec0.nchannels != channels || spec0.depth != 1)
    throw LutFileError(path + ": image size " + std::to_string(spec0.width) + "x" + std::to_string(spec0.height) + "x" +
                       std::to_string(spec0.nchannels) + " does not match the header's shape and channels");
  // Channels by name: OpenEXR stores them sorted by name.
  const std::vector<std::string> names = channel_names(channels);
  std::vector<int> order(channels);
  for (int c = 0; c < channels; ++c) {
    order[c] = spec0.channelindex(names[c]);
    if (order[c] < 0) throw LutFileError(path + ": channel '" + names[c] + "' missing");
  }
  const std::size_t nodes = lut.nodes_per_channel();
  std::vector<float> pixels(nodes * channels);
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data()))
    throw LutFileError(path + ": truncated or corrupt table data (" + first_line(in->geterror()) + ")");
  lut.values.resize(nodes * channels);
  for (int c = 0; c < channels; ++c)
    for (std::size_t i = 0; i < nodes; ++i) lut.values[c * nodes + i] = pixels[i * channels + order[c]];

  if (!in->seek_subimage(1, 0)) throw LutFileError(path + ": the R_spec/K subimage is missing");
  const OIIO::ImageSpec spec1 = in->spec();
  if (spec1.width < 2 || spec1.height != 2 || spec1.nchannels != channels)
    throw LutFileError(path + ": the R_spec/K subimage has the wrong size");
  std::vector<int> side_order(channels);
  for (int c = 0; c < channels; ++c) {
    side_order[c] = spec1.channelindex(names[c]);
    if (side_order[c] < 0) throw LutFileError(path + ": channel '" + names[c] + "' missing in the R_spec/K subimage");
  }
  std::vector<float> side(static_cast<std::size_t>(spec1.width) * 2 * channels);
  if (!in->read_image(1, 0, 0, channels, OIIO::TypeDesc::FLOAT, side.data()))
    throw LutFileError(path + ": truncated or corrupt R_spec/K data (" + first_line(in->geterror()) + ")");
  lut.specular_reflectance.assign(channels, std::vector<float>(spec1.width));
  lut.renormalization.assign(channels, std::vector<float>(spec1.width));
  for (int c = 0; c < channels; ++c) {
    for (int m = 0; m < spec1.width; ++m) {
      lut.specular_reflectance[c][m] = side[static_cast<std::size_t>(m) * channels + side_order[c]];
      lut.renormalization[c][m] = side[static_cast<std::size_t>(spec1.width + m) * channels + side_order[c]];
    }
  }
  in->close();
  detail::check_lut_consistency(lut, path);
  return lut;
}

}  // namespace libbrdf
