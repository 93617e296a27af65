#include <algorithm>
#include <array>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstring>
#include <new>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "granular/rule_presets.hpp"
#include "io/file_names.hpp"
#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "granular/extend/memory_budget.hpp"
#include "io/expansion_bound.hpp"
#include "granular/vox_io.hpp"
#include "io/little_endian.hpp"

namespace granular {

namespace {

constexpr std::uint32_t kVoxWriteVersion = 150;
constexpr std::size_t kChunkHeaderSize = 12;
constexpr std::size_t kFileHeaderSize = 8;

/// `_r` of an unrotated node: row 0 has its 1 in column 0, row 1 in column 1, all signs positive.
constexpr int kIdentityRotation = 0 | (1 << 2);

/// Colour of palette index m (= material m) for m in 1..7: the presets' material table colours
/// (MaterialDef::colour, default_materials); index 0 is unused.
std::array<std::uint8_t, 4> material_colour(int m) {
  static const MaterialTable table = default_materials();
  const std::uint32_t c = table[std::size_t(m)].colour;
  return {std::uint8_t(c >> 16), std::uint8_t(c >> 8), std::uint8_t(c), 255};
}

/// Colour of the palette entries no material uses.
constexpr std::array<std::uint8_t, 4> kUnusedColour = {0x40, 0x40, 0x40, 255};

/// A string from the file for messages: at most 40 characters, non-printable bytes escaped.
std::string excerpt(std::string_view text) {
  constexpr std::size_t kMax = 40;
  const auto* b = reinterpret_cast<const std::uint8_t*>(text.data());
  std::string s = escaped_bytes(std::span<const std::uint8_t>(b, std::min(text.size(), kMax)), '\'');
  if (text.size() > kMax) s += "... (" + std::to_string(text.size()) + " bytes)";
  return s;
}

bool id_is(std::span<const std::uint8_t> b, std::size_t at, const char (&id)[5]) {
  return std::memcmp(b.data() + at, id, 4) == 0;
}

// ---------------------------------------------------------------------------------------------
// Writing

/// Appends little-endian values and chunks to a byte buffer.
class VoxWriter {
 public:
  void reserve(std::size_t n) { out_.reserve(n); }
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    out_.insert(out_.end(), b, b + n);
  }
  void u8(std::uint8_t v) { out_.push_back(v); }
  void i32(std::int32_t v) {
    const auto u = std::uint32_t(v);
    for (int i = 0; i < 4; ++i) out_.push_back(std::uint8_t(u >> (8 * i)));
  }
  void text(std::string_view s) {
    i32(std::int32_t(s.size()));
    bytes(s.data(), s.size());
  }
  /// Writes a chunk header with zero sizes and returns its position, for end_content/end_children.
  std::size_t begin(const char (&id)[5]) {
    const std::size_t at = out_.size();
    bytes(id, 4);
    i32(0);
    i32(0);
    return at;
  }
  /// Sets the content size of the chunk begun at `at` to everything written since its header.
  void end_content(std::size_t at) { patch(at + 4, out_.size() - at - kChunkHeaderSize); }
  /// Sets the children size of the chunk begun at `at` to everything written since its header.
  void end_children(std::size_t at) { patch(at + 8, out_.size() - at - kChunkHeaderSize); }
  /// Overwrites the int32 at `at` (a count written as a placeholder).
  void patch(std::size_t at, std::uint64_t v) {
    if (v > std::uint64_t(INT32_MAX))
      throw InvalidArgument("encode_vox: a chunk would hold " + std::to_string(v) +
                            " bytes, beyond the .vox limit of 2 GiB per chunk; save this grid as .raw instead");
    for (int i = 0; i < 4; ++i) out_[at + std::size_t(i)] = std::uint8_t(v >> (8 * i));
  }
  std::size_t size() const { return out_.size(); }
  std::vector<std::uint8_t> take() { return std::move(out_); }

 private:
  std::vector<std::uint8_t> out_;
};

/// One exported model: the cells [origin, origin + size) of the grid.
struct Tile {
  Int3 origin;
  Int3 size;
};

std::vector<Tile> split_into_tiles(Int3 n) {
  std::vector<Tile> tiles;
  for (int z = 0; z < n.z; z += kVoxMaxModelExtent)
    for (int y = 0; y < n.y; y += kVoxMaxModelExtent)
      for (int x = 0; x < n.x; x += kVoxMaxModelExtent)
        tiles.push_back({{x, y, z},
                         {std::min(kVoxMaxModelExtent, n.x - x), std::min(kVoxMaxModelExtent, n.y - y),
                          std::min(kVoxMaxModelExtent, n.z - z)}});
  return tiles;
}

void write_model(VoxWriter& w, const Grid& grid, const Tile& t) {
  const std::size_t size_chunk = w.begin("SIZE");
  w.i32(t.size.x);
  w.i32(t.size.y);
  w.i32(t.size.z);
  w.end_content(size_chunk);

  const std::size_t xyzi = w.begin("XYZI");
  const std::size_t count_at = w.size();
  w.i32(0);
  std::uint64_t count = 0;
  const auto cells = grid.cells();
  for (int z = 0; z < t.size.z; ++z)
    for (int y = 0; y < t.size.y; ++y) {
      const std::size_t row = grid.index({t.origin.x, t.origin.y + y, t.origin.z + z});
      for (int x = 0; x < t.size.x; ++x) {
        const std::uint8_t v = cells[row + std::size_t(x)];
        if (v == to_cell(Material::Void)) continue;
        w.u8(std::uint8_t(x));
        w.u8(std::uint8_t(y));
        w.u8(std::uint8_t(z));
        w.u8(v);
        ++count;
      }
    }
  w.patch(count_at, count);
  w.end_content(xyzi);
}

void write_palette(VoxWriter& w) {
  const std::size_t rgba = w.begin("RGBA");
  for (int entry = 0; entry < 256; ++entry) {
    const int index = entry + 1;  // entry k of the chunk is palette index k + 1
    const auto c = index < kMaterialCount ? material_colour(index) : kUnusedColour;
    w.bytes(c.data(), c.size());
  }
  w.end_content(rgba);
}

/// nTRN root (node 0) -> nGRP (node 1) -> per tile k: nTRN (node 2 + 2k, translation of the
/// tile's centre, layer 0) -> nSHP (node 3 + 2k, model k); then the LAYR chunk of layer 0. The
/// scene is centred on x and y, base at z = 0.
void write_scene_graph(VoxWriter& w, Int3 grid_size, const std::vector<Tile>& tiles) {
  const std::size_t root = w.begin("nTRN");
  w.i32(0);   // node id
  w.i32(0);   // attributes: empty dict
  w.i32(1);   // child node id
  w.i32(-1);  // reserved
  w.i32(-1);  // layer id
  w.i32(1);   // frames
  w.i32(0);   // frame 0 attributes: empty dict
  w.end_content(root);

  const std::size_t group = w.begin("nGRP");
  w.i32(1);
  w.i32(0);
  w.i32(std::int32_t(tiles.size()));
  for (std::size_t k = 0; k < tiles.size(); ++k) w.i32(std::int32_t(2 + 2 * k));
  w.end_content(group);

  for (std::size_t k = 0; k < tiles.size(); ++k) {
    const Tile& t = tiles[k];
    const std::string translation = std::to_string(t.origin.x + t.size.x / 2 - grid_size.x / 2) + " " +
                                    std::to_string(t.origin.y + t.size.y / 2 - grid_size.y / 2) + " " +
                                    std::to_string(t.origin.z + t.size.z / 2);
    const std::size_t trn = w.begin("nTRN");
    w.i32(std::int32_t(2 + 2 * k));
    w.i32(0);
    w.i32(std::int32_t(3 + 2 * k));
    w.i32(-1);
    w.i32(0);
    w.i32(1);
    w.i32(1);  // frame 0 attributes: one pair
    w.text("_t");
    w.text(translation);
    w.end_content(trn);

    const std::size_t shp = w.begin("nSHP");
    w.i32(std::int32_t(3 + 2 * k));
    w.i32(0);
    w.i32(1);  // models
    w.i32(std::int32_t(k));
    w.i32(0);  // model attributes: empty dict
    w.end_content(shp);
  }

  const std::size_t layer = w.begin("LAYR");
  w.i32(0);   // layer id, used by the per-tile nTRN nodes
  w.i32(0);   // attributes: empty dict
  w.i32(-1);  // reserved
  w.end_content(layer);
}

// ---------------------------------------------------------------------------------------------
// Reading

using Dict = std::vector<std::pair<std::string, std::string>>;

const std::string* find_key(const Dict& d, std::string_view key) {
  for (const auto& [k, v] : d)
    if (k == key) return &v;
  return nullptr;
}

/// Reads the fields of one chunk's content, with errors naming the chunk, field and offsets.
class ChunkReader {
 public:
  ChunkReader(std::span<const std::uint8_t> bytes, std::size_t begin, std::size_t end, const std::string& src,
              std::string chunk)
      : bytes_(bytes), at_(begin), end_(end), src_(src), chunk_(std::move(chunk)) {}

  std::int32_t i32(const char* field) {
    need(4, field);
    const std::uint32_t v = get_u32(bytes_, at_);
    at_ += 4;
    return std::int32_t(v);
  }
  /// A count or length: must be >= 0 and, at `min_bytes_each`, fit in what is left.
  std::size_t count(const char* field, std::size_t min_bytes_each) {
    const std::size_t field_at = at_;
    const std::int32_t n = i32(field);
    if (n < 0)
      fail(std::string(field) + " at offset " + std::to_string(field_at) + " is negative (" + std::to_string(n) + ")");
    if (min_bytes_each > 0 && std::size_t(n) > left() / min_bytes_each)
      fail(std::string(field) + " at offset " + std::to_string(field_at) + " is " + std::to_string(n) + ", needing " +
           std::to_string(std::uint64_t(n) * min_bytes_each) + " bytes, but only " + std::to_string(left()) +
           " bytes of the chunk are left (it ends at offset " + std::to_string(end_) + ")");
    return std::size_t(n);
  }
  std::string text(const char* field) {
    const std::size_t n = count(field, 1);
    std::string s(reinterpret_cast<const char*>(bytes_.data() + at_), n);
    at_ += n;
    return s;
  }
  Dict dict(const char* field) {
    const std::size_t n = count(field, 8);
    Dict d;
    d.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::string k = text("dictionary key length");
      std::string v = text("dictionary value length");
      d.emplace_back(std::move(k), std::move(v));
    }
    return d;
  }
  std::span<const std::uint8_t> take(std::size_t n, const char* field) {
    need(n, field);
    const auto s = bytes_.subspan(at_, n);
    at_ += n;
    return s;
  }
  std::size_t offset() const { return at_; }
  std::size_t left() const { return end_ - at_; }
  const std::string& chunk() const { return chunk_; }

  [[noreturn]] void fail(const std::string& what) const { throw ParseError(src_ + ": " + chunk_ + ": " + what); }

 private:
  void need(std::size_t n, const char* field) const {
    if (left() < n)
      throw ParseError(src_ + ": truncated " + chunk_ + ": field '" + field + "' needs " + std::to_string(n) +
                       " bytes at offset " + std::to_string(at_) + " but the chunk content ends at offset " +
                       std::to_string(end_));
  }

  std::span<const std::uint8_t> bytes_;
  std::size_t at_;
  std::size_t end_;
  const std::string& src_;
  std::string chunk_;
};

struct Model {
  Int3 size;
  std::size_t size_offset = 0;
  bool has_voxels = false;
  std::size_t xyzi_offset = 0;
  std::span<const std::uint8_t> voxels;  // 4 bytes per voxel: x, y, z, palette index
};

enum class NodeKind { Transform, Group, Shape };

struct Node {
  NodeKind kind = NodeKind::Group;
  std::size_t offset = 0;
  std::array<std::int64_t, 3> translation{};
  std::vector<std::int32_t> children;
  std::int32_t model = -1;  // shapes: the model of frame 0, -1 for none
};

/// Parses "x y z" (decimal int32 values separated by single spaces).
bool parse_translation(std::string_view s, std::array<std::int64_t, 3>& t) {
  const char* p = s.data();
  const char* end = s.data() + s.size();
  for (int a = 0; a < 3; ++a) {
    if (a > 0) {
      if (p == end || *p != ' ') return false;
      ++p;
    }
    std::int32_t v = 0;
    const auto r = std::from_chars(p, end, v);
    if (r.ec != std::errc()) return false;
    t[std::size_t(a)] = v;
    p = r.ptr;
  }
  return p == end;
}

Node read_transform(ChunkReader& r, std::int32_t& id) {
  Node n;
  n.kind = NodeKind::Transform;
  id = r.i32("node id");
  r.dict("node attribute count");
  n.children.push_back(r.i32("child node id"));
  r.i32("reserved id");
  r.i32("layer id");
  const std::size_t frames = r.count("frame count", 4);
  for (std::size_t f = 0; f < frames; ++f) {
    const Dict attrs = r.dict("frame attribute count");
    if (f != 0) continue;
    const std::string node = "nTRN node " + std::to_string(id);
    if (const std::string* rot = find_key(attrs, "_r")) {
      int v = -1;
      const auto res = std::from_chars(rot->data(), rot->data() + rot->size(), v);
      if (res.ec != std::errc() || res.ptr != rot->data() + rot->size())
        r.fail(node + ": rotation _r = \"" + excerpt(*rot) + "\" is not an integer");
      if (v != kIdentityRotation)
        r.fail(node + ": rotated models are not supported (_r = " + excerpt(*rot) +
               "; only the identity, _r = " + std::to_string(kIdentityRotation) + ", is)");
    }
    if (const std::string* t = find_key(attrs, "_t")) {
      if (!parse_translation(*t, n.translation))
        r.fail(node + ": translation _t = \"" + excerpt(*t) + "\" is not three integers \"x y z\"");
    }
  }
  return n;
}

Node read_group(ChunkReader& r, std::int32_t& id) {
  Node n;
  n.kind = NodeKind::Group;
  id = r.i32("node id");
  r.dict("node attribute count");
  const std::size_t count = r.count("child count", 4);
  for (std::size_t i = 0; i < count; ++i) n.children.push_back(r.i32("child node id"));
  return n;
}

Node read_shape(ChunkReader& r, std::int32_t& id) {
  Node n;
  n.kind = NodeKind::Shape;
  id = r.i32("node id");
  r.dict("node attribute count");
  const std::size_t count = r.count("model count", 8);
  for (std::size_t i = 0; i < count; ++i) {
    const std::int32_t model = r.i32("model id");
    r.dict("model attribute count");
    if (i == 0) n.model = model;
  }
  return n;
}

/// Everything decode_vox keeps from the chunks.
struct VoxContent {
  std::vector<Model> models;
  std::unordered_map<std::int32_t, Node> nodes;
};

void read_size(ChunkReader& r, VoxContent& c, std::size_t chunk_at) {
  if (!c.models.empty() && !c.models.back().has_voxels)
    r.fail("model " + std::to_string(c.models.size() - 1) + " (SIZE chunk at offset " +
           std::to_string(c.models.back().size_offset) + ") has no XYZI chunk before this next SIZE chunk");
  Model m;
  m.size_offset = chunk_at;
  m.size.x = r.i32("size x");
  m.size.y = r.i32("size y");
  m.size.z = r.i32("size z");
  const int e[3] = {m.size.x, m.size.y, m.size.z};
  for (int v : e)
    if (v < 1 || v > kVoxMaxModelExtent)
      r.fail("model " + std::to_string(c.models.size()) + " has the absurd size " + to_string(m.size) +
             "; each extent must be 1.." + std::to_string(kVoxMaxModelExtent));
  c.models.push_back(m);
}

void read_voxels(ChunkReader& r, VoxContent& c, std::size_t chunk_at) {
  if (c.models.empty() || c.models.back().has_voxels) r.fail("no SIZE chunk precedes this XYZI chunk");
  Model& m = c.models.back();
  const std::size_t n = r.count("voxel count", 4);
  const std::size_t first = r.offset();
  m.voxels = r.take(4 * n, "voxels");
  m.has_voxels = true;
  m.xyzi_offset = chunk_at;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* v = m.voxels.data() + 4 * i;
    if (v[0] >= m.size.x || v[1] >= m.size.y || v[2] >= m.size.z)
      r.fail("voxel #" + std::to_string(i) + " at offset " + std::to_string(first + 4 * i) + " lies at (" +
             std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) +
             "), outside its model's SIZE " + to_string(m.size) + " (model " + std::to_string(c.models.size() - 1) +
             ")");
  }
}

/// Reads the children of MAIN, [begin, end), into `c`.
void read_chunks(std::span<const std::uint8_t> bytes, std::size_t begin, std::size_t end, const std::string& src,
                 VoxContent& c) {
  std::size_t at = begin;
  while (at < end) {
    if (end - at < kChunkHeaderSize)
      throw ParseError(src + ": truncated chunk header at offset " + std::to_string(at) + ": only " +
                       std::to_string(end - at) + " bytes are left before the end of the MAIN chunk at offset " +
                       std::to_string(end) + ", a chunk header needs " + std::to_string(kChunkHeaderSize));
    std::string name(1, '\'');  // appended: GCC 12 warns falsely on "'" + string (-Wrestrict)
    name.append(escaped_bytes(bytes.subspan(at, 4), '\''));
    name.push_back('\'');
    const std::uint64_t content = get_u32(bytes, at + 4);
    const std::uint64_t children = get_u32(bytes, at + 8);
    const std::uint64_t room = end - at - kChunkHeaderSize;
    if (content > room || children > room - content)
      throw ParseError(src + ": chunk " + name + " at offset " + std::to_string(at) + " declares " +
                       std::to_string(content) + " content bytes and " + std::to_string(children) +
                       " children bytes, running past the end of the " +
                       (end == bytes.size() ? std::string("file") : std::string("MAIN chunk")) + " at offset " +
                       std::to_string(end) + " (only " + std::to_string(room) + " bytes are left)");
    const std::size_t content_at = at + kChunkHeaderSize;
    ChunkReader r(bytes, content_at, content_at + std::size_t(content), src,
                  "chunk " + name + " at offset " + std::to_string(at));
    std::int32_t id = 0;
    if (id_is(bytes, at, "SIZE")) {
      read_size(r, c, at);
    } else if (id_is(bytes, at, "XYZI")) {
      read_voxels(r, c, at);
    } else if (id_is(bytes, at, "nTRN") || id_is(bytes, at, "nGRP") || id_is(bytes, at, "nSHP")) {
      Node node = id_is(bytes, at, "nTRN")   ? read_transform(r, id)
                  : id_is(bytes, at, "nGRP") ? read_group(r, id)
                                             : read_shape(r, id);
      node.offset = at;
      if (const auto seen = c.nodes.find(id); seen != c.nodes.end())
        r.fail("scene graph node " + std::to_string(id) + " is defined twice (first by the chunk at offset " +
               std::to_string(seen->second.offset) + ")");
      c.nodes.emplace(id, std::move(node));
    }
    at = content_at + std::size_t(content + children);
  }
}

/// A model placed in world space: its minimum corner.
struct Instance {
  std::size_t model;
  std::array<std::int64_t, 3> min;
};

std::array<std::int64_t, 3> model_min_corner(const Model& m, const std::array<std::int64_t, 3>& t) {
  return {t[0] - m.size.x / 2, t[1] - m.size.y / 2, t[2] - m.size.z / 2};
}

/// Walks the scene graph from the root (node 0), summing translations down to each shape.
std::vector<Instance> place_by_scene_graph(const VoxContent& c, const std::string& src) {
  struct Visit {
    std::int32_t id;
    std::int32_t parent;
    std::array<std::int64_t, 3> t;
  };
  std::vector<Instance> out;
  std::vector<Visit> stack{{0, -1, {0, 0, 0}}};
  std::unordered_set<std::int32_t> visited;
  while (!stack.empty()) {
    const Visit v = stack.back();
    stack.pop_back();
    const auto it = c.nodes.find(v.id);
    if (it == c.nodes.end()) {
      if (v.parent < 0) throw ParseError(src + ": the scene graph has no root node 0");
      throw ParseError(src + ": scene graph node " + std::to_string(v.parent) + " refers to node " +
                       std::to_string(v.id) + ", which does not exist");
    }
    if (!visited.insert(v.id).second)
      throw ParseError(src + ": scene graph node " + std::to_string(v.id) + " is reached twice (again from node " +
                       std::to_string(v.parent) + "); the scene graph must be a tree");
    const Node& n = it->second;
    switch (n.kind) {
      case NodeKind::Transform: {
        auto t = v.t;
        for (int a = 0; a < 3; ++a) t[std::size_t(a)] += n.translation[std::size_t(a)];
        stack.push_back({n.children.front(), v.id, t});
        break;
      }
      case NodeKind::Group:
        for (auto child = n.children.rbegin(); child != n.children.rend(); ++child)
          stack.push_back({*child, v.id, v.t});
        break;
      case NodeKind::Shape:
        if (n.model < 0) break;
        if (std::size_t(n.model) >= c.models.size())
          throw ParseError(src + ": nSHP node " + std::to_string(v.id) + " (chunk at offset " +
                           std::to_string(n.offset) + ") refers to model " + std::to_string(n.model) +
                           " but the file has " + std::to_string(c.models.size()) + " models");
        out.push_back({std::size_t(n.model), model_min_corner(c.models[std::size_t(n.model)], v.t)});
        break;
    }
  }
  if (out.empty()) throw ParseError(src + ": the scene graph places no model (no nSHP node is reachable from node 0)");
  return out;
}

}  // namespace

std::vector<std::uint8_t> encode_vox(const Grid& grid) {
  const Int3 n = grid.size();
  if (grid.cell_count() == 0)
    throw InvalidArgument("encode_vox: the grid is empty (" + to_string(n) + "); there is nothing to encode");
  const std::vector<Tile> tiles = split_into_tiles(n);
  const std::uint64_t solid_cells = std::uint64_t(grid.cell_count()) - grid.count()[0];
  const std::uint64_t estimate = 4 * solid_cells + 256 * tiles.size() + 2048;
  if (estimate > std::uint64_t(INT32_MAX))
    throw InvalidArgument("encode_vox: the " + to_string(n) + " grid has " + std::to_string(solid_cells) +
                          " non-void cells, about " + std::to_string(estimate) +
                          " bytes of .vox chunks, beyond the format's 2 GiB limit; save it as .raw instead");
  VoxWriter w;
  try {
    w.reserve(std::size_t(estimate));
  } catch (const std::bad_alloc&) {
    throw OutOfMemory("encode_vox: could not allocate " + std::to_string(estimate) + " bytes for a " + to_string(n) +
                      " grid");
  }
  w.bytes("VOX ", 4);
  w.i32(std::int32_t(kVoxWriteVersion));
  const std::size_t main = w.begin("MAIN");
  for (const Tile& t : tiles) write_model(w, grid, t);
  if (tiles.size() > 1) write_scene_graph(w, n, tiles);
  write_palette(w);
  w.end_children(main);
  return w.take();
}

Grid decode_vox(std::span<const std::uint8_t> bytes, const std::string& source_name, VoxImportReport* report) {
  const std::string& src = source_name;
  const std::size_t magic_have = std::min<std::size_t>(bytes.size(), 4);
  if (bytes.empty() || std::memcmp(bytes.data(), "VOX ", magic_have) != 0)
    throw ParseError(src + ": not a MagicaVoxel file: bad magic '" + escaped_bytes(bytes.first(magic_have), '\'') +
                     "' at byte 0 (expected 'VOX ')");
  if (bytes.size() < kFileHeaderSize)
    throw ParseError(src + ": truncated header: the file has " + std::to_string(bytes.size()) +
                     " bytes and ends inside the version field (bytes 4..7)");
  const std::uint32_t version = get_u32(bytes, 4);
  if (version != 150 && version != 200)
    throw ParseError(src + ": unsupported .vox version " + std::to_string(version) +
                     " (bytes 4..7); supported versions are 150 and 200");
  if (bytes.size() < kFileHeaderSize + kChunkHeaderSize)
    throw ParseError(src + ": truncated chunk 'MAIN' at offset 8: its header needs 12 bytes but the file has only " +
                     std::to_string(bytes.size() - kFileHeaderSize) + " left");
  if (!id_is(bytes, kFileHeaderSize, "MAIN"))
    throw ParseError(src + ": expected chunk 'MAIN' at offset 8, found '" +
                     escaped_bytes(bytes.subspan(kFileHeaderSize, 4), '\'') + "'");
  const std::uint64_t main_content = get_u32(bytes, 12);
  const std::uint64_t main_children = get_u32(bytes, 16);
  const std::uint64_t room = bytes.size() - kFileHeaderSize - kChunkHeaderSize;
  if (main_content > room || main_children > room - main_content)
    throw ParseError(src + ": chunk 'MAIN' at offset 8 declares " + std::to_string(main_content) +
                     " content bytes and " + std::to_string(main_children) +
                     " children bytes, running past the end of the file (only " + std::to_string(room) +
                     " bytes follow its header)");
  const std::size_t children_at = kFileHeaderSize + kChunkHeaderSize + std::size_t(main_content);

  VoxContent c;
  read_chunks(bytes, children_at, children_at + std::size_t(main_children), src, c);
  if (c.models.empty()) throw ParseError(src + ": the file holds no model (no SIZE/XYZI chunk pair)");
  if (!c.models.back().has_voxels)
    throw ParseError(src + ": model " + std::to_string(c.models.size() - 1) + " (SIZE chunk at offset " +
                     std::to_string(c.models.back().size_offset) + ") has no XYZI chunk");

  std::vector<Instance> instances;
  if (c.nodes.empty()) {
    for (std::size_t m = 0; m < c.models.size(); ++m)
      instances.push_back({m, model_min_corner(c.models[m], {0, 0, 0})});
  } else {
    instances = place_by_scene_graph(c, src);
  }

  std::array<std::int64_t, 3> lo{INT64_MAX, INT64_MAX, INT64_MAX}, hi{INT64_MIN, INT64_MIN, INT64_MIN};
  for (const Instance& inst : instances) {
    const Int3 s = c.models[inst.model].size;
    const std::int64_t ext[3] = {s.x, s.y, s.z};
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], inst.min[a]);
      hi[a] = std::max(hi[a], inst.min[a] + ext[a]);
    }
  }
  static const char* kAxes[3] = {"x", "y", "z"};
  for (std::size_t a = 0; a < 3; ++a)
    if (hi[a] - lo[a] > kMaxGridExtent)
      throw ParseError(src + ": the models span " + std::to_string(hi[a] - lo[a]) + " cells along " + kAxes[a] +
                       " (world " + kAxes[a] + " from " + std::to_string(lo[a]) + " to " + std::to_string(hi[a]) +
                       "); at most " + std::to_string(kMaxGridExtent) + " are supported");
  const Int3 size{int(hi[0] - lo[0]), int(hi[1] - lo[1]), int(hi[2] - lo[2])};
  try {
    check_grid_extents(size, src + ": bounding box of all models");  // the memory below
  } catch (const InvalidArgument& e) {
    throw ParseError(e.what());
  }
  std::int64_t model_cells = 0;
  for (const Instance& inst : instances) {
    const Int3 s = c.models[inst.model].size;
    model_cells += std::int64_t(s.x) * s.y * s.z;  // each <= 2^24; at most 2^31 instances
  }
  const std::int64_t grid_cells = std::int64_t(size.x) * size.y * size.z;
  if (exceeds_expansion(std::uint64_t(grid_cells), std::uint64_t(model_cells), kVoxMaxSpread, kVoxSparseGridCells))
    throw ParseError(src + ": the " + std::to_string(instances.size()) + " placed models (" +
                     std::to_string(model_cells) + " cells of SIZE in all) span a " + to_string(size) +
                     " bounding box of " + std::to_string(grid_cells) + " cells (" + format_bytes(double(grid_cells)) +
                     "), more than " + std::to_string(kVoxMaxSpread) + " times their volume and more than " +
                     std::to_string(kVoxSparseGridCells) +
                     " cells: a grid this sparse is refused (is a model translated far away?)");
  std::int64_t placed_voxels = 0;
  for (const Instance& inst : instances) placed_voxels += std::int64_t(c.models[inst.model].voxels.size() / 4);
  if (placed_voxels > kVoxMaxOverlap * grid_cells)
    throw ParseError(src + ": the " + std::to_string(instances.size()) + " placed models hold " +
                     std::to_string(placed_voxels) + " voxels for a grid of " + std::to_string(grid_cells) +
                     " cells, more than " + std::to_string(kVoxMaxOverlap) +
                     " per cell: models placed on top of each other this often are refused");
  check_grid_size(size, src + ": bounding box of all models");

  Grid grid(size);
  VoxImportReport rep;
  std::array<bool, 256> unmapped_seen{};
  auto cells = grid.cells();
  for (const Instance& inst : instances) {
    const Model& m = c.models[inst.model];
    const Int3 o{int(inst.min[0] - lo[0]), int(inst.min[1] - lo[1]), int(inst.min[2] - lo[2])};
    for (std::size_t i = 0; i + 4 <= m.voxels.size(); i += 4) {
      const std::uint8_t* v = m.voxels.data() + i;
      const std::uint8_t index = v[3];
      Material mat = Material::Solid;
      if (index >= 1 && index < kMaterialCount) {
        mat = Material(index);
      } else {
        ++rep.unmapped_voxels;
        unmapped_seen[index] = true;
      }
      cells[grid.index({o.x + v[0], o.y + v[1], o.z + v[2]})] = to_cell(mat);
      ++rep.voxels;
    }
  }
  rep.models = int(instances.size());
  for (int i = 0; i < 256; ++i)
    if (unmapped_seen[std::size_t(i)]) rep.unmapped_indices.push_back(i);
  if (report) *report = std::move(rep);
  return grid;
}

std::string vox_import_notice(const VoxImportReport& report, const std::string& source_name) {
  if (report.unmapped_voxels == 0) return {};
  std::string indices;
  for (std::size_t i = 0; i < report.unmapped_indices.size(); ++i) {
    if (i == 8) {
      indices += ", ...";
      break;
    }
    indices += (i ? ", " : "") + std::to_string(report.unmapped_indices[i]);
  }
  return source_name + ": " + std::to_string(report.unmapped_voxels) + " of " + std::to_string(report.voxels) +
         " voxels have palette indices that are not materials (" + indices +
         ") and were imported as solid; materials are palette indices 1..7 (docs/FORMATS.md)";
}

Grid load_vox(const std::filesystem::path& path, VoxImportReport* report) {
  return decode_vox(read_file_bytes(path), path.string(), report);
}

void save_vox(const Grid& grid, const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = encode_vox(grid);
  write_file_atomic(path, {std::span<const std::uint8_t>(bytes)});
}

}  // namespace granular
