#include "granular/world_snapshot.hpp"

#include <algorithm>
#include <cstring>
#include <new>

#include "io/file_names.hpp"
#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular/grid_io.hpp"
#include "granular/extend/hex.hpp"
#include "io/expansion_bound.hpp"
#include "io/little_endian.hpp"
#include "io/regular_file.hpp"
#include "io/snapshot_bodies.hpp"
#include "io/snapshot_header.hpp"
#include "io/zstd_bytes.hpp"

namespace granular {

namespace {

/// Where each field of the header lies (docs/FORMATS.md, "Snapshot format").
struct Field {
  const char* name;
  std::size_t at;
  std::size_t bytes;
};
constexpr Field kMagicField{"magic", 0, 4};
constexpr Field kVersionField{"version", 4, 4};
constexpr Field kExtentFields[3] = {{"nx", 8, 4}, {"ny", 12, 4}, {"nz", 16, 4}};
constexpr Field kNameLengthField{"rules_length", 20, 4};
constexpr Field kTickField{"tick", 24, 8};
constexpr Field kSeedField{"seed", 32, 8};
constexpr Field kToolCallsField{"tool_calls", 40, 8};
constexpr Field kFingerprintField{"rule_fingerprint", 48, 8};
constexpr Field kHashField{"hash", 56, 8};
constexpr Field kPackedSizeField{"packed_size", 64, 8};
constexpr Field kHeaderFields[] = {kMagicField,        kVersionField,   kExtentFields[0], kExtentFields[1],
                                   kExtentFields[2],   kNameLengthField, kTickField,      kSeedField,
                                   kToolCallsField,    kFingerprintField, kHashField,     kPackedSizeField};
static_assert(kPackedSizeField.at + kPackedSizeField.bytes == kSnapshotHeaderSize);

/// "field (bytes a..b)" for messages.
std::string field_text(const Field& f) {
  return std::string(f.name) + " (bytes " + std::to_string(f.at) + ".." + std::to_string(f.at + f.bytes - 1) + ")";
}

/// What keeps `name` from being a snapshot's rule set name ("is empty"), or "" when nothing does.
std::string name_problem(const std::string& name) {
  if (name.empty()) return "is empty";
  if (name.size() > kMaxSnapshotRulesName)
    return "is " + std::to_string(name.size()) + " bytes, more than " + std::to_string(kMaxSnapshotRulesName);
  for (std::size_t i = 0; i < name.size(); ++i)
    if (static_cast<unsigned char>(name[i]) < 0x20 || name[i] == 0x7F)
      return "holds the control character " + printable_bytes(std::span(reinterpret_cast<const std::uint8_t*>(name.data()) + i, 1)) +
             " at byte " + std::to_string(i);
  return {};
}

/// Where each field of a version-6 body header lies, counted from its start (after the name).
constexpr Field kLayoutField{"layout", 0, 4};
constexpr Field kBodyCountField{"body_count", 4, 4};
constexpr Field kBodyBytesField{"body_bytes", 8, 8};

/// Bytes of the plane the frames of `layout` (a snapshot's version, or a version-6 body header's
/// layout) hold after the cells of its `size` grid: a side byte per cell (kSideSnapshotVersion), 4
/// int32 per column (kFacesSnapshotVersion), or none.
std::uint64_t plane_bytes(std::uint32_t layout, Int3 size) {
  const std::uint64_t columns = std::uint64_t(size.x) * std::uint64_t(size.y);
  if (layout == kSideSnapshotVersion) return columns * std::uint64_t(size.z);
  if (layout == kFacesSnapshotVersion) return 16 * columns;
  return 0;
}

/// The layout of `s`'s cells and plane: the version it would be written as without bodies.
std::uint32_t layout_of(const WorldSnapshot& s) {
  return !s.faces.empty() ? kFacesSnapshotVersion : !s.side.empty() ? kSideSnapshotVersion : kSnapshotVersion;
}

/// True when `s` is written as kBodiesSnapshotVersion: it has a body, or a next handle past the first.
bool has_bodies(const WorldSnapshot& s) { return !s.bodies.bodies.empty() || s.bodies.next_id != 1; }

/// A hash of `bytes` (the body section), for snapshot_file_hash.
std::uint64_t bytes_hash(std::span<const std::uint8_t> bytes) {
  std::uint64_t h = mix64(bytes.size() ^ 0x424F444945535345ull);  // "BODIESSE"
  for (std::size_t i = 0; i < bytes.size(); i += 8) {
    std::uint64_t word = 0;
    for (std::size_t k = 0; k < 8 && i + k < bytes.size(); ++k) word |= std::uint64_t(bytes[i + k]) << (8 * k);
    h = mix64(h ^ word) + 0x9E3779B97F4A7C15ull;
  }
  return mix64(h);
}

/// The extents of the header, checked (ParseError, or OutOfMemory when the cells do not fit).
Int3 parse_extents(std::span<const std::uint8_t> head, const std::string& src) {
  std::uint64_t dims[3];
  for (int a = 0; a < 3; ++a) {
    dims[a] = get_u32(head, kExtentFields[a].at);
    if (dims[a] == 0 || dims[a] > std::uint64_t(kMaxGridExtent))
      throw ParseError(src + ": header field " + field_text(kExtentFields[a]) + " = " + std::to_string(dims[a]) +
                       " is outside 1.." + std::to_string(kMaxGridExtent));
  }
  return {int(dims[0]), int(dims[1]), int(dims[2])};
}

}  // namespace

std::uint64_t WorldSnapshot::hash() const {
  return finish_hash(size, hash_words(cells, 0, (cells.size() + 7) / 8) + side_hash_term(side) + faces_hash_term(faces));
}

namespace {

/// snapshot_file_hash, given the bytes_hash of the body section (version kBodiesSnapshotVersion), so
/// that a caller holding the section's bytes does not encode it again.
std::uint64_t file_hash(const WorldSnapshot& meta, std::uint64_t cells_hash, std::uint32_t version,
                        std::uint64_t section_hash) {
  if (version < kSnapshotVersion) return cells_hash;
  std::uint64_t h = mix64(cells_hash ^ 0x47534E5048454144ull);  // "GSNPHEAD"
  for (const std::uint64_t field : {std::uint64_t(version), std::uint64_t(std::uint32_t(meta.size.x)),
                                    std::uint64_t(std::uint32_t(meta.size.y)), std::uint64_t(std::uint32_t(meta.size.z)),
                                    meta.tick, meta.seed, meta.tool_calls, meta.rule_fingerprint,
                                    std::uint64_t(meta.rules.size())})
    h = mix64(h ^ field) + 0x9E3779B97F4A7C15ull;
  for (const char c : meta.rules) h = mix64(h ^ static_cast<unsigned char>(c)) + 0x9E3779B97F4A7C15ull;
  if (version == kBodiesSnapshotVersion)
    for (const std::uint64_t field :
         {std::uint64_t(layout_of(meta)), std::uint64_t(meta.bodies.bodies.size()), section_hash})
      h = mix64(h ^ field) + 0x9E3779B97F4A7C15ull;
  return mix64(h);
}

}  // namespace

std::uint64_t snapshot_file_hash(const WorldSnapshot& meta, std::uint64_t cells_hash, std::uint32_t version) {
  return file_hash(
      meta, cells_hash, version,
      version == kBodiesSnapshotVersion ? bytes_hash(encode_body_section(meta.bodies, "snapshot_file_hash")) : 0);
}

std::vector<std::uint8_t> encode_snapshot(const WorldSnapshot& s) {
  check_grid_extents(s.size, "encode_snapshot: WorldSnapshot::size");
  const std::uint64_t cells = std::uint64_t(s.size.x) * std::uint64_t(s.size.y) * std::uint64_t(s.size.z);
  if (s.cells.size() != cells)
    throw InvalidArgument("encode_snapshot: WorldSnapshot::cells holds " + std::to_string(s.cells.size()) +
                          " bytes; the " + to_string(s.size) + " grid has " + std::to_string(cells) + " cells");
  if (const std::string problem = name_problem(s.rules); !problem.empty())
    throw InvalidArgument("encode_snapshot: WorldSnapshot::rules '" + s.rules.substr(0, 40) + "' " + problem);
  if (!s.side.empty() && s.side.size() != cells)
    throw InvalidArgument("encode_snapshot: WorldSnapshot::side holds " + std::to_string(s.side.size()) +
                          " bytes; the " + to_string(s.size) + " grid has " + std::to_string(cells) +
                          " cells (or 0 bytes: no velocity)");
  const std::uint64_t face_values = 4 * std::uint64_t(s.size.x) * std::uint64_t(s.size.y);
  if (!s.faces.empty() && s.faces.size() != face_values)
    throw InvalidArgument("encode_snapshot: WorldSnapshot::faces holds " + std::to_string(s.faces.size()) +
                          " values; the " + to_string(s.size) + " grid's face plane has " + std::to_string(face_values) +
                          " (4 per column; or 0: every face at rest)");
  if (!s.faces.empty() && !s.side.empty())
    throw InvalidArgument("encode_snapshot: WorldSnapshot::side and WorldSnapshot::faces are both set; no rule set "
                          "keeps both planes (MotionParams::momentum needs pressure, which shallow refuses)");
  const std::uint32_t layout = layout_of(s);
  const std::uint32_t version = has_bodies(s) ? kBodiesSnapshotVersion : layout;
  const std::vector<std::uint8_t> section =
      has_bodies(s) ? encode_body_section(s.bodies, "encode_snapshot: WorldSnapshot::bodies") : std::vector<std::uint8_t>{};
  const std::uint64_t extra = s.side.size() + 4 * s.faces.size() + section.size();
  std::vector<std::uint8_t> body;
  if (extra != 0) {
    try {
      body.reserve(s.cells.size() + extra);
    } catch (const std::bad_alloc&) {
      throw OutOfMemory("encode_snapshot: could not allocate " + std::to_string(cells + extra) +
                        " bytes for the cells, the side or face plane and the bodies of a " + to_string(s.size) +
                        " grid");
    }
    body.insert(body.end(), s.cells.begin(), s.cells.end());
    body.insert(body.end(), s.side.begin(), s.side.end());
    for (const std::int32_t f : s.faces) {
      std::uint8_t le[4];
      put_u32(le, std::uint32_t(f));
      body.insert(body.end(), le, le + 4);
    }
    body.insert(body.end(), section.begin(), section.end());
  }
  const std::vector<std::uint8_t> packed = zstd_compress(extra == 0 ? s.cells : body, 3, "encode_snapshot");
  std::vector<std::uint8_t> out = snapshot_header_bytes(
      s, version, file_hash(s, s.hash(), version, bytes_hash(section)), packed.size(), layout, section.size());
  try {
    out.insert(out.end(), packed.begin(), packed.end());
  } catch (const std::bad_alloc&) {
    throw OutOfMemory("encode_snapshot: could not allocate " + std::to_string(kSnapshotHeaderSize + packed.size()) +
                      " bytes for the snapshot of a " + to_string(s.size) + " grid");
  }
  return out;
}

std::vector<std::uint8_t> snapshot_header_bytes(const WorldSnapshot& s, std::uint32_t version, std::uint64_t hash,
                                                std::uint64_t packed_size, std::uint32_t layout,
                                                std::uint64_t body_bytes) {
  const bool bodies = version == kBodiesSnapshotVersion;
  std::vector<std::uint8_t> out(kSnapshotHeaderSize + s.rules.size() + (bodies ? kSnapshotBodyHeaderSize : 0));
  std::uint8_t* h = out.data();
  std::copy(std::begin(kSnapshotMagic), std::end(kSnapshotMagic), h);
  put_u32(h + kVersionField.at, version);
  put_u32(h + kExtentFields[0].at, std::uint32_t(s.size.x));
  put_u32(h + kExtentFields[1].at, std::uint32_t(s.size.y));
  put_u32(h + kExtentFields[2].at, std::uint32_t(s.size.z));
  put_u32(h + kNameLengthField.at, std::uint32_t(s.rules.size()));
  put_u64(h + kTickField.at, s.tick);
  put_u64(h + kSeedField.at, s.seed);
  put_u64(h + kToolCallsField.at, s.tool_calls);
  put_u64(h + kFingerprintField.at, s.rule_fingerprint);
  put_u64(h + kHashField.at, hash);
  put_u64(h + kPackedSizeField.at, packed_size);
  std::memcpy(h + kSnapshotHeaderSize, s.rules.data(), s.rules.size());
  if (bodies) {
    std::uint8_t* b = h + kSnapshotHeaderSize + s.rules.size();
    put_u32(b + kLayoutField.at, layout);
    put_u32(b + kBodyCountField.at, std::uint32_t(s.bodies.bodies.size()));
    put_u64(b + kBodyBytesField.at, body_bytes);
  }
  return out;
}

namespace {

/// Parses and checks the body header of a version-6 snapshot, at h.body_at of `bytes` (a file of
/// `total` bytes whose grid holds `cells` cells), into `h`, and moves h.body_at past it.
void parse_body_header(std::span<const std::uint8_t> bytes, std::uint64_t total, std::uint64_t cells,
                       SnapshotHeader& h, const std::string& src) {
  const std::size_t at = h.body_at;
  auto text = [at](const Field& f) {
    return std::string(f.name) + " (bytes " + std::to_string(at + f.at) + ".." + std::to_string(at + f.at + f.bytes - 1) +
           ")";
  };
  if (total < at + kSnapshotBodyHeaderSize || bytes.size() < at + kSnapshotBodyHeaderSize)
    throw ParseError(src + ": truncated body header: version " + std::to_string(kBodiesSnapshotVersion) + " has " +
                     std::to_string(kSnapshotBodyHeaderSize) + " bytes after the rule set name, at byte " +
                     std::to_string(at) + ", but the file has " + std::to_string(total));
  h.layout = get_u32(bytes, at + kLayoutField.at);
  if (h.layout != kSnapshotVersion && h.layout != kSideSnapshotVersion && h.layout != kFacesSnapshotVersion)
    throw ParseError(src + ": body header field " + text(kLayoutField) + " = " + std::to_string(h.layout) + " is not " +
                     std::to_string(kSnapshotVersion) + ", " + std::to_string(kSideSnapshotVersion) + " or " +
                     std::to_string(kFacesSnapshotVersion));
  h.body_count = get_u32(bytes, at + kBodyCountField.at);
  if (h.body_count > kMaxBodies)
    throw ParseError(src + ": body header field " + text(kBodyCountField) + " = " + std::to_string(h.body_count) +
                     " is more than kMaxBodies (" + std::to_string(kMaxBodies) + ")");
  h.body_bytes = get_u64(bytes, at + kBodyBytesField.at);
  const std::uint64_t least = body_section_bytes(h.body_count, 0), most = body_section_bytes(h.body_count, cells);
  if (h.body_bytes < least || h.body_bytes > most)
    throw ParseError(src + ": body header field " + text(kBodyBytesField) + " = " + std::to_string(h.body_bytes) +
                     " is outside " + std::to_string(least) + ".." + std::to_string(most) + " (" +
                     std::to_string(h.body_count) + " bodies holding at most the grid's " + std::to_string(cells) +
                     " cells)");
  h.body_at = at + kSnapshotBodyHeaderSize;
}

}  // namespace

SnapshotHeader parse_snapshot_header(std::span<const std::uint8_t> bytes, std::uint64_t total, const std::string& src) {
  const std::size_t magic_have = std::min<std::size_t>(bytes.size(), 4);
  if (!std::equal(bytes.begin(), bytes.begin() + std::ptrdiff_t(magic_have), kSnapshotMagic))
    throw ParseError(src + ": not a snapshot file: bad magic " + printable_bytes(bytes.first(magic_have)) +
                     " at byte 0 (expected \"GSNP\")");
  if (total < kSnapshotHeaderSize) {
    const Field* ends_in = &kHeaderFields[0];
    for (const Field& f : kHeaderFields)
      if (f.at < total) ends_in = &f;
    throw ParseError(src + ": truncated header: the file has " + std::to_string(total) +
                     " bytes and ends inside field " + field_text(*ends_in) + "; a snapshot header is " +
                     std::to_string(kSnapshotHeaderSize) + " bytes");
  }
  SnapshotHeader h;
  h.version = get_u32(bytes, kVersionField.at);
  if (h.version < kOneFrameSnapshotVersion || h.version > kBodiesSnapshotVersion)
    throw ParseError(src + ": unsupported snapshot version " + std::to_string(h.version) + " (field " +
                     field_text(kVersionField) + "); this build reads versions " +
                     std::to_string(kOneFrameSnapshotVersion) + ".." + std::to_string(kBodiesSnapshotVersion));
  WorldSnapshot& s = h.meta;
  s.size = parse_extents(bytes, src);
  const std::uint32_t name_length = get_u32(bytes, kNameLengthField.at);
  if (name_length == 0 || name_length > kMaxSnapshotRulesName)
    throw ParseError(src + ": header field " + field_text(kNameLengthField) + " = " + std::to_string(name_length) +
                     " is outside 1.." + std::to_string(kMaxSnapshotRulesName));
  if (total < kSnapshotHeaderSize + name_length || bytes.size() < kSnapshotHeaderSize + name_length)
    throw ParseError(src + ": truncated rule set name: the header says " + std::to_string(name_length) +
                     " bytes but only " + std::to_string(total - kSnapshotHeaderSize) + " follow the " +
                     std::to_string(kSnapshotHeaderSize) + "-byte header");
  s.rules.assign(reinterpret_cast<const char*>(bytes.data()) + kSnapshotHeaderSize, name_length);
  if (const std::string problem = name_problem(s.rules); !problem.empty())
    throw ParseError(src + ": the rule set name at byte " + std::to_string(kSnapshotHeaderSize) + " " + problem);
  s.tick = get_u64(bytes, kTickField.at);
  s.seed = get_u64(bytes, kSeedField.at);
  s.tool_calls = get_u64(bytes, kToolCallsField.at);
  s.rule_fingerprint = get_u64(bytes, kFingerprintField.at);
  h.hash = get_u64(bytes, kHashField.at);
  h.packed_size = get_u64(bytes, kPackedSizeField.at);
  h.body_at = kSnapshotHeaderSize + name_length;
  h.layout = h.version;
  const std::uint64_t cells = std::uint64_t(s.size.x) * std::uint64_t(s.size.y) * std::uint64_t(s.size.z);
  if (h.version == kBodiesSnapshotVersion) parse_body_header(bytes, total, cells, h, src);
  const std::uint64_t body = total - h.body_at;
  if (body < h.packed_size)
    throw ParseError(src + ": truncated body: header field " + field_text(kPackedSizeField) + " says " +
                     std::to_string(h.packed_size) + " bytes of compressed cells but only " + std::to_string(body) +
                     " follow the rule set name");
  if (body > h.packed_size)
    throw ParseError(src + ": " + std::to_string(body - h.packed_size) + " trailing bytes after the compressed cells: " +
                     "the file should be " + std::to_string(h.body_at + h.packed_size) + " bytes but it is " +
                     std::to_string(total));
  const std::uint64_t plane = plane_bytes(h.layout, s.size);  // the side or face plane after the cells
  const std::uint64_t extra = plane + h.body_bytes;
  if (exceeds_expansion(cells + extra, h.packed_size, kMaxZstdExpansion))
    throw ParseError(src + ": header fields nx, ny, nz (" + to_string(s.size) + " = " + std::to_string(cells) +
                     " cells" + (plane == 0 ? "" : ", and " + std::to_string(plane) + " bytes of its plane") +
                     (h.body_bytes == 0 ? "" : ", and " + std::to_string(h.body_bytes) + " bytes of bodies") +
                     ") cannot come from " +
                     std::to_string(h.packed_size) + " bytes of compressed cells (zstd expands at most " +
                     std::to_string(kMaxZstdExpansion) + "-fold)");
  return h;
}

std::string snapshot_hash_problem(std::uint64_t found, std::uint64_t header, std::uint32_t version) {
  const std::string what = version < kSnapshotVersion
                               ? "the cells' hash "
                               : "the hash of the cells and the header's fields (extents, tick, seed, tool_calls, "
                                 "rule_fingerprint, the rule set name) ";
  return what + hex64(found) + " differs from header field " + field_text(kHashField) + " = " + hex64(header) +
         " (the file is damaged)";
}

namespace {

/// The cells of the snapshot whose header is `h` from its compressed cells `packed`, checked
/// against the header's hash.
WorldSnapshot decode_body(SnapshotHeader h, std::span<const std::uint8_t> packed, const std::string& src) {
  WorldSnapshot& s = h.meta;
  const std::uint64_t cells = std::uint64_t(s.size.x) * std::uint64_t(s.size.y) * std::uint64_t(s.size.z);
  const std::uint64_t plane = plane_bytes(h.layout, s.size);
  const std::uint64_t extra = plane + h.body_bytes;
  s.cells = zstd_decompress(packed, cells + extra, src + ": the compressed cells at byte " + std::to_string(h.body_at),
                            h.version != kOneFrameSnapshotVersion);
  std::uint64_t section_hash = 0;  // of the body section's bytes, for the file's hash
  if (h.version == kBodiesSnapshotVersion) {
    const auto section = std::span<const std::uint8_t>(s.cells).subspan(std::size_t(cells + plane));
    s.bodies = decode_body_section(section, h.body_count, cells, src);
    section_hash = bytes_hash(section);
  }
  if (h.layout == kSideSnapshotVersion)
    s.side.assign(s.cells.begin() + std::ptrdiff_t(cells), s.cells.begin() + std::ptrdiff_t(cells + plane));
  if (h.layout == kFacesSnapshotVersion) {
    s.faces.resize(std::size_t(plane / 4));
    for (std::size_t i = 0; i < s.faces.size(); ++i)
      s.faces[i] = std::int32_t(get_u32(std::span<const std::uint8_t>(s.cells), std::size_t(cells) + 4 * i));
  }
  if (extra != 0) {
    s.cells.resize(std::size_t(cells));
    s.cells.shrink_to_fit();
  }
  const std::uint64_t found = file_hash(s, s.hash(), h.version, section_hash);
  if (found != h.hash) throw ParseError(src + ": " + snapshot_hash_problem(found, h.hash, h.version));
  return std::move(s);
}

/// Throws OutOfMemory when the cells the header `h` declares, and `extra` bytes besides, do not
/// fit in the memory budget.
void check_snapshot_memory(const SnapshotHeader& h, double extra, const std::string& src) {
  const Int3 size = h.meta.size;
  const std::uint64_t cells = std::uint64_t(size.x) * std::uint64_t(size.y) * std::uint64_t(size.z);
  // A snapshot with a side or face plane or bodies decodes the cells and the rest, then keeps them apart.
  const double rest = double(plane_bytes(h.layout, size)) + double(h.body_bytes);
  check_grid_size(size, src + ": header fields nx, ny, nz (" + to_string(size) + " = " + std::to_string(cells) + " cells)",
                  rest == 0 ? 1.0 : 2.0, extra + 2.0 * rest);
}

}  // namespace

WorldSnapshot decode_snapshot(std::span<const std::uint8_t> bytes, const std::string& src) {
  const SnapshotHeader h = parse_snapshot_header(bytes, bytes.size(), src);
  check_snapshot_memory(h, 0, src);
  return decode_body(h, bytes.subspan(h.body_at), src);
}

void save_snapshot(const WorldSnapshot& snapshot, const std::filesystem::path& path) {
  check_snapshot_save_path(path);
  const std::vector<std::uint8_t> bytes = encode_snapshot(snapshot);
  write_file_atomic(path, {std::span<const std::uint8_t>(bytes)});
}

SnapshotHeader read_snapshot_header(const ReadableFile& file) {
  std::vector<std::uint8_t> head(std::size_t(
      std::min<std::uint64_t>(file.size(), kSnapshotHeaderSize + kMaxSnapshotRulesName + kSnapshotBodyHeaderSize)));
  file.read_at(0, head);
  return parse_snapshot_header(head, file.size(), file.path().string());
}

WorldSnapshot load_snapshot(const std::filesystem::path& path) {
  const ReadableFile file(path);
  const std::string src = path.string();
  const SnapshotHeader h = read_snapshot_header(file);
  check_snapshot_memory(h, double(h.packed_size), src);
  std::vector<std::uint8_t> packed;
  try {
    packed.resize(std::size_t(h.packed_size));
  } catch (const std::exception&) {
    throw OutOfMemory(src + ": not enough memory to hold its " + std::to_string(h.packed_size) + " bytes of compressed cells");
  }
  file.read_at(h.body_at, packed);
  return decode_body(h, packed, src);
}

bool is_snapshot_file(const std::filesystem::path& path) { return lower_extension(path) == kSnapshotExtension; }

void check_snapshot_save_path(const std::filesystem::path& path) {
  if (!is_snapshot_file(path)) {
    const std::string ext = path.extension().string();
    throw InvalidArgument("cannot save snapshot " + quoted(path) + ": the file name " +
                          (ext.empty() ? std::string("has no extension") : "has the extension '" + ext + "'") +
                          "; a snapshot file's extension is " + kSnapshotExtension);
  }
  check_save_target(path);
}

}  // namespace granular
