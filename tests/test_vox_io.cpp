#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular/grid_io.hpp"
#include "granular/vox_io.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace granular;

using granular::test::check_has;
using granular::test::error_of;

namespace {

using Bytes = std::vector<std::uint8_t>;
using Voxel = std::array<std::uint8_t, 4>;
using Pairs = std::vector<std::pair<std::string, std::string>>;

/// A fresh directory under the system temp dir, removed with everything in it at scope exit.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ =
        fs::temp_directory_path() / ("granular_vox_io_" + std::to_string(getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  fs::path operator/(const std::string& name) const { return path_ / name; }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// --- building .vox files by hand ---------------------------------------------------------------

void i32(Bytes& b, std::int32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(std::uint8_t(std::uint32_t(v) >> (8 * i)));
}

void text(Bytes& b, std::string_view s) {
  i32(b, std::int32_t(s.size()));
  b.insert(b.end(), s.begin(), s.end());
}

void dict(Bytes& b, const Pairs& d) {
  i32(b, std::int32_t(d.size()));
  for (const auto& [k, v] : d) {
    text(b, k);
    text(b, v);
  }
}

Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const Bytes& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

Bytes chunk(const char (&id)[5], const Bytes& content, const Bytes& children = {}) {
  Bytes b(id, id + 4);
  i32(b, std::int32_t(content.size()));
  i32(b, std::int32_t(children.size()));
  return cat({b, content, children});
}

Bytes vox_file(const Bytes& main_children, std::int32_t version = 150) {
  Bytes b = {'V', 'O', 'X', ' '};
  i32(b, version);
  return cat({b, chunk("MAIN", {}, main_children)});
}

Bytes size_chunk(int x, int y, int z) {
  Bytes c;
  i32(c, x);
  i32(c, y);
  i32(c, z);
  return chunk("SIZE", c);
}

Bytes xyzi_chunk(const std::vector<Voxel>& voxels) {
  Bytes c;
  i32(c, std::int32_t(voxels.size()));
  for (const Voxel& v : voxels) c.insert(c.end(), v.begin(), v.end());
  return chunk("XYZI", c);
}

Bytes ntrn(int id, int child, const Pairs& frame) {
  Bytes c;
  i32(c, id);
  dict(c, {});
  i32(c, child);
  i32(c, -1);
  i32(c, -1);
  i32(c, 1);
  dict(c, frame);
  return chunk("nTRN", c);
}

Bytes ngrp(int id, const std::vector<int>& children) {
  Bytes c;
  i32(c, id);
  dict(c, {});
  i32(c, std::int32_t(children.size()));
  for (int ch : children) i32(c, ch);
  return chunk("nGRP", c);
}

Bytes nshp(int id, int model) {
  Bytes c;
  i32(c, id);
  dict(c, {});
  i32(c, 1);
  i32(c, model);
  dict(c, {});
  return chunk("nSHP", c);
}

void set_u32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + std::size_t(i)] = std::uint8_t(v >> (8 * i));
}

std::uint32_t get_u32(const Bytes& b, std::size_t at) {
  return std::uint32_t(b[at]) | (std::uint32_t(b[at + 1]) << 8) | (std::uint32_t(b[at + 2]) << 16) |
         (std::uint32_t(b[at + 3]) << 24);
}

std::size_t occurrences(const Bytes& b, std::string_view s) {
  std::size_t n = 0;
  for (auto it = b.begin(); (it = std::search(it, b.end(), s.begin(), s.end())) != b.end(); ++it) ++n;
  return n;
}

// --- assertions --------------------------------------------------------------------------------

Grid random_grid(Int3 size, unsigned seed, int void_percent = 30) {
  Grid g(size);
  std::mt19937 rng(seed);
  for (auto& c : g.cells()) c = int(rng() % 100) < void_percent ? 0 : std::uint8_t(1 + rng() % (kMaterialCount - 1));
  return g;
}

bool same_cells(const Grid& a, const Grid& b) {
  return a.size() == b.size() && std::equal(a.cells().begin(), a.cells().end(), b.cells().begin(), b.cells().end());
}

std::int64_t non_void(const Grid& g) { return g.cell_count() - std::int64_t(g.count()[0]); }


/// Checks that `bytes` fail with a ParseError naming the source and `parts`, in memory and from a file.
void check_vox_rejected(const Bytes& bytes, std::initializer_list<std::string_view> parts) {
  const std::string mem = error_of<ParseError>([&] { decode_vox(bytes, "memory-model.vox"); });
  check_has(mem, {"memory-model.vox"});
  check_has(mem, parts);
  TempDir dir;
  const fs::path p = dir / "bad_model.vox";
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  const std::string file = error_of<ParseError>([&] { load_vox(p); });
  check_has(file, {p.string()});
  check_has(file, parts);
}

/// A 3x3x3 model with voxels at (0,0,0) and (2,2,2): SIZE at offset 20, XYZI at 44, ends at 68.
const Bytes kOneModelChildren = cat({size_chunk(3, 3, 3), xyzi_chunk({{0, 0, 0, 1}, {2, 2, 2, 2}})});

}  // namespace

TEST_CASE("vox: a small grid is one SIZE/XYZI model plus the material palette") {
  Grid g({7, 5, 3});
  g.set({0, 0, 0}, Material::Solid);
  g.set({2, 3, 1}, Material::Granular);
  g.set({6, 4, 2}, Material::Liquid);
  const Bytes b = encode_vox(g);
  REQUIRE(b.size() == 8 + 12 + 24 + 28 + 12 + 1024);
  CHECK(std::string(b.begin(), b.begin() + 4) == "VOX ");
  CHECK(get_u32(b, 4) == 150);
  CHECK(std::string(b.begin() + 8, b.begin() + 12) == "MAIN");
  CHECK(get_u32(b, 12) == 0);
  CHECK(get_u32(b, 16) == b.size() - 20);
  CHECK(std::string(b.begin() + 20, b.begin() + 24) == "SIZE");
  CHECK((std::array{get_u32(b, 32), get_u32(b, 36), get_u32(b, 40)} == std::array<std::uint32_t, 3>{7, 5, 3}));
  CHECK(std::string(b.begin() + 44, b.begin() + 48) == "XYZI");
  CHECK(get_u32(b, 48) == 16);
  CHECK(get_u32(b, 56) == 3);
  CHECK(Bytes(b.begin() + 60, b.begin() + 72) == Bytes{0, 0, 0, 1, 2, 3, 1, 2, 6, 4, 2, 3});
  CHECK(std::string(b.begin() + 72, b.begin() + 76) == "RGBA");
  CHECK(get_u32(b, 76) == 1024);
  const std::size_t palette = 84;  // entry k = palette index k + 1
  // The presets' material colours (MaterialDef::colour): solid, sand, water, ..., gravel.
  CHECK(Bytes(b.begin() + palette, b.begin() + palette + 4) == Bytes{0x8C, 0x8C, 0x94, 0xFF});
  CHECK(Bytes(b.begin() + palette + 4, b.begin() + palette + 8) == Bytes{0xD9, 0xB8, 0x73, 0xFF});
  CHECK(Bytes(b.begin() + palette + 8, b.begin() + palette + 12) == Bytes{0x2E, 0x6F, 0xD9, 0xFF});
  CHECK(Bytes(b.begin() + palette + 16, b.begin() + palette + 20) == Bytes{0x6E, 0x6A, 0x64, 0xFF});
  CHECK(occurrences(b, "nTRN") == 0);
}

TEST_CASE("vox: grids of at most 256 per axis round-trip") {
  const Int3 sizes[] = {{1, 1, 1}, {7, 5, 3}, {16, 9, 31}, {256, 2, 3}};
  unsigned seed = 11;
  for (Int3 s : sizes) {
    CAPTURE(to_string(s));
    const Grid g = random_grid(s, seed++);
    VoxImportReport report;
    const Grid back = decode_vox(encode_vox(g), "mem.vox", &report);
    CHECK(same_cells(back, g));
    CHECK(report.models == 1);
    CHECK(report.voxels == non_void(g));
    CHECK(report.unmapped_voxels == 0);
  }
}

TEST_CASE("vox: an all-void grid keeps its size") {
  const Grid g({4, 6, 5});
  VoxImportReport report;
  const Grid back = decode_vox(encode_vox(g), "void.vox", &report);
  CHECK(back.size() == Int3{4, 6, 5});
  CHECK(non_void(back) == 0);
  CHECK(report.voxels == 0);
}

TEST_CASE("vox: a grid longer than 256 is split into models assembled by the scene graph") {
  const Grid g = random_grid({300, 4, 3}, 21);
  const Bytes b = encode_vox(g);
  CHECK(occurrences(b, "SIZE") == 2);
  CHECK(occurrences(b, "XYZI") == 2);
  CHECK(occurrences(b, "nTRN") == 3);
  CHECK(occurrences(b, "nGRP") == 1);
  CHECK(occurrences(b, "nSHP") == 2);
  CHECK(occurrences(b, "LAYR") == 1);
  // Centre translations: tile 0 is x 0..255 (centre 128), tile 1 is x 256..299 (centre 256 + 22);
  // the scene is centred on x (- 150) and y (- 2), base at z = 0.
  CHECK(occurrences(b, "-22 0 1") == 1);
  CHECK(occurrences(b, "128 0 1") == 1);
  VoxImportReport report;
  const Grid back = decode_vox(b, "long.vox", &report);
  CHECK(same_cells(back, g));
  CHECK(report.models == 2);
  CHECK(report.voxels == non_void(g));
  CHECK(report.unmapped_voxels == 0);
}

TEST_CASE("vox: a grid over 256 on two axes round-trips through files") {
  Grid g({260, 3, 258});
  for (int z : {0, 1, 255, 256, 257})
    for (int x : {0, 1, 255, 256, 259}) g.set({x, z % 3, z}, Material(1 + (x + z) % 7));
  g.fill({{100, 0, 100}, {160, 3, 130}}, Material::Granular);
  TempDir dir;
  const fs::path p = dir / "big.vox";
  save_vox(g, p);
  VoxImportReport report;
  const Grid back = load_vox(p, &report);
  CHECK(same_cells(back, g));
  CHECK(report.models == 4);
  CHECK(report.voxels == non_void(g));
}

TEST_CASE("vox: palette indices 1..7 map to materials, others to Solid and are counted") {
  const Bytes b = vox_file(cat({size_chunk(10, 1, 1), xyzi_chunk({{0, 0, 0, 1},
                                                                  {1, 0, 0, 2},
                                                                  {2, 0, 0, 3},
                                                                  {3, 0, 0, 4},
                                                                  {4, 0, 0, 5},
                                                                  {5, 0, 0, 6},
                                                                  {6, 0, 0, 7},
                                                                  {7, 0, 0, 8},
                                                                  {8, 0, 0, 255},
                                                                  {9, 0, 0, 0}})}));
  VoxImportReport report;
  const Grid g = decode_vox(b, "palette.vox", &report);
  REQUIRE(g.size() == Int3{10, 1, 1});
  for (int i = 0; i < 7; ++i) CHECK(g.at({i, 0, 0}) == Material(i + 1));
  for (int i = 7; i < 10; ++i) CHECK(g.at({i, 0, 0}) == Material::Solid);
  CHECK(report.voxels == 10);
  CHECK(report.unmapped_voxels == 3);
  CHECK(report.unmapped_indices == std::vector<int>{0, 8, 255});
  CHECK(report.models == 1);
  check_has(vox_import_notice(report, "palette.vox"),
            {"palette.vox: 3 of 10 voxels", "(0, 8, 255)", "imported as solid", "1..7"});
  CHECK(vox_import_notice(VoxImportReport{}, "clean.vox").empty());
}

TEST_CASE("vox: nested translations are summed and the bounding box is shifted to 0") {
  const Bytes b = vox_file(cat({
      size_chunk(2, 2, 2),
      xyzi_chunk({{0, 0, 0, 2}, {1, 1, 1, 2}}),  // model 0
      size_chunk(3, 1, 1),
      xyzi_chunk({{2, 0, 0, 3}}),  // model 1
      ntrn(0, 1, {{"_t", "100 100 100"}}),
      ngrp(1, {2, 4}),
      ntrn(2, 3, {{"_t", "10 0 0"}, {"_r", "4"}}),
      nshp(3, 0),
      ntrn(4, 5, {{"_t", "1 1 1"}}),
      ngrp(5, {6}),
      ntrn(6, 7, {{"_t", "-6 3 6"}}),
      nshp(7, 1),
  }));
  // model 0: centre (110,100,100), min corner - (1,1,1) = (109,99,99)
  // model 1: centre (95,104,107), min corner - (1,0,0) = (94,104,107); box [94..111) x [99..105) x [99..108)
  VoxImportReport report;
  const Grid g = decode_vox(b, "scene.vox", &report);
  REQUIRE(g.size() == Int3{17, 6, 9});
  CHECK(g.at({15, 0, 0}) == Material::Granular);
  CHECK(g.at({16, 1, 1}) == Material::Granular);
  CHECK(g.at({2, 5, 8}) == Material::Liquid);
  CHECK(non_void(g) == 3);
  CHECK(report.models == 2);
  CHECK(report.voxels == 3);
}

TEST_CASE("vox: models without a scene graph are centred on the origin") {
  const Bytes b =
      vox_file(cat({size_chunk(2, 2, 2), xyzi_chunk({{0, 0, 0, 1}}), size_chunk(4, 4, 4), xyzi_chunk({{3, 3, 3, 2}})}));
  VoxImportReport report;
  const Grid g = decode_vox(b, "two.vox", &report);
  REQUIRE(g.size() == Int3{4, 4, 4});
  CHECK(g.at({1, 1, 1}) == Material::Solid);
  CHECK(g.at({3, 3, 3}) == Material::Granular);
  CHECK(report.models == 2);
}

TEST_CASE("vox: unknown chunks, MAIN content and version 200 are accepted") {
  Bytes unknown_content(5, 0xEE);
  const Bytes children = cat({chunk("ZZZZ", unknown_content, chunk("YYYY", {1, 2, 3})), chunk("PACK", {1, 0, 0, 0}),
                              kOneModelChildren, chunk("MATL", Bytes(7, 1))});
  Bytes b = {'V', 'O', 'X', ' '};
  i32(b, 200);
  Bytes main_content = {9, 9, 9};
  b = cat({b, chunk("MAIN", main_content, children)});
  const Grid g = decode_vox(b, "extra.vox");
  REQUIRE(g.size() == Int3{3, 3, 3});
  CHECK(g.at({0, 0, 0}) == Material::Solid);
  CHECK(g.at({2, 2, 2}) == Material::Granular);
  CHECK(non_void(g) == 2);
}

TEST_CASE("vox: malformed headers and chunk framing are rejected") {
  const Bytes valid = vox_file(kOneModelChildren);
  REQUIRE_NOTHROW(decode_vox(valid, "ok.vox"));

  SUBCASE("bad magic") {
    Bytes b = valid;
    b[3] = 'X';
    check_vox_rejected(b, {"bad magic 'VOXX'", "expected 'VOX '"});
  }
  SUBCASE("a raw grid file") { check_vox_rejected(encode_raw(Grid({2, 2, 2})), {"not a MagicaVoxel file", "'GRAW'"}); }
  SUBCASE("empty file") { check_vox_rejected({}, {"bad magic ''"}); }
  SUBCASE("unsupported version") {
    Bytes b = valid;
    set_u32(b, 4, 999);
    check_vox_rejected(b, {"unsupported .vox version 999", "150 and 200"});
  }
  SUBCASE("truncated file header") {
    check_vox_rejected({'V', 'O', 'X', ' ', 150, 0}, {"truncated header", "6 bytes"});
  }
  SUBCASE("truncated MAIN header") {
    check_vox_rejected(Bytes(valid.begin(), valid.begin() + 15), {"truncated chunk 'MAIN' at offset 8"});
  }
  SUBCASE("first chunk is not MAIN") {
    Bytes b = valid;
    std::memcpy(b.data() + 8, "SIZE", 4);
    check_vox_rejected(b, {"expected chunk 'MAIN' at offset 8, found 'SIZE'"});
  }
  SUBCASE("MAIN runs past the end of the file") {
    Bytes b = valid;
    set_u32(b, 16, get_u32(b, 16) + 100);
    check_vox_rejected(b, {"chunk 'MAIN' at offset 8", "running past the end of the file"});
  }
  SUBCASE("a chunk runs past the end of the file") {
    Bytes b = valid;
    set_u32(b, 48, 1000);
    check_vox_rejected(b,
                       {"chunk 'XYZI' at offset 44 declares 1000 content bytes", "running past the end of the file"});
  }
  SUBCASE("a chunk with a huge declared size") {
    Bytes b = valid;
    set_u32(b, 24, 0xFFFFFFF0u);
    check_vox_rejected(b, {"chunk 'SIZE' at offset 20 declares 4294967280 content bytes"});
  }
  SUBCASE("truncated chunk header") {
    const Bytes b = vox_file(cat({kOneModelChildren, Bytes{'R', 'G', 'B', 'A', 0}}));
    check_vox_rejected(b, {"truncated chunk header at offset 68", "only 5 bytes"});
  }
}

TEST_CASE("vox: malformed models are rejected") {
  SUBCASE("truncated SIZE content") {
    const Bytes b = vox_file(cat({chunk("SIZE", Bytes(8, 1)), xyzi_chunk({})}));
    check_vox_rejected(b, {"truncated chunk 'SIZE' at offset 20", "field 'size z'", "offset 40"});
  }
  SUBCASE("XYZI voxel count beyond its content") {
    Bytes xyzi;
    i32(xyzi, 5);
    xyzi.insert(xyzi.end(), {0, 0, 0, 1, 1, 1, 1, 1});
    const Bytes b = vox_file(cat({size_chunk(3, 3, 3), chunk("XYZI", xyzi)}));
    check_vox_rejected(b, {"chunk 'XYZI' at offset 44", "voxel count at offset 56 is 5", "only 8 bytes"});
  }
  SUBCASE("negative voxel count") {
    Bytes xyzi;
    i32(xyzi, -1);
    const Bytes b = vox_file(cat({size_chunk(3, 3, 3), chunk("XYZI", xyzi)}));
    check_vox_rejected(b, {"chunk 'XYZI' at offset 44", "voxel count", "negative (-1)"});
  }
  SUBCASE("voxel outside its SIZE") {
    const Bytes b = vox_file(cat({size_chunk(3, 3, 3), xyzi_chunk({{0, 0, 0, 1}, {3, 0, 0, 1}})}));
    check_vox_rejected(
        b, {"chunk 'XYZI' at offset 44", "voxel #1 at offset 64", "(3, 0, 0)", "outside its model's SIZE 3x3x3"});
  }
  SUBCASE("no model") { check_vox_rejected(vox_file(chunk("RGBA", Bytes(1024, 0))), {"no model", "SIZE/XYZI"}); }
  SUBCASE("SIZE without XYZI at the end") {
    check_vox_rejected(vox_file(size_chunk(2, 2, 2)), {"model 0 (SIZE chunk at offset 20) has no XYZI chunk"});
  }
  SUBCASE("SIZE followed by another SIZE") {
    const Bytes b = vox_file(cat({size_chunk(2, 2, 2), size_chunk(2, 2, 2), xyzi_chunk({})}));
    check_vox_rejected(b, {"chunk 'SIZE' at offset 44", "model 0 (SIZE chunk at offset 20) has no XYZI chunk"});
  }
  SUBCASE("XYZI without SIZE") {
    check_vox_rejected(vox_file(xyzi_chunk({{0, 0, 0, 1}})), {"chunk 'XYZI' at offset 20", "no SIZE chunk precedes"});
  }
  SUBCASE("zero size") {
    check_vox_rejected(vox_file(cat({size_chunk(0, 3, 3), xyzi_chunk({})})), {"absurd size 0x3x3", "1..256"});
  }
  SUBCASE("size above 256") {
    check_vox_rejected(vox_file(cat({size_chunk(257, 1, 1), xyzi_chunk({})})), {"absurd size 257x1x1", "1..256"});
  }
  SUBCASE("negative size") {
    check_vox_rejected(vox_file(cat({size_chunk(4, -5, 1), xyzi_chunk({})})), {"absurd size 4x-5x1"});
  }
  SUBCASE("models spread over more than the maximum grid extent") {
    const Bytes b =
        vox_file(cat({size_chunk(1, 1, 1), xyzi_chunk({}), size_chunk(1, 1, 1), xyzi_chunk({}), ntrn(0, 1, {}),
                      ngrp(1, {2, 4}), ntrn(2, 3, {}), nshp(3, 0), ntrn(4, 5, {{"_t", "70000 0 0"}}), nshp(5, 1)}));
    check_vox_rejected(b, {"span 70001 cells along x", "at most 65536"});
  }
}

TEST_CASE("vox: malformed scene graphs are rejected naming the node") {
  const Bytes model = cat({size_chunk(2, 2, 2), xyzi_chunk({{0, 0, 0, 1}})});

  SUBCASE("rotated model") {
    const Bytes b = vox_file(cat({model, ntrn(0, 1, {}), ngrp(1, {2}), ntrn(2, 3, {{"_r", "20"}}), nshp(3, 0)}));
    check_vox_rejected(b, {"rotated models are not supported", "nTRN node 2", "_r = 20"});
  }
  SUBCASE("rotation that is not a number") {
    const Bytes b = vox_file(cat({model, ntrn(0, 1, {{"_r", "4x"}}), nshp(1, 0)}));
    check_vox_rejected(b, {"nTRN node 0", "_r = \"4x\" is not an integer"});
  }
  SUBCASE("translation that is not three integers") {
    const Bytes b = vox_file(cat({model, ntrn(0, 1, {}), ngrp(1, {2}), ntrn(2, 3, {{"_t", "1 2"}}), nshp(3, 0)}));
    check_vox_rejected(b, {"nTRN node 2", "translation _t = \"1 2\""});
  }
  SUBCASE("reference to a missing node") {
    const Bytes b = vox_file(cat({model, ntrn(0, 1, {}), ngrp(1, {9})}));
    check_vox_rejected(b, {"node 1 refers to node 9, which does not exist"});
  }
  SUBCASE("cycle") {
    const Bytes b = vox_file(cat({model, ntrn(0, 1, {}), ngrp(1, {2}), ntrn(2, 1, {})}));
    check_vox_rejected(b, {"node 1 is reached twice (again from node 2)", "must be a tree"});
  }
  SUBCASE("no root node") {
    const Bytes b = vox_file(cat({model, ntrn(1, 2, {}), nshp(2, 0)}));
    check_vox_rejected(b, {"no root node 0"});
  }
  SUBCASE("shape referring to a missing model") {
    const Bytes b = vox_file(cat({model, ntrn(0, 3, {}), nshp(3, 5)}));
    check_vox_rejected(b, {"nSHP node 3", "refers to model 5", "has 1 models"});
  }
  SUBCASE("duplicate node id") {
    const Bytes b = vox_file(cat({model, ntrn(0, 3, {}), nshp(3, 0), nshp(3, 0)}));
    check_vox_rejected(b, {"node 3 is defined twice"});
  }
  SUBCASE("negative dictionary size") {
    Bytes c;
    i32(c, 0);
    i32(c, -7);
    const Bytes b = vox_file(cat({model, chunk("nTRN", c)}));
    check_vox_rejected(b, {"chunk 'nTRN'", "node attribute count at offset", "negative (-7)"});
  }
  SUBCASE("truncated node chunk") {
    Bytes c;
    i32(c, 0);
    dict(c, {});
    const Bytes b = vox_file(cat({model, chunk("nTRN", c)}));
    check_vox_rejected(b, {"truncated chunk 'nTRN' at offset 64", "field 'child node id'", "offset 84"});
  }
  SUBCASE("string running past its chunk") {
    Bytes c;
    i32(c, 0);
    i32(c, 1);
    i32(c, 1000);
    i32(c, 0);
    const Bytes b = vox_file(cat({model, chunk("nTRN", c)}));
    check_vox_rejected(b, {"chunk 'nTRN' at offset 64", "dictionary key length at offset 84 is 1000", "only 4 bytes"});
  }
  SUBCASE("graph placing no model") {
    const Bytes b = vox_file(cat({model, ntrn(0, 1, {}), ngrp(1, {})}));
    check_vox_rejected(b, {"places no model"});
  }
}

TEST_CASE("vox: truncated and corrupted files raise ParseError, never crash") {
  const Bytes scene = vox_file(cat({
      size_chunk(2, 2, 2),
      xyzi_chunk({{0, 0, 0, 2}, {1, 1, 1, 9}}),
      size_chunk(3, 1, 1),
      xyzi_chunk({{2, 0, 0, 3}}),
      ntrn(0, 1, {{"_t", "5 5 5"}}),
      ngrp(1, {2, 4}),
      ntrn(2, 3, {{"_t", "10 0 0"}}),
      nshp(3, 0),
      ntrn(4, 5, {{"_t", "-6 3 6"}, {"_r", "4"}}),
      nshp(5, 1),
      chunk("RGBA", Bytes(1024, 7)),
  }));
  const Bytes tiled = encode_vox(random_grid({270, 2, 2}, 5));
  for (const Bytes* original : {&scene, &tiled}) {
    REQUIRE_NOTHROW(decode_vox(*original, "fuzz.vox"));
    int parse_errors = 0;
    for (std::size_t n = 0; n < original->size(); ++n) {
      try {
        decode_vox(std::span<const std::uint8_t>(original->data(), n), "fuzz.vox");
      } catch (const ParseError& e) {
        ++parse_errors;
        CHECK(std::string(e.what()).rfind("fuzz.vox: ", 0) == 0);
      }
    }
    // every strict prefix cuts MAIN's declared children short
    CHECK(parse_errors == int(original->size()));
    std::mt19937 rng(1234);
    for (int round = 0; round < 3000; ++round) {
      Bytes b = *original;
      const int flips = 1 + int(rng() % 4);
      for (int f = 0; f < flips; ++f) b[rng() % b.size()] = std::uint8_t(rng());
      try {
        decode_vox(b, "fuzz.vox");
      } catch (const ParseError&) {
      }
    }
  }
}

TEST_CASE("vox: file errors") {
  TempDir dir;
  SUBCASE("missing file") {
    const fs::path p = dir / "missing.vox";
    check_has(error_of<FileError>([&] { load_vox(p); }), {p.string(), std::strerror(ENOENT)});
  }
  SUBCASE("failed save keeps the existing target") {
    const fs::path target = dir / "taken.vox";
    fs::create_directory(target);
    const std::string m = error_of<FileError>([&] { save_vox(random_grid({3, 3, 3}, 2), target); });
    check_has(m, {target.string()});
    CHECK(fs::is_directory(target));
    CHECK(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()) == 1);
  }
  SUBCASE("save into a missing directory") {
    const fs::path p = dir / "nowhere" / "x.vox";
    check_has(error_of<FileError>([&] { save_vox(Grid({1, 1, 1}), p); }), {p.string(), std::strerror(ENOENT)});
  }
  SUBCASE("empty grid") {
    check_has(error_of<InvalidArgument>([&] { encode_vox(Grid()); }), {"encode_vox", "empty"});
  }
}

TEST_CASE("vox: a small file whose scene graph places a model far away is refused, not a 2004^3 grid") {
  // Two 4x4x4 models, the second translated by 2000 on every axis: 320 bytes, a 2004^3 (7.5 GiB) box.
  const Bytes b = vox_file(cat({
      size_chunk(4, 4, 4), xyzi_chunk({{0, 0, 0, 1}}), size_chunk(4, 4, 4), xyzi_chunk({{0, 0, 0, 2}}),
      ntrn(0, 1, {}), ngrp(1, {2, 4}), ntrn(2, 3, {}), nshp(3, 0), ntrn(4, 5, {{"_t", "2000 2000 2000"}}), nshp(5, 1),
  }));
  CHECK(b.size() < 400);
  check_vox_rejected(b, {"2 placed models", "128 cells of SIZE", "2004x2004x2004", "8048096064 cells",
                         "more than 64 times their volume", "sparse"});
  // The same two models 100 cells apart (a 104^3 box, under 256^3 cells) are accepted.
  const Bytes near = vox_file(cat({
      size_chunk(4, 4, 4), xyzi_chunk({{0, 0, 0, 1}}), size_chunk(4, 4, 4), xyzi_chunk({{0, 0, 0, 2}}),
      ntrn(0, 1, {}), ngrp(1, {2, 4}), ntrn(2, 3, {}), nshp(3, 0), ntrn(4, 5, {{"_t", "100 100 100"}}), nshp(5, 1),
  }));
  CHECK(decode_vox(near, "near.vox").size() == Int3{104, 104, 104});
}

TEST_CASE("vox: a large grid that its models fill is accepted (a written 300x300x4 grid)") {
  Grid g({300, 300, 4});
  g.set({299, 299, 3}, Material::Granular);
  const Grid back = decode_vox(encode_vox(g), "tiles.vox");
  CHECK(back.size() == g.size());
  CHECK(back.hash() == g.hash());
}

TEST_CASE("vox: one model placed over and over on the same cells is refused") {
  std::vector<Voxel> voxels;
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y)
      for (int z = 0; z < 2; ++z) voxels.push_back({std::uint8_t(x), std::uint8_t(y), std::uint8_t(z), 1});
  std::vector<int> children;
  Bytes graph;
  for (int k = 0; k < 10; ++k) {
    children.push_back(2 + 2 * k);
    graph = cat({graph, ntrn(2 + 2 * k, 3 + 2 * k, {}), nshp(3 + 2 * k, 0)});
  }
  const Bytes b = vox_file(cat({size_chunk(2, 2, 2), xyzi_chunk(voxels), ntrn(0, 1, {}), ngrp(1, children), graph}));
  check_vox_rejected(b, {"10 placed models hold 80 voxels for a grid of 8 cells", "more than 8 per cell"});
}

TEST_CASE("vox: messages quote at most an excerpt of a long attribute") {
  const std::string long_t(100000, '7');
  const Bytes b = vox_file(cat({size_chunk(1, 1, 1), xyzi_chunk({{0, 0, 0, 1}}), ntrn(0, 1, {{"_t", long_t}}), nshp(1, 0)}));
  const std::string m = error_of<ParseError>([&] { decode_vox(b, "long.vox"); });
  check_has(m, {"translation _t", "... (100000 bytes)"});
  CHECK(m.size() < 300);
}
