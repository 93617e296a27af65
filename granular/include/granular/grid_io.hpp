#pragma once
/// @file grid_io.hpp
/// Grid files: the native raw format (.raw), extension-dispatched load/save (.raw, .vox), and the
/// whole-file read / atomic write helpers they share. Formats are documented in docs/FORMATS.md.
///
/// Raw format (little-endian): bytes 0..3 magic "GRAW", 4..7 uint32 version (1), 8..11 uint32 nx,
/// 12..15 uint32 ny, 16..19 uint32 nz, then nx*ny*nz bytes, one Material value (< 8) per cell,
/// x fastest, then y, then z (up). Nothing may follow the last cell.

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

#include "granular/grid.hpp"

namespace granular {

/// The 4 magic bytes that open a raw grid file.
inline constexpr char kRawMagic[4] = {'G', 'R', 'A', 'W'};

/// The raw format version this library reads and writes.
inline constexpr std::uint32_t kRawVersion = 1;

/// Size in bytes of the raw header (magic, version, nx, ny, nz).
inline constexpr std::size_t kRawHeaderSize = 20;

/// Encodes `grid` in the raw format (header then one byte per cell). Throws InvalidArgument for
/// an empty (0x0x0) grid and OutOfMemory when the buffer cannot be allocated.
std::vector<std::uint8_t> encode_raw(const Grid& grid);

/// Decodes a raw grid from `bytes`. `source_name` (usually the file path) starts every error
/// message. Throws ParseError for a bad magic, an unsupported version, a truncated header, zero or
/// over-large dimensions, a truncated body, trailing bytes or a cell value >= 8 (with its byte
/// offset, x, y, z and value); OutOfMemory when the grid does not fit in memory.
Grid decode_raw(std::span<const std::uint8_t> bytes, const std::string& source_name);

/// Writes `grid` to `path` in the raw format, atomically (see write_file_atomic). Throws
/// InvalidArgument for an empty grid and FileError when the file cannot be written; on failure
/// an existing file at `path` is left untouched.
void save_raw(const Grid& grid, const std::filesystem::path& path);

/// Reads a raw grid file. Throws FileError when the file cannot be opened or read (with the path
/// and the system's reason) and the errors of decode_raw for malformed content.
Grid load_raw(const std::filesystem::path& path);

/// Saves `grid` in the format named by the extension of `path` (case-insensitive): ".raw" (see
/// save_raw) or ".vox" (see save_vox). Any other extension throws InvalidArgument naming it and
/// the accepted ones.
void save_grid(const Grid& grid, const std::filesystem::path& path);

/// Loads a grid from the format named by the extension of `path` (case-insensitive): ".raw" (see
/// load_raw) or ".vox" (see load_vox). Any other extension throws InvalidArgument naming it and
/// the accepted ones.
Grid load_grid(const std::filesystem::path& path);

/// Reads a whole file into memory. Throws FileError (path and system reason) when it cannot be
/// opened or read, and OutOfMemory when it does not fit in memory.
std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path);

/// Writes the concatenation of `parts` to `path` without ever leaving a partial file there: the
/// bytes go to "<path>.tmp-<pid>", are flushed to disk, then the temporary is renamed over `path`.
/// On any failure the temporary is removed, an existing file at `path` is untouched, and FileError
/// is thrown naming the path, the step that failed and the system's reason.
void write_file_atomic(const std::filesystem::path& path, std::initializer_list<std::span<const std::uint8_t>> parts);

}  // namespace granular
