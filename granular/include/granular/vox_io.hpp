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

/// The placed models of a .vox may span a grid this many times larger than their summed volume...
inline constexpr std::int64_t kVoxMaxSpread = 64;

/// ...unless the grid holds no more than this many cells (256^3, one full-size model): a sparser,
/// larger grid is refused, so a small file cannot demand gigabytes (docs/FORMATS.md).
inline constexpr std::int64_t kVoxSparseGridCells = std::int64_t(256) * 256 * 256;

/// The placed models of a .vox may hold at most this many voxels per grid cell (overlapping
/// models write a cell more than once; a shape node that places one model over and over is refused).
inline constexpr std::int64_t kVoxMaxOverlap = 8;

/// What an import found, so that lossy mappings are reported rather than silent.
struct VoxImportReport {
  std::int64_t voxels = 0;           ///< voxels written into the grid (every placed XYZI entry)
  std::int64_t unmapped_voxels = 0;  ///< voxels whose palette index is not in 1..7, imported as Solid
  std::vector<int> unmapped_indices; ///< the distinct palette indices of those voxels, ascending
  int models = 0;                    ///< model instances placed into the grid
};

/// The one-line notice a user should see about an import, "" when nothing was lossy: e.g.
/// "scene.vox: 12 of 40 voxels have palette indices that are not materials (0, 9) and were
/// imported as solid; materials are palette indices 1..7 (docs/FORMATS.md)".
std::string vox_import_notice(const VoxImportReport& report, const std::string& source_name);

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
/// byte offset, node or value) for malformed content and for a grid both larger than
/// kVoxSparseGridCells and more than kVoxMaxSpread times the placed models' volume, or for more than kVoxMaxOverlap placed voxels
/// per cell; OutOfMemory
/// when the grid does not fit in memory. Only granular::Error subclasses are thrown.
Grid decode_vox(std::span<const std::uint8_t> bytes, const std::string& source_name, VoxImportReport* report = nullptr);

/// Reads a .vox file; see decode_vox. Throws FileError when the file cannot be opened or read.
Grid load_vox(const std::filesystem::path& path, VoxImportReport* report = nullptr);

/// Writes `grid` to `path` as .vox (see encode_vox), atomically: on failure an existing file at
/// `path` is untouched and FileError is thrown.
void save_vox(const Grid& grid, const std::filesystem::path& path);

}  // namespace granular
