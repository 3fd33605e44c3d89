#include "libbrdf/image_file.h"

#include "libbrdf/error.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>

namespace libbrdf {

namespace {

// The registry of live temporaries (image_file.h, "Interruption"). Never destroyed: a signal
// thread may use it while static objects are being torn down at exit.
struct TemporaryRegistry {
  std::mutex mutex;
  std::set<std::string> temporaries;
  std::size_t publications = 0;  // renames (a group counts once), under `mutex`
};
TemporaryRegistry& registry() {
  static auto* instance = new TemporaryRegistry;
  return *instance;
}
thread_local PublicationGroup* open_group = nullptr;

void register_temporary(const std::string& path) {
  std::lock_guard<std::mutex> lock(registry().mutex);
  registry().temporaries.insert(path);
}
void discard_temporary(const std::string& path) {
  std::lock_guard<std::mutex> lock(registry().mutex);
  ::unlink(path.c_str());
  registry().temporaries.erase(path);
}

// Temporaries ".NAME.tmp-PID-..." of this target whose process is gone (killed by SIGKILL, the
// one signal that cannot be handled): removed before a new write to the same target.
void remove_stale_temporaries(const std::filesystem::path& directory, const std::string& name) {
  namespace fs = std::filesystem;
  const std::string prefix = "." + name + ".tmp-";
  std::error_code ec;
  for (fs::directory_iterator it(directory, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string file = it->path().filename().string();
    if (file.compare(0, prefix.size(), prefix) != 0) continue;
    const long pid = std::strtol(file.c_str() + prefix.size(), nullptr, 10);
    if (pid > 0 && pid != ::getpid() && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
      std::error_code ignored;
      fs::remove(it->path(), ignored);
    }
  }
}

// flock(2) on a directory for the lifetime of the object (LOCK_EX or LOCK_SH); no-op if the
// directory cannot be opened (the write or read that follows reports the real problem).
int lock_directory(const std::filesystem::path& directory, int operation) {
  const int fd = ::open(directory.empty() ? "." : directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return -1;
  while (::flock(fd, operation) != 0 && errno == EINTR) {
  }
  return fd;
}

}  // namespace

PublicationLock::PublicationLock() { registry().mutex.lock(); }
PublicationLock::~PublicationLock() { registry().mutex.unlock(); }
std::size_t PublicationLock::publications() const { return registry().publications; }

void PublicationLock::remove_temporaries() {
  for (const std::string& path : registry().temporaries) ::unlink(path.c_str());
  registry().temporaries.clear();
}

PublicationGroup::PublicationGroup() : previous_(open_group) { open_group = this; }

PublicationGroup::~PublicationGroup() {
  open_group = previous_;
  for (const auto& [temporary, target] : staged_) discard_temporary(temporary);
}

void PublicationGroup::publish() {
  namespace fs = std::filesystem;
  if (open_group == this) open_group = previous_;
  // Exclusive locks on the target directories first (waiting for another publisher must not
  // hold the publication lock, which a signal thread needs), in a fixed order.
  std::set<std::string> directories;
  // One lock per directory, however its files spell it: flock() locks of one process through two
  // descriptors conflict, so "out" and "/abs/out" taken separately would wait for each other forever.
  for (const auto& entry : staged_) {
    std::error_code ec;
    const fs::path parent = fs::path(entry.second).parent_path();
    const fs::path canonical = fs::weakly_canonical(fs::absolute(parent.empty() ? fs::path(".") : parent, ec), ec);
    directories.insert(ec ? parent.string() : canonical.string());
  }
  std::vector<int> locks;
  for (const std::string& directory : directories) locks.push_back(lock_directory(directory, LOCK_EX));
  std::string failure;
  // A target that is a directory would fail its rename after the earlier ones succeeded: found
  // before any rename, so that a group is published entirely or not at all.
  for (const auto& entry : staged_) {
    std::error_code ec;
    if (fs::is_directory(entry.second, ec)) failure = entry.second + ": is a directory; cannot replace it with a file";
  }
  {
    std::lock_guard<std::mutex> lock(registry().mutex);
    for (const auto& [temporary, target] : staged_) {
      if (failure.empty() && ::rename(temporary.c_str(), target.c_str()) != 0)
        failure = target + ": cannot rename the temporary file into place (" + std::strerror(errno) + ")";
      if (!failure.empty()) ::unlink(temporary.c_str());
      registry().temporaries.erase(temporary);
    }
    if (failure.empty() && !staged_.empty()) ++registry().publications;
    staged_.clear();
  }
  for (int fd : locks)
    if (fd >= 0) ::close(fd);
  if (!failure.empty()) throw LutFileError(failure);
}

DirectoryReadLock::DirectoryReadLock(const std::string& file_path)
    : fd_(lock_directory(std::filesystem::path(file_path).parent_path(), LOCK_SH)) {}
DirectoryReadLock::~DirectoryReadLock() {
  if (fd_ >= 0) ::close(fd_);
}

void write_file_atomically(const std::string& path, const std::string& suffix,
                           const std::function<void(const std::string&)>& write_to) {
  namespace fs = std::filesystem;
  static std::atomic<unsigned> counter{0};
  const fs::path target(path);
  if (target.filename().empty()) throw LutFileError(path + ": not a file name");
  const fs::path directory = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(directory, ec)) throw LutFileError(path + ": directory '" + directory.string() + "' does not exist");
  remove_stale_temporaries(directory, target.filename().string());
  // Hidden, unique per process and call, in the same directory (the rename stays on one file system).
  const fs::path temporary = directory / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                                          std::to_string(counter++) + suffix);
  register_temporary(temporary.string());  // before it exists: a signal from here on removes it
  try {
    write_to(temporary.string());
  } catch (...) {
    discard_temporary(temporary.string());
    throw;
  }
  if (open_group) {
    open_group->staged_.emplace_back(temporary.string(), target.string());
    return;
  }
  std::string failure;
  {
    std::lock_guard<std::mutex> lock(registry().mutex);
    if (::rename(temporary.c_str(), target.c_str()) != 0) {
      failure = path + ": cannot rename the temporary file into place (" + std::strerror(errno) + ")";
      ::unlink(temporary.c_str());
    } else {
      ++registry().publications;
    }
    registry().temporaries.erase(temporary.string());
  }
  if (!failure.empty()) throw LutFileError(failure);
}

void require_writable_output(const std::string& output, const char* parameter, bool create_directory) {
  namespace fs = std::filesystem;
  const fs::path path(output);
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InvalidArgument(parameter, "'" + message_excerpt(output) + "' is a directory, not a file name");
  const fs::path directory = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (create_directory && !fs::is_directory(directory, ec) && (fs::create_directories(directory, ec), ec))
    throw InvalidArgument(parameter, "cannot create directory '" + message_excerpt(directory.string()) + "': " + ec.message());
  if (!fs::is_directory(directory, ec))
    throw InvalidArgument(parameter, "directory '" + message_excerpt(directory.string()) + "' does not exist");
  if (::access(directory.c_str(), W_OK | X_OK) != 0)
    throw InvalidArgument(parameter, "directory '" + message_excerpt(directory.string()) + "' is not writable");
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
  std::error_code size_error;
  const double file_bytes = static_cast<double>(std::filesystem::file_size(path, size_error));
  try {
    Imf::MultiPartInputFile file(path.c_str());
    std::vector<ExrPart> parts(static_cast<std::size_t>(file.parts()));
    // Decoded size of every part from the headers, checked against the file's size before any
    // pixel buffer is allocated (image_file.h: a 71 KB file claiming 20000^2 pixels took 4.7 GB).
    double decoded_bytes = 0.0;
    for (int i = 0; i < file.parts(); ++i) {
      const Imf::Header& header = file.header(i);
      const Imath::Box2i window = header.dataWindow();
      const double width = double(window.max.x) - window.min.x + 1, height = double(window.max.y) - window.min.y + 1;
      double channels = 0;
      for (auto c = header.channels().begin(); c != header.channels().end(); ++c) ++channels;
      const double values = width * height * channels;
      if (!(width >= 1 && height >= 1) || values > double(std::size_t{1} << 31))
        throw LutFileError(path + ": part " + std::to_string(i) + " claims " + std::to_string(static_cast<long long>(width)) + "x" +
                           std::to_string(static_cast<long long>(height)) + " pixels x " + std::to_string(static_cast<int>(channels)) +
                           " channels: empty or more than 2^31 values (refused)");
      decoded_bytes += values * sizeof(float);
    }
    if (size_error || decoded_bytes > std::max(kExrDecodedBytesFloor, kMaxExrCompressionRatio * file_bytes))
      throw LutFileError(path + ": header claims " + std::to_string(static_cast<long long>(decoded_bytes)) +
                         " bytes of pixels in a file of " + std::to_string(static_cast<long long>(file_bytes)) +
                         " bytes, more than any OpenEXR compression reaches (refused before reading)");
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
