#include "io/regular_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "granular/errors.hpp"
#include "io/file_names.hpp"

namespace granular {

const char* file_kind(mode_t mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string link_note(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_symlink(path, ec)) return {};
  const auto target = std::filesystem::read_symlink(path, ec);
  return ec ? std::string(" (a symbolic link)") : " (a symbolic link to " + quoted(target) + ")";
}

ReadableFile::ReadableFile(const std::filesystem::path& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd_ < 0) {
    const int err = errno;
    throw FileError("cannot open " + quoted(path) + " for reading: " + std::strerror(err));
  }
  struct stat info {};
  if (fstat(fd_, &info) != 0) {
    const int err = errno;
    ::close(fd_);
    throw FileError("cannot read " + quoted(path) + ": " + std::strerror(err));
  }
  if (!S_ISREG(info.st_mode)) {
    ::close(fd_);
    const std::string reason = S_ISDIR(info.st_mode) ? std::string(": ") + std::strerror(EISDIR) : std::string();
    throw FileError("cannot read " + quoted(path) + link_note(path) + ": it is " + file_kind(info.st_mode) +
                    ", not a regular file" + reason);
  }
  size_ = std::uint64_t(info.st_size);
}

ReadableFile::~ReadableFile() { ::close(fd_); }

void ReadableFile::read_at(std::uint64_t at, std::span<std::uint8_t> out) const {
  std::size_t done = 0;
  while (done < out.size()) {
    const ssize_t n = ::pread(fd_, out.data() + done, out.size() - done, off_t(at + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      throw FileError("cannot read " + quoted(path_) + " at byte " + std::to_string(at + done) + ": " + std::strerror(err));
    }
    if (n == 0)
      throw FileError("cannot read " + quoted(path_) + ": the file ended at byte " + std::to_string(at + done) +
                      " while " + std::to_string(at + out.size()) + " bytes were expected (was it modified while being read?)");
    done += std::size_t(n);
  }
}

void check_replaceable(const std::filesystem::path& path, const std::filesystem::path& target) {
  struct stat info {};
  if (::stat(target.c_str(), &info) != 0 || S_ISREG(info.st_mode)) return;
  const std::string reason = S_ISDIR(info.st_mode) ? std::string(": ") + std::strerror(EISDIR) : std::string();
  throw FileError("cannot write " + quoted(path) + link_note(path) + ": it is " + file_kind(info.st_mode) +
                  ", not a regular file; only a regular file (or a symbolic link to one) is replaced" + reason);
}

}  // namespace granular
