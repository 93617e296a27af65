#pragma once
/// @file expansion_bound.hpp
/// The one rule by which a reader bounds what a file declares by what the file holds, before it
/// allocates: a declared size above a floor may be at most a fixed multiple of the bytes (or cells)
/// that back it. The .vox reader bounds a scene's bounding box by its models' volume with it
/// (kVoxMaxSpread over kVoxSparseGridCells); the snapshot readers bound a header's cells, and each
/// zstd frame's stated content, by the compressed bytes with it (kMaxZstdExpansion, no floor).

#include <cstdint>

namespace granular {

/// The most a zstd frame expands: a block yields at most 128 KiB and takes at least 4 bytes (an
/// RLE block: its 3-byte header and the byte), so P bytes of frames hold at most 32768 P bytes.
inline constexpr std::uint64_t kMaxZstdExpansion = 32768;

/// True when `declared` is more than `floor` and at least `max_ratio` times `backing`: more than
/// `backing` can stand for.
constexpr bool exceeds_expansion(std::uint64_t declared, std::uint64_t backing, std::uint64_t max_ratio,
                                 std::uint64_t floor = 0) {
  return declared > floor && declared / max_ratio >= backing;
}

}  // namespace granular
