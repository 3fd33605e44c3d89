#include "libbrdf/image_file.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace libbrdf {

void write_file_atomically(const std::string& path, const std::string& suffix,
                           const std::function<void(const std::string&)>& write_to) {
  namespace fs = std::filesystem;
  static std::atomic<unsigned> counter{0};
  const fs::path target(path);
  if (target.filename().empty()) throw LutFileError(path + ": not a file name");
  const fs::path directory = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(directory, ec)) throw LutFileError(path + ": directory '" + directory.string() + "' does not exist");
  // Hidden, unique per process and call, in the same directory (the rename stays on one file system).
  const fs::path temporary = directory / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                                          std::to_string(counter++) + suffix);
  try {
    write_to(temporary.string());
    fs::rename(temporary, target, ec);
    if (ec) throw LutFileError(path + ": cannot rename the temporary file into place (" + ec.message() + ")");
  } catch (...) {
    fs::remove(temporary, ec);
    throw;
  }
}

void write_text_file_atomically(const std::string& path, const std::string& text) {
  write_file_atomically(path, "", [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw LutFileError(path + ": cannot write (" + std::strerror(errno) + ")");
  });
}

namespace {

// OpenEXR messages can span lines; keep the first.
std::string first_line(const char* text) {
  std::string line(text ? text : "");
  if (const auto end = line.find('\n'); end != std::string::npos) line.resize(end);
  return line.empty() ? "unknown error" : line;
}

Imf::FrameBuffer frame_buffer(const ExrPart& part, float* pixels, int min_x, int min_y) {
  Imf::FrameBuffer buffer;
  const std::size_t channels = part.channel_names.size();
  const std::size_t x_stride = sizeof(float) * channels;
  const std::size_t y_stride = x_stride * static_cast<std::size_t>(part.width);
  for (std::size_t c = 0; c < channels; ++c) {
    // Slices address pixel (x, y) of the data window at base + x * xStride + y * yStride.
    char* base = reinterpret_cast<char*>(pixels + c) - static_cast<std::ptrdiff_t>(min_x) * static_cast<std::ptrdiff_t>(x_stride) -
                 static_cast<std::ptrdiff_t>(min_y) * static_cast<std::ptrdiff_t>(y_stride);
    buffer.insert(part.channel_names[c], Imf::Slice(Imf::FLOAT, base, x_stride, y_stride));
  }
  return buffer;
}

}  // namespace

void write_exr(const std::string& path, const std::vector<ExrPart>& parts) {
  if (parts.empty()) throw LutFileError(path + ": nothing to write");
  std::vector<Imf::Header> headers;
  for (const ExrPart& part : parts) {
    if (part.pixels.size() != static_cast<std::size_t>(part.width) * part.height * part.channel_names.size())
      throw std::logic_error("write_exr: pixel count does not match the part's size");
    // Every part of a multi-part file shares the first part's display window (OpenEXR's rule).
    const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(parts[0].width - 1, parts[0].height - 1));
    const Imath::Box2i data(Imath::V2i(0, 0), Imath::V2i(part.width - 1, part.height - 1));
    Imf::Header header(display, data, 1.0f, Imath::V2f(0, 0), 1.0f, Imf::INCREASING_Y, Imf::ZIP_COMPRESSION);
    for (const std::string& name : part.channel_names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    for (const auto& [key, value] : part.attributes) header.insert(key, Imf::StringAttribute(value));
    header.setName(part.name);
    header.setType(Imf::SCANLINEIMAGE);
    headers.push_back(std::move(header));
  }
  write_file_atomically(path, ".exr", [&](const std::string& temporary) {
    try {
      Imf::MultiPartOutputFile file(temporary.c_str(), headers.data(), static_cast<int>(headers.size()));
      for (std::size_t i = 0; i < parts.size(); ++i) {
        Imf::OutputPart out(file, static_cast<int>(i));
        // The writer only reads through the frame buffer.
        out.setFrameBuffer(frame_buffer(parts[i], const_cast<float*>(parts[i].pixels.data()), 0, 0));
        out.writePixels(parts[i].height);
      }
    } catch (const std::exception& e) {
      throw LutFileError(path + ": write failed (" + first_line(e.what()) + ")");
    }
  });
}

std::vector<ExrPart> read_exr(const std::string& path) {
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw LutFileError(path + ": cannot open (" + std::strerror(errno) + ")");
    char magic[4] = {};
    probe.read(magic, 4);
    // OpenEXR magic number 20000630 (0x762f3101), little-endian.
    if (probe.gcount() != 4 || std::memcmp(magic, "\x76\x2f\x31\x01", 4) != 0)
      throw LutFileError(path + ": not an OpenEXR file (wrong magic number)");
  }
  try {
    Imf::MultiPartInputFile file(path.c_str());
    std::vector<ExrPart> parts(static_cast<std::size_t>(file.parts()));
    for (int i = 0; i < file.parts(); ++i) {
      const Imf::Header& header = file.header(i);
      if (header.hasType() && header.type() != Imf::SCANLINEIMAGE)
        throw LutFileError(path + ": part " + std::to_string(i) + " is not a scan-line image");
      ExrPart& part = parts[static_cast<std::size_t>(i)];
      part.name = header.hasName() ? header.name() : "";
      const Imath::Box2i window = header.dataWindow();
      part.width = window.max.x - window.min.x + 1;
      part.height = window.max.y - window.min.y + 1;
      for (auto c = header.channels().begin(); c != header.channels().end(); ++c) part.channel_names.push_back(c.name());
      for (auto a = header.begin(); a != header.end(); ++a)
        if (const auto* text = dynamic_cast<const Imf::StringAttribute*>(&a.attribute())) part.attributes[a.name()] = text->value();
      part.pixels.assign(static_cast<std::size_t>(part.width) * part.height * part.channel_names.size(), 0.0f);
      Imf::InputPart in(file, i);
      in.setFrameBuffer(frame_buffer(part, part.pixels.data(), window.min.x, window.min.y));
      in.readPixels(window.min.y, window.max.y);
    }
    return parts;
  } catch (const LutFileError&) {
    throw;
  } catch (const std::exception& e) {
    throw LutFileError(path + ": truncated or corrupt OpenEXR file (" + first_line(e.what()) + ")");
  }
}

}  // namespace libbrdf
