#pragma once
/// @file snapshot_bodies.hpp
/// The body section of a snapshot file (version kBodiesSnapshotVersion; docs/FORMATS.md, "Bodies"):
/// a world's BodyStates as bytes, and back.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "granular/body.hpp"

namespace granular {

/// Bytes of one body's record before its cells: its handle, shape, sizes, density and pose.
inline constexpr std::size_t kBodyRecordBytes = 168;

/// Bytes of the body section that holds `bodies` bodies and `cells` cells in all: the next handle,
/// each body's record and cell count, and a uint64 per cell.
constexpr std::uint64_t body_section_bytes(std::uint64_t bodies, std::uint64_t cells) {
  return 8 + bodies * (kBodyRecordBytes + 8) + 8 * cells;
}

/// The body section of `states`: the next handle, then per body its record, its cell count and its
/// cells as the first grid index and the gaps to each next. Throws InvalidArgument, starting with
/// `who`, for more than kMaxBodies bodies, a shape that is not a BodyShape, or cells that are not
/// ascending.
std::vector<std::uint8_t> encode_body_section(const BodyStates& states, const std::string& who);

/// The BodyStates of the body section `bytes`, which holds `count` bodies of a grid of `cells` cells.
/// Throws ParseError starting with `src` and naming the body and field for a section shorter or
/// longer than its bodies, a shape that is not a BodyShape, a reserved field that is not 0, a cell gap
/// of 0 or a cell past the grid.
/// What a World checks (sizes, densities, poses, handles, the cells' material) it leaves to it.
BodyStates decode_body_section(std::span<const std::uint8_t> bytes, std::uint32_t count, std::uint64_t cells,
                               const std::string& src);

}  // namespace granular
