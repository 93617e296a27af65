#pragma once
/// @file vox_io.hpp
/// MagicaVoxel .vox import and export (file versions 150 and 200). The mapping is by palette
/// index: index i in 1..7 is Material(i); void cells are not stored. Grids larger than 256 cells
/// along an axis are split into models of at most 256^3 placed by a scene graph. See
/// docs/FORMATS.md for the details.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "granular/grid.hpp"

namespace granular {

/// Largest model extent along one axis that MagicaVoxel accepts.
inline constexpr int kVoxMaxModelExtent = 256;

/// What an import found, so that lossy mappings are reported rather than silent.
struct VoxImportReport {
  std::int64_t voxels = 0;           ///< voxels written into the grid (every placed XYZI entry)
  std::int64_t unmapped_voxels = 0;  ///< voxels whose palette index is not in 1..7, imported as Solid
  int models = 0;                    ///< model instances placed into the grid
};

/// Encodes `grid` as a .vox file (version 150). Void cells are omitted; material m is written
/// with palette index m, and an RGBA chunk gives each material a distinct colour. A grid of at
/// most 256 cells per axis becomes one model; a larger one is split into models of at most 256^3
/// with a scene graph (nTRN root, nGRP, one nTRN + nSHP per model) that assembles them. Throws
/// InvalidArgument for an empty grid or one whose voxels exceed the format's 2 GiB chunk limit.
std::vector<std::uint8_t> encode_vox(const Grid& grid);

/// Decodes a .vox file held in `bytes`; `source_name` (usually the path) starts every error
/// message. Models are placed by their scene-graph translations (identity rotations only); the
/// grid is the bounding box of all placed models, shifted to start at 0. Palette index i in 1..7
/// becomes Material(i); any other index becomes Solid and is counted in
/// `report->unmapped_voxels`. Unknown chunks are skipped. Throws ParseError (naming the chunk,
/// byte offset, node or value) for malformed content and OutOfMemory when the grid is too large.
Grid decode_vox(std::span<const std::uint8_t> bytes, const std::string& source_name, VoxImportReport* report = nullptr);

/// Reads a .vox file; see decode_vox. Throws FileError when the file cannot be opened or read.
Grid load_vox(const std::filesystem::path& path, VoxImportReport* report = nullptr);

/// Writes `grid` to `path` as .vox (see encode_vox), atomically: on failure an existing file at
/// `path` is untouched and FileError is thrown.
void save_vox(const Grid& grid, const std::filesystem::path& path);

}  // namespace granular
