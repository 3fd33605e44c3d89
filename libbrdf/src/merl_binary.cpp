// MERL binary BRDF files (W. Matusik, H. Pfister, M. Brand, L. McMillan, "A data-driven
// reflectance model", ACM TOG 22, 759 (2003); layout of the reference reader MERLBRDFRead.cpp
// distributed with the MERL BRDF database):
//   header: three int32 (theta_h, theta_d, phi_d resolutions) = 90, 90, 180, little-endian;
//   then 3 x 90 x 90 x 180 doubles (little-endian): channel-major (red, green, blue), each in the
//   order index = phi_d + 180 theta_d + 180 x 90 theta_h, i.e. our [channel][i0][i1][i2];
//   stored value = BRDF / scale with scales 1/1500 (red), 1.15/1500 (green), 1.66/1500 (blue)
//   (the reader multiplies by them).
// The format carries no metadata. libbrdf writes a JSON sidecar "<file>.json" beside it with the
// header attributes (model, parameters, wavelengths, axes, texel convention, measured error) and
// the R_spec / K side tables, and reads it back when present. Without a sidecar the reader
// assigns the RGB wavelengths 0.65, 0.55, 0.45 um, R_spec = 0 and K = 1, and says so in the
// attributes ("side_tables" = "absent").
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "libbrdf/lut.h"
#include "lut_internal.h"

namespace libbrdf {
namespace {

constexpr std::array<double, 3> kMerlScales{1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

bool host_is_little_endian() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

template <class T>
void to_little_endian(T& value) {
  if (host_is_little_endian()) return;
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (std::size_t k = 0; k < sizeof(T) / 2; ++k) std::swap(bytes[k], bytes[sizeof(T) - 1 - k]);
  std::memcpy(&value, bytes, sizeof(T));
}

std::string sidecar_path(const std::string& path) { return path + ".json"; }

}  // namespace

void write_merl_binary(const Lut& lut, const std::string& path) {
  detail::check_lut_consistency(lut, path);
  if (lut.layout != LutLayout::merl) throw LutFileError(path + ": MERL binary needs a table of layout merl");
  if (lut.channels() != 3) throw LutFileError(path + ": MERL binary needs exactly 3 channels (red, green, blue)");
  const std::size_t nodes = lut.nodes_per_channel();

  nlohmann::ordered_json sidecar;
  sidecar["format"] = "libbrdf-merl-sidecar";
  sidecar["describes"] = std::filesystem::path(path).filename().string();
  nlohmann::ordered_json header;
  for (const auto& [key, value] : detail::lut_metadata(lut)) header[key] = value;
  header["storage"] =
      "MERL binary: int32 dims 90,90,180 then 3 x 90x90x180 float64, channel-major red, green, blue, index = i2 + 180 i1 "
      "+ 180*90 i0, value = BRDF / scale, scales 1/1500, 1.15/1500, 1.66/1500; little-endian";
  sidecar["header"] = header;
  sidecar["specular_reflectance"] = lut.specular_reflectance;
  sidecar["renormalization"] = lut.renormalization;
  const std::string sidecar_text = sidecar.dump(1);

  write_file_atomically(sidecar_path(path), ".tmp", [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << sidecar_text << "\n";
    out.close();
    if (!out) throw LutFileError(sidecar_path(path) + ": write failed");
  });
  try {
    write_file_atomically(path, ".tmp", [&](const std::string& temporary) {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      std::int32_t dims[3] = {kMerlShape[0], kMerlShape[1], kMerlShape[2]};
      for (std::int32_t& d : dims) to_little_endian(d);
      out.write(reinterpret_cast<const char*>(dims), sizeof dims);
      std::vector<double> block(nodes);
      for (int c = 0; c < 3; ++c) {
        for (std::size_t i = 0; i < nodes; ++i) {
          block[i] = double(lut.values[c * nodes + i]) / kMerlScales[c];
          to_little_endian(block[i]);
        }
        out.write(reinterpret_cast<const char*>(block.data()), static_cast<std::streamsize>(nodes * sizeof(double)));
      }
      out.close();
      if (!out) throw LutFileError(path + ": write failed");
    });
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(sidecar_path(path), ec);  // no sidecar without its table
    throw;
  }
}

Lut read_merl_binary(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw LutFileError(path + ": cannot open (" + std::strerror(errno) + ")");
  std::int32_t dims[3] = {0, 0, 0};
  in.read(reinterpret_cast<char*>(dims), sizeof dims);
  if (in.gcount() != static_cast<std::streamsize>(sizeof dims)) throw LutFileError(path + ": not a MERL binary (file shorter than its header)");
  for (std::int32_t& d : dims) to_little_endian(d);
  if (dims[0] != kMerlShape[0] || dims[1] != kMerlShape[1] || dims[2] != kMerlShape[2])
    throw LutFileError(path + ": not a MERL binary (header dimensions " + std::to_string(dims[0]) + "x" +
                       std::to_string(dims[1]) + "x" + std::to_string(dims[2]) + ", expected 90x90x180)");
  const std::size_t nodes = std::size_t(90) * 90 * 180;
  const std::uintmax_t expected = sizeof dims + 3 * nodes * sizeof(double);
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size != expected)
    throw LutFileError(path + ": truncated or padded MERL binary (" + std::to_string(ec ? 0 : size) + " bytes, expected " +
                       std::to_string(expected) + ")");

  Lut lut;
  lut.layout = LutLayout::merl;
  lut.shape = kMerlShape;
  lut.values.resize(3 * nodes);
  std::vector<double> block(nodes);
  for (int c = 0; c < 3; ++c) {
    in.read(reinterpret_cast<char*>(block.data()), static_cast<std::streamsize>(nodes * sizeof(double)));
    if (in.gcount() != static_cast<std::streamsize>(nodes * sizeof(double))) throw LutFileError(path + ": truncated MERL binary");
    for (std::size_t i = 0; i < nodes; ++i) {
      to_little_endian(block[i]);
      const double value = block[i] * kMerlScales[c];
      if (!std::isfinite(value) || std::abs(value) > 3.0e38)
        throw LutFileError(path + ": corrupt MERL binary (non-finite or out-of-range value at channel " + std::to_string(c) + ")");
      lut.values[c * nodes + i] = static_cast<float>(value);
    }
  }

  const std::string side = sidecar_path(path);
  if (std::filesystem::exists(side, ec)) {
    try {
      std::ifstream sin(side);
      const nlohmann::json j = nlohmann::json::parse(sin);
      if (j.value("format", "") != "libbrdf-merl-sidecar") throw LutFileError(side + ": not a libbrdf MERL sidecar");
      std::map<std::string, std::string> metadata;
      for (const auto& [key, value] : j.at("header").items()) metadata[key] = value.get<std::string>();
      std::vector<float> keep_values = std::move(lut.values);
      detail::restore_from_metadata(lut, metadata, side);
      lut.values = std::move(keep_values);
      if (lut.layout != LutLayout::merl || lut.shape != kMerlShape || lut.channels() != 3)
        throw LutFileError(side + ": sidecar does not describe a 3-channel merl table");
      lut.specular_reflectance = j.at("specular_reflectance").get<std::vector<std::vector<float>>>();
      lut.renormalization = j.at("renormalization").get<std::vector<std::vector<float>>>();
    } catch (const nlohmann::json::exception& e) {
      throw LutFileError(side + ": corrupt sidecar (" + std::string(e.what()) + ")");
    }
  } else {
    lut.wavelengths_um = {0.65, 0.55, 0.45};
    lut.specular_reflectance.assign(3, std::vector<float>(kThetaINodes, 0.0f));
    lut.renormalization.assign(3, std::vector<float>(kThetaINodes, 1.0f));
    lut.attributes["format"] = "merl-binary";
    lut.attributes["side_tables"] = "absent (no sidecar " + side + "): R_spec = 0, K = 1";
    lut.attributes["wavelengths_um"] = "0.65,0.55,0.45 (assigned: MERL files carry no wavelengths)";
  }
  detail::check_lut_consistency(lut, path);
  return lut;
}

Lut read_lut_file(const std::string& path) {
  std::ifstream probe(path, std::ios::binary);
  if (!probe) throw LutFileError(path + ": cannot open (" + std::strerror(errno) + ")");
  char magic[4] = {};
  probe.read(magic, 4);
  if (probe.gcount() == 4 && std::memcmp(magic, "\x76\x2f\x31\x01", 4) == 0) return read_lut_exr(path);
  const bool merl_header = probe.gcount() == 4 && std::memcmp(magic, "\x5a\x00\x00\x00", 4) == 0;  // int32 90
  if (!merl_header) throw LutFileError(path + ": not a libbrdf table (neither an OpenEXR file nor a MERL binary)");
  return read_merl_binary(path);
}

}  // namespace libbrdf
