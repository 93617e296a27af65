#pragma once
/// @file regular_file.hpp
/// The first check of every reader and writer: a path names a regular file (or a symbolic link to
/// one). A reader opens it without blocking (a FIFO cannot hang it), learns its size from fstat and
/// reads byte ranges of it only after its header and sizes are checked; a writer refuses to replace
/// anything that is not a regular file (a device, a FIFO, a socket, a directory).

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace granular {

/// What a file of mode `mode` is, for messages ("a FIFO (named pipe)", "a character device").
const char* file_kind(mode_t mode);

/// " (a symbolic link to 'target')" when `path` is a symbolic link, else "".
std::string link_note(const std::filesystem::path& path);

/// A regular file open for reading.
class ReadableFile {
 public:
  /// Opens `path` (symbolic links followed) with O_NONBLOCK, then fstat: a FIFO, a device, a socket
  /// or a directory is a FileError naming the path and what it is, and nothing is read from it.
  explicit ReadableFile(const std::filesystem::path& path);
  ~ReadableFile();
  ReadableFile(const ReadableFile&) = delete;
  ReadableFile& operator=(const ReadableFile&) = delete;
  /// The file's size in bytes when it was opened.
  std::uint64_t size() const { return size_; }
  /// The path it was opened by.
  const std::filesystem::path& path() const { return path_; }
  /// Reads exactly `out.size()` bytes at byte `at`; FileError (the path, the byte and the system's
  /// reason, or where the file ended) when it cannot.
  void read_at(std::uint64_t at, std::span<std::uint8_t> out) const;

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// Throws FileError naming `path` (and the link it is) when `target` (`path` after its symbolic
/// links) exists and is not a regular file: saving never replaces a device, a FIFO, a socket or a
/// directory.
void check_replaceable(const std::filesystem::path& path, const std::filesystem::path& target);

}  // namespace granular
