#include "output_paths.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <system_error>

#include "granular/errors.hpp"

namespace granular::cli {

namespace {

std::string head(std::string_view option, const std::filesystem::path& path) {
  return std::string(option) + " " + path.string() + ": ";
}

std::string system_reason() { return std::strerror(errno); }

/// Throws unless `dir` is an existing folder this process may create files in.
void check_writable_folder(std::string_view option, const std::filesystem::path& path, const std::filesystem::path& dir,
                           const std::string& which) {
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(dir, ec);
  if (ec || !std::filesystem::exists(st))
    throw FileError(head(option, path) + which + " '" + dir.string() + "' does not exist");
  if (!std::filesystem::is_directory(st))
    throw FileError(head(option, path) + which + " '" + dir.string() + "' is not a folder");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw FileError(head(option, path) + which + " '" + dir.string() + "' is not writable: " + system_reason());
}

}  // namespace

CLI::Validator non_empty_path() {
  return CLI::Validator(
      [](std::string& value) {
        return value.empty() ? std::string("needs a file or folder name, not an empty value")
                             : std::string();
      },
      "PATH", "non-empty path");
}

void check_output_file(std::string_view option, const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw FileError(head(option, path) + "is a folder, not a file");
  if (std::filesystem::exists(path, ec)) {
    // Overwriting an existing file needs the file's permission, not its folder's (/dev/stdout).
    if (::access(path.c_str(), W_OK) != 0) throw FileError(head(option, path) + "is not writable: " + system_reason());
    return;
  }
  const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  check_writable_folder(option, path, dir, "its folder");
}

void prepare_output_folder(std::string_view option, const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw FileError(head(option, dir) + "cannot create the folder: " + ec.message());
  check_writable_folder(option, dir, dir, "the folder");
}

void write_output_file(const std::filesystem::path& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw FileError("cannot write '" + path.string() + "': " + system_reason());
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size() && std::fflush(f) == 0;
  const std::string reason = written ? std::string() : system_reason();
  if (std::fclose(f) != 0 && written) throw FileError("writing '" + path.string() + "' failed: " + system_reason());
  if (!written) throw FileError("writing '" + path.string() + "' failed: " + reason);
}

void flush_standard_output() {
  std::cout.flush();
  const bool ok = std::cout.good() && std::fflush(stdout) == 0 && !std::ferror(stdout);
  if (!ok) throw FileError("writing the standard output failed: " + system_reason());
}

}  // namespace granular::cli
