#pragma once
/// @file snapshot_header.hpp
/// The snapshot file's header, parsed and checked apart from its cells: decode_snapshot and a
/// DistributedWorld's ranks, each of which reads only the header and its slab's part of the cells.

#include <cstdint>
#include <span>
#include <vector>
#include <string>

#include "granular/world_snapshot.hpp"

namespace granular {

/// A snapshot file's header (docs/FORMATS.md).
struct SnapshotHeader {
  WorldSnapshot meta;            ///< every field but the cells
  std::uint32_t version = 0;     ///< kOneFrameSnapshotVersion .. kBodiesSnapshotVersion
  std::uint32_t layout = 0;      ///< the version whose cells and plane the frames hold (version, but in
                                 ///< kBodiesSnapshotVersion its body header's)
  std::uint32_t body_count = 0;  ///< bodies of the body section (kBodiesSnapshotVersion)
  std::uint64_t body_bytes = 0;  ///< bytes of the body section after the cells and plane
  std::uint64_t hash = 0;        ///< the header's hash field (snapshot_file_hash)
  std::size_t body_at = 0;       ///< where the compressed cells start
  std::uint64_t packed_size = 0; ///< their bytes
};

/// Parses the header and rule set name at the start of `bytes` (at least that much of a file of
/// `total` bytes) and checks what does not need the cells (decode_snapshot's errors but those of the
/// cells). Throws ParseError starting with `src`.
SnapshotHeader parse_snapshot_header(std::span<const std::uint8_t> bytes, std::uint64_t total, const std::string& src);

class ReadableFile;

/// The header of the snapshot file `file`, read (its first bytes only: the header and the rule set
/// name at most) and checked (parse_snapshot_header) before anything else of the file is.
SnapshotHeader read_snapshot_header(const ReadableFile& file);

/// The message of a hash (snapshot_file_hash) that differs from the header's, in a file of `version`.
std::string snapshot_hash_problem(std::uint64_t found, std::uint64_t header, std::uint32_t version);

/// The bytes of a snapshot header (version `version`) and rule set name for `meta` (its cells
/// unused) whose hash field is `hash` (snapshot_file_hash) and whose cells take `packed_size`
/// compressed bytes; in kBodiesSnapshotVersion then the body header: `layout`, meta's body count
/// and `body_bytes`.
std::vector<std::uint8_t> snapshot_header_bytes(const WorldSnapshot& meta, std::uint32_t version, std::uint64_t hash,
                                                std::uint64_t packed_size, std::uint32_t layout = 0,
                                                std::uint64_t body_bytes = 0);

}  // namespace granular
