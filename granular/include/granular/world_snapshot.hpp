#pragma once
/// @file world_snapshot.hpp
/// Snapshots: a world's whole state (every cell byte, motion state included; the tick; the seed;
/// the tool calls pour salts its choice with; the rule set's name and fingerprint), so that a world
/// made from one continues bit-identically, and the snapshot file (.gsnap, zstd-compressed cells)
/// documented field by field in docs/FORMATS.md. World::capture, World::restore and
/// World(def, snapshot) move a state into and out of a World.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "granular/body.hpp"
#include "granular/geometry.hpp"

namespace granular {

/// A world's whole state.
struct WorldSnapshot {
  Int3 size{};                      ///< grid extent
  std::vector<std::uint8_t> cells;  ///< every cell byte as the backend holds it (x fastest; motion.hpp)
  std::uint64_t tick = 0;           ///< World::tick()
  std::uint64_t seed = 0;           ///< WorldDef::seed
  std::uint64_t tool_calls = 0;     ///< World::tool_calls()
  std::string rules;                ///< the rule set's name (RuleSet::name)
  std::uint64_t rule_fingerprint = 0;  ///< rule_fingerprint() of the rule set
  std::vector<std::uint8_t> side;      ///< the side plane under MotionParams::momentum (a liquid's velocity per
                                       ///< cell, x fastest; granular/step/momentum.hpp), or empty when every
                                       ///< cell is at rest
  std::vector<std::int32_t> faces;     ///< the face plane under MotionParams::shallow (4 int32 per column:
                                       ///< the x faces' velocities, the y faces', the x faces' fractions, the
                                       ///< y faces', each nx ny values, x fastest; granular/step/shallow_water.hpp),
                                       ///< or empty when every face is at rest
  BodyStates bodies;                   ///< the rigid bodies (World::body_states); none in most worlds
  /// The World::hash() of the cells, their velocities and the faces.
  std::uint64_t hash() const;
};

/// The 4 magic bytes that open a snapshot file.
inline constexpr char kSnapshotMagic[4] = {'G', 'S', 'N', 'P'};

/// The snapshot format version World and DistributedWorld write: the cells in one or more zstd
/// frames (a World's one, a DistributedWorld's one per rank's slab), and a header hash that covers
/// the header's fields (extents, tick, seed, tool calls, rule fingerprint, rule set name) as well
/// as the cells (snapshot_file_hash).
inline constexpr std::uint32_t kSnapshotVersion = 3;

/// The snapshot format version of a snapshot with a side plane (WorldSnapshot::side not empty): as
/// kSnapshotVersion, but the zstd frames hold the side plane after the cells (2 nx ny nz bytes in
/// all), and the hash covers it (WorldSnapshot::hash). A snapshot without one is written as
/// kSnapshotVersion, which every earlier reader reads.
inline constexpr std::uint32_t kSideSnapshotVersion = 4;

/// The snapshot format version of a snapshot with a face plane (WorldSnapshot::faces not empty): as
/// kSnapshotVersion, but the zstd frames hold the face plane after the cells (16 nx ny bytes, each
/// value a little-endian int32), and the hash covers it (WorldSnapshot::hash).
inline constexpr std::uint32_t kFacesSnapshotVersion = 5;

/// The snapshot format version of a snapshot with bodies (WorldSnapshot::bodies holds a body, or a
/// next handle other than 1): a 16-byte body header after the rule set name gives the version whose
/// cells and plane the zstd frames hold first (kSnapshotVersion, kSideSnapshotVersion or
/// kFacesSnapshotVersion), the body count and the bytes of the body section the frames hold after
/// them (docs/FORMATS.md); the hash covers the body section too.
inline constexpr std::uint32_t kBodiesSnapshotVersion = 6;

/// Bytes of a version-6 snapshot's body header, after the rule set name.
inline constexpr std::size_t kSnapshotBodyHeaderSize = 16;

/// An older version, still read: the cells in one zstd frame; the header hash covers the cells only.
inline constexpr std::uint32_t kOneFrameSnapshotVersion = 1;

/// An older version, still read: one zstd frame per slab; the header hash covers the cells only.
inline constexpr std::uint32_t kSlabSnapshotVersion = 2;

/// Size in bytes of the snapshot header, before the rule set's name.
inline constexpr std::size_t kSnapshotHeaderSize = 72;

/// Longest rule set name a snapshot holds, in bytes.
inline constexpr std::size_t kMaxSnapshotRulesName = 256;

/// The extension of snapshot files (matched case-insensitively).
inline constexpr const char* kSnapshotExtension = ".gsnap";

/// Encodes `snapshot` in the snapshot format, version kSnapshotVersion (header, rule set name, one
/// zstd frame of the cells), or kSideSnapshotVersion when it has a side plane (the frame holds the
/// cells, then the side plane), or kFacesSnapshotVersion when it has a face plane (the cells, then
/// the faces), or kBodiesSnapshotVersion when it has bodies (one of those, then the body section).
/// Throws InvalidArgument for a bad size, a cell count other than the size's, a side plane of
/// another size, a face plane of other than 4 values per column, both planes at once, more than
/// kMaxBodies bodies, a body shape that is not a BodyShape or cells not ascending, or a rule set name
/// that is empty, longer than kMaxSnapshotRulesName or holds a control character; OutOfMemory when
/// the buffer cannot be allocated.
std::vector<std::uint8_t> encode_snapshot(const WorldSnapshot& snapshot);

/// Decodes a snapshot from `bytes`. `source_name` (usually the file path) starts every error
/// message. Throws ParseError naming the field, offset or value for a bad magic, an unsupported
/// version, a truncated header, rule set name or body, trailing bytes, zero or over-large extents,
/// a bad name, more cells than zstd can expand the body to, a compressed body that is not zstd
/// frames (one in version 1) each stating its content size, together exactly nx * ny * nz bytes
/// (sizes are checked before anything is allocated), or a hash (snapshot_file_hash) that is not the
/// header's; OutOfMemory when the grid does not fit in memory (check_grid_size).
WorldSnapshot decode_snapshot(std::span<const std::uint8_t> bytes, const std::string& source_name);

/// Writes `snapshot` to `path` atomically (write_file_atomic). Throws what encode_snapshot throws,
/// InvalidArgument when the extension is not .gsnap, and FileError when the file cannot be written
/// (an existing file is then left untouched).
void save_snapshot(const WorldSnapshot& snapshot, const std::filesystem::path& path);

/// Reads a snapshot file in this order: a regular file (opened without blocking, then fstat), its
/// header and name, the sizes they declare against the file's size, zstd's largest expansion and
/// the memory budget, and only then the compressed cells, which are decompressed and hashed.
/// Throws FileError when the file cannot be read, and decode_snapshot's errors.
WorldSnapshot load_snapshot(const std::filesystem::path& path);

/// The header field `hash` of a snapshot of `version` whose cells hash to `cells_hash`
/// (hash_cells): `cells_hash` itself in versions 1 and 2; in version 3 a mix of it with the header's
/// version, extents, tick, seed, tool calls, rule fingerprint and rule set name, so that a changed
/// header field is refused as damage.
std::uint64_t snapshot_file_hash(const WorldSnapshot& meta, std::uint64_t cells_hash, std::uint32_t version);

/// True when the extension of `path` is .gsnap, in any case.
bool is_snapshot_file(const std::filesystem::path& path);

/// Throws what save_snapshot would throw because of the path alone, before any work is done:
/// InvalidArgument for an extension other than .gsnap, FileError when the path (after symbolic
/// links) exists and is not a regular file (a directory, a FIFO, a device, a socket) or its
/// directory is missing or not writable.
void check_snapshot_save_path(const std::filesystem::path& path);

}  // namespace granular
