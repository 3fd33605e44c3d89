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
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include "libbrdf/error.h"
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

std::string crc32_text(const char* data, std::size_t size) {
  uLong crc = ::crc32(0L, Z_NULL, 0);
  while (size > 0) {  // zlib takes uInt lengths
    const uInt chunk = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
    crc = ::crc32(crc, reinterpret_cast<const Bytef*>(data), chunk);
    data += chunk;
    size -= chunk;
  }
  char text[16];
  std::snprintf(text, sizeof text, "%08lx", static_cast<unsigned long>(crc));
  return text;
}

// Largest sidecar read (a real one is ~0.1 MB: two 3 x 1441 float tables and the header).
constexpr std::uintmax_t kMaxSidecarBytes = 16u << 20;

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

  // The binary's bytes first: the sidecar carries their CRC-32 (zlib) and size, which the reader
  // checks, so a binary and a sidecar from different bakes are never used together.
  std::string binary;
  binary.reserve(sizeof(std::int32_t) * 3 + 3 * nodes * sizeof(double));
  std::int32_t dims[3] = {kMerlShape[0], kMerlShape[1], kMerlShape[2]};
  for (std::int32_t& d : dims) to_little_endian(d);
  binary.append(reinterpret_cast<const char*>(dims), sizeof dims);
  for (int c = 0; c < 3; ++c) {
    for (std::size_t i = 0; i < nodes; ++i) {
      double value = double(lut.values[c * nodes + i]) / kMerlScales[c];
      to_little_endian(value);
      binary.append(reinterpret_cast<const char*>(&value), sizeof value);
    }
  }
  sidecar["binary_bytes"] = binary.size();
  sidecar["binary_crc32"] = crc32_text(binary.data(), binary.size());
  const std::string sidecar_text = sidecar.dump(1);

  // One unit (image_file.h, PublicationGroup): both temporaries written, then both renamed under
  // an exclusive flock on the directory -- sidecar first, so that a SIGKILL between the renames
  // leaves either a sidecar without a binary (unreadable) or a pair the checksum rejects.
  PublicationGroup group;
  write_file_atomically(sidecar_path(path), ".tmp", [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << sidecar_text << "\n";
    out.close();
    if (!out) throw LutFileError(sidecar_path(path) + ": write failed");
  });
  write_file_atomically(path, ".tmp", [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(binary.data(), static_cast<std::streamsize>(binary.size()));
    out.close();
    if (!out) throw LutFileError(path + ": write failed");
  });
  group.publish();
}

Lut read_merl_binary(const std::string& path) {
  // Both files are opened under a shared flock on the directory, so a publication of a new pair
  // (an exclusive flock, image_file.h) is seen entirely or not at all.
  std::ifstream in, sin;
  const std::string side = sidecar_path(path);
  std::error_code ec;
  bool has_sidecar = false;
  {
    DirectoryReadLock lock(path);
    in.open(path, std::ios::binary);
    if (!in) throw LutFileError(path + ": cannot open (" + std::strerror(errno) + ")");
    has_sidecar = std::filesystem::exists(side, ec);
    if (has_sidecar) {
      sin.open(side, std::ios::binary);
      if (!sin) throw LutFileError(side + ": cannot open (" + std::strerror(errno) + ")");
    }
  }
  const std::size_t nodes = std::size_t(90) * 90 * 180;
  const std::size_t expected = sizeof(std::int32_t) * 3 + 3 * nodes * sizeof(double);
  // Read at most one byte more than a MERL binary has: longer files are refused without reading them.
  std::string binary(expected + 1, '\0');
  in.read(binary.data(), static_cast<std::streamsize>(binary.size()));
  binary.resize(static_cast<std::size_t>(in.gcount()));
  std::int32_t dims[3] = {0, 0, 0};
  if (binary.size() < sizeof dims) throw LutFileError(path + ": not a MERL binary (file shorter than its header)");
  std::memcpy(dims, binary.data(), sizeof dims);
  for (std::int32_t& d : dims) to_little_endian(d);
  if (dims[0] != kMerlShape[0] || dims[1] != kMerlShape[1] || dims[2] != kMerlShape[2])
    throw LutFileError(path + ": not a MERL binary (header dimensions " + std::to_string(dims[0]) + "x" +
                       std::to_string(dims[1]) + "x" + std::to_string(dims[2]) + ", expected 90x90x180)");
  if (binary.size() != expected)
    throw LutFileError(path + ": truncated or padded MERL binary (" + (binary.size() > expected ? std::string("more than ") : "") +
                       std::to_string(binary.size() > expected ? expected : binary.size()) + " bytes, expected " +
                       std::to_string(expected) + ")");

  Lut lut;
  lut.layout = LutLayout::merl;
  lut.shape = kMerlShape;
  lut.values.resize(3 * nodes);
  for (int c = 0; c < 3; ++c) {
    for (std::size_t i = 0; i < nodes; ++i) {
      double stored = 0.0;
      std::memcpy(&stored, binary.data() + sizeof dims + (c * nodes + i) * sizeof(double), sizeof stored);
      to_little_endian(stored);
      const double value = stored * kMerlScales[c];
      // A BRDF is finite and >= 0 (MERL's measured files mark missing data with negative values,
      // which a renderer would take as negative reflectance).
      if (!std::isfinite(value) || value < 0.0 || value > 3.0e38)
        throw LutFileError(path + ": corrupt MERL binary (negative, non-finite or out-of-range value " +
                           std::to_string(value) + " at channel " + std::to_string(c) + ", node " + std::to_string(i) + ")");
      lut.values[c * nodes + i] = static_cast<float>(value);
    }
  }

  if (has_sidecar) {
    try {
      const std::uintmax_t side_size = std::filesystem::file_size(side, ec);
      if (ec || side_size > kMaxSidecarBytes)
        throw LutFileError(side + ": sidecar larger than " + std::to_string(kMaxSidecarBytes) + " bytes (refused)");
      const nlohmann::json j = nlohmann::json::parse(sin);
      if (j.value("format", "") != "libbrdf-merl-sidecar") throw LutFileError(side + ": not a libbrdf MERL sidecar");
      // The pair check (write_merl_binary): sidecars written before the checksum existed have none.
      if (j.contains("binary_crc32")) {
        if (j.at("binary_crc32").get<std::string>() != crc32_text(binary.data(), binary.size()) ||
            j.value("binary_bytes", std::uint64_t{0}) != binary.size())
          throw LutFileError(side + ": describes a different binary than " + path +
                             " (CRC-32 mismatch: the two files come from different bakes; bake again)");
      }
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
      throw LutFileError(side + ": corrupt sidecar (" + message_excerpt(e.what()) + ")");
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
