#pragma once
/// @file file_names.hpp
/// What the file readers and writers share about paths and bytes: how a path and bytes read from a
/// file appear in messages, a path's extension, and the checks of a path to save to.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace granular {

/// `path` in single quotes, for messages.
std::string quoted(const std::filesystem::path& path);

/// Bytes from a file for a message quoted with `quote`: printable ASCII as is, and `quote`, the
/// backslash and every other byte as \xHH.
std::string escaped_bytes(std::span<const std::uint8_t> bytes, char quote);

/// Bytes from a file in double quotes (escaped_bytes).
std::string printable_bytes(std::span<const std::uint8_t> bytes);

/// The extension of `path` in lower case (".raw"), "" when it has none.
std::string lower_extension(const std::filesystem::path& path);

/// Throws FileError when a file cannot be saved at `path` because of the path alone: the path
/// (after symbolic links) exists and is not a regular file (check_replaceable: a directory, a
/// FIFO, a device, a socket), or its directory is missing, not a directory or not writable.
void check_save_target(const std::filesystem::path& path);

}  // namespace granular
