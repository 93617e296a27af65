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
/// and the system's reason) or is not a regular file after following symbolic links (a FIFO, a
/// device, a directory...: never opened in a way that blocks), and the errors of decode_raw for
/// malformed content. The body's length is checked against the file's size before the grid is
/// allocated, and no more bytes than the header declares are read.
Grid load_raw(const std::filesystem::path& path);

/// Saves `grid` in the format named by the extension of `path` (case-insensitive): ".raw" (see
/// save_raw) or ".vox" (see save_vox). Any other extension throws InvalidArgument naming it and
/// the accepted ones.
void save_grid(const Grid& grid, const std::filesystem::path& path);

/// Loads a grid from the format named by the extension of `path` (case-insensitive): ".raw" (see
/// load_raw) or ".vox" (see load_vox). Any other extension throws InvalidArgument naming it and
/// the accepted ones. What a user should be told about the import (a .vox whose palette indices
/// are not materials, see vox_import_notice) is appended to `notices` as one line each.
Grid load_grid(const std::filesystem::path& path, std::vector<std::string>* notices = nullptr);

/// True when the extension of `path` names a grid format: ".raw" or ".vox", in any case.
bool is_grid_file(const std::filesystem::path& path);

/// Throws what save_grid would throw because of the path alone, before any work is done:
/// InvalidArgument for an extension other than .raw or .vox, FileError when the path (after
/// symbolic links) exists and is not a regular file (a directory, a FIFO, a device, a socket) or its
/// directory is missing or not writable.
void check_grid_save_path(const std::filesystem::path& path);

/// Largest file read_file_bytes reads unless told otherwise.
inline constexpr std::uint64_t kMaxReadBytes = std::uint64_t(1) << 40;

/// Reads a whole regular file into memory: exactly its size in bytes, never more. Throws FileError
/// (path and system reason) when it cannot be opened or read, when it is not a regular file after
/// following symbolic links (a FIFO, a device, a socket or a directory: never opened in a way that
/// blocks) and when it is larger than `max_bytes`; OutOfMemory when it does not fit in memory.
std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path, std::uint64_t max_bytes = kMaxReadBytes);

/// Follows `path` while it is a symbolic link (relative targets from the link's directory) and
/// returns the first path that is not one (which may not exist). Throws FileError after 40 links.
std::filesystem::path resolve_symlinks(const std::filesystem::path& path);

/// Writes the concatenation of `parts` to `path` without ever leaving a partial file there. When
/// `path` is a symbolic link, its target (resolve_symlinks) is written and the link stays. A target
/// that exists and is not a regular file (a FIFO, a device, a socket, a directory) is refused with
/// a FileError naming the path, the link and what it is, and left as it is. The
/// bytes go to "<target>.tmp-<pid>" beside the target (created exclusively), are flushed to disk,
/// then the temporary is renamed over the target, which keeps the permissions of the file it
/// replaces. On any failure the temporary is removed, an existing file is untouched, and FileError
/// is thrown naming the path, the step that failed and the system's reason. While the write is in
/// progress, remove_pending_temporaries() removes the temporary (for signal handlers).
void write_file_atomic(const std::filesystem::path& path, std::initializer_list<std::span<const std::uint8_t>> parts);

/// Removes the temporary files of the write_file_atomic calls in progress in this process.
/// Async-signal-safe (unlink only): a SIGINT/SIGTERM handler calls it before re-raising the
/// signal, so an interrupted save leaves no "<path>.tmp-<pid>" behind. The library installs no
/// handler itself.
void remove_pending_temporaries() noexcept;

}  // namespace granular
