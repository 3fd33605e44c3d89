#pragma once
// File writing shared by the LUT files and the exporters: atomic writes (a temporary beside the
// target, then a rename, so an interrupted or failed write leaves no partial file) and float32
// OpenEXR images with string attributes. OpenEXR itself stays in the sources.
#include <cstddef>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace libbrdf {

// Unreadable, truncated, corrupt or foreign files: one line naming the file and the problem.
struct LutFileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Writes through `write_to(temporary_path)` beside `path`, then renames onto `path`. A throw from
// write_to (or a failed rename) removes the temporary. `suffix` ends the temporary's name, which
// is ".NAME.tmp-PID-N<suffix>" in the target's directory. Temporaries of the same target left by
// processes that no longer exist (a SIGKILL) are removed first. Inside a PublicationGroup the
// rename is deferred to the group's publish().
void write_file_atomically(const std::string& path, const std::string& suffix,
                           const std::function<void(const std::string& temporary_path)>& write_to);
void write_text_file_atomically(const std::string& path, const std::string& text);

// Checks, before any work, that a file `output` can be written: not a directory, its directory
// exists (with create_directory, is created with its parents first) and is writable. Throws
// InvalidArgument naming `parameter` (the CLI's option, the Python keyword).
void require_writable_output(const std::string& output, const char* parameter, bool create_directory = false);

// Interruption. Every temporary of write_file_atomically is in a process-wide registry from
// before it is created until it is renamed into place or removed, and every rename happens while
// the registry's lock is held. A program that takes SIGINT/SIGTERM in a thread of its own (brdf:
// cli/interrupt.h) locks it, removes the registered temporaries and exits: it never interrupts a
// rename, so every final file is either untouched or completely written, and no temporary stays.
class PublicationLock {
 public:
  PublicationLock();  // blocks while a rename (or a group's renames) is in progress
  ~PublicationLock();
  PublicationLock(const PublicationLock&) = delete;
  PublicationLock& operator=(const PublicationLock&) = delete;
  // Deletes every registered temporary (unlink; the files may be half written).
  void remove_temporaries();
  // Publications so far in this process (single renames and whole groups): with the lock held, a
  // signal thread tells "nothing written" from "outputs already in place".
  std::size_t publications() const;
};

// Files published as one unit. While a group is open on this thread, write_file_atomically writes
// its temporaries and records them; publish() renames them all, in the order written, under one
// hold of the publication lock and of an exclusive flock(2) on each target directory (so
// concurrent publishers to one directory take turns: a group's files never interleave with
// another's). Destroying a group that was not published removes its temporaries: a failure or
// exception part-way (e.g. the OSL after the atlas) leaves no file. Readers that need a
// consistent set hold a shared flock on the directory while they open the files
// (DirectoryReadLock). A SIGKILL between two renames of a group can still leave the new first
// file beside an old second one: the MERL sidecar carries the binary's CRC-32 for that (lut.h).
class PublicationGroup {
 public:
  PublicationGroup();
  ~PublicationGroup();
  PublicationGroup(const PublicationGroup&) = delete;
  PublicationGroup& operator=(const PublicationGroup&) = delete;
  void publish();  // throws LutFileError if a rename fails (the remaining temporaries are removed)

 private:
  friend void write_file_atomically(const std::string&, const std::string&, const std::function<void(const std::string&)>&);
  std::vector<std::pair<std::string, std::string>> staged_;  // (temporary, target)
  PublicationGroup* previous_ = nullptr;
};

// A shared flock(2) on a file's directory for as long as it lives (see PublicationGroup).
class DirectoryReadLock {
 public:
  explicit DirectoryReadLock(const std::string& file_path);
  ~DirectoryReadLock();
  DirectoryReadLock(const DirectoryReadLock&) = delete;
  DirectoryReadLock& operator=(const DirectoryReadLock&) = delete;

 private:
  int fd_ = -1;
};

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
// name). Throws LutFileError for anything that is not a complete, readable OpenEXR file, and
// before allocating for a header whose pixel count the file cannot hold: more than
// kMaxExrCompressionRatio x the file's size in decoded bytes (zlib, the densest OpenEXR
// compression, never exceeds 1032:1), beyond a floor of kExrDecodedBytesFloor, or more than
// 2^31 values in a part.
inline constexpr double kMaxExrCompressionRatio = 1100.0;
inline constexpr double kExrDecodedBytesFloor = 64.0 * 1024 * 1024;
std::vector<ExrPart> read_exr(const std::string& path);

}  // namespace libbrdf
