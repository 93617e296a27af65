#include "io/file_names.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "io/regular_file.hpp"

namespace granular {

std::string quoted(const std::filesystem::path& p) {
  std::string q(1, '\'');  // built by appending: GCC 12 warns falsely on "'" + string (-Wrestrict)
  q.append(p.string());
  q.push_back('\'');
  return q;
}

std::string escaped_bytes(std::span<const std::uint8_t> b, char quote) {
  static const char* kHex = "0123456789ABCDEF";
  std::string s;
  for (std::uint8_t c : b) {
    if (c >= 0x20 && c < 0x7F && c != std::uint8_t(quote) && c != '\\') {
      s += char(c);
    } else {
      s += "\\x";
      s += kHex[c >> 4];
      s += kHex[c & 15];
    }
  }
  return s;
}

std::string printable_bytes(std::span<const std::uint8_t> b) { return '"' + escaped_bytes(b, '"') + '"'; }

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

void check_save_target(const std::filesystem::path& path) {
  const std::filesystem::path target = resolve_symlinks(path);
  check_replaceable(path, target);
  const std::filesystem::path dir = target.parent_path().empty() ? std::filesystem::path(".") : target.parent_path();
  struct stat dir_info {};
  if (::stat(dir.c_str(), &dir_info) != 0) {
    const int err = errno;
    throw FileError("cannot write " + quoted(path) + ": its directory " + quoted(dir) + ": " + std::strerror(err));
  }
  if (!S_ISDIR(dir_info.st_mode))
    throw FileError("cannot write " + quoted(path) + ": " + quoted(dir) + " is not a directory");
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    const int err = errno;
    throw FileError("cannot write " + quoted(path) + ": its directory " + quoted(dir) + " is not writable: " +
                    std::strerror(err));
  }
}

}  // namespace granular
