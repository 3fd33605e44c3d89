#pragma once
// File writing shared by the LUT files and the exporters: atomic writes (a temporary beside the
// target, then a rename, so an interrupted or failed write leaves no partial file) and float32
// OpenEXR images with string attributes. OpenEXR itself stays in the sources.
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace libbrdf {

// Unreadable, truncated, corrupt or foreign files: one line naming the file and the problem.
struct LutFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Writes through `write_to(temporary_path)` beside `path`, then renames onto `path`. A throw from
// write_to (or a failed rename) removes the temporary. `suffix` ends the temporary's name.
void write_file_atomically(const std::string& path, const std::string& suffix,
                           const std::function<void(const std::string& temporary_path)>& write_to);
void write_text_file_atomically(const std::string& path, const std::string& text);

// One part of an OpenEXR file: float32 pixels, interleaved by channel, row 0 at the top.
struct ExrPart {
  std::string name;                               // part name (multi-part files)
  int width = 0, height = 0;
  std::vector<std::string> channel_names;         // in the order of `pixels`' interleaving
  std::vector<float> pixels;                      // width * height * channels
  std::map<std::string, std::string> attributes;  // string header attributes
};

// Writes the parts (ZIP compression, lossless) atomically. Throws LutFileError.
void write_exr(const std::string& path, const std::vector<ExrPart>& parts);
// Reads every part; channels come back in `channel_names` order as stored (OpenEXR sorts them by
// name). Throws LutFileError for anything that is not a complete, readable OpenEXR file.
std::vector<ExrPart> read_exr(const std::string& path);

}  // namespace libbrdf
