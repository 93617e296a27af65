/// @file test_world_snapshot.cpp
/// Snapshots: a world captured, written to a .gsnap file, read back and made into a fresh World
/// continues with the same hash and tick after every later tick as one that never stopped (the
/// default rules with their motion state, water, gas and tools between ticks; sparse and dense);
/// restore() does the same into an existing world. Bad files and mismatched worlds are typed errors
/// naming the field and the value.

#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "granular/extend/hex.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/world.hpp"
#include "granular/world_snapshot.hpp"
#include "io/little_endian.hpp"
#include "test_support.hpp"
#include "tool_session.hpp"

using namespace granular;
using granular::test::check_has;
using granular::test::error_of;
using granular::test::fluid_scene;
using granular::test::play;
using granular::test::play_alike;
using granular::test::test_def;

namespace {

const Int3 kSize{40, 36, 44};

/// inertial-24 rules on the CPU, sparse or dense, seed 7.
WorldDef snapshot_def(bool sparse) {
  WorldDef def = test_def(kSize, "inertial-24", 2, 7);
  def.sparse = sparse;
  return def;
}

/// A file in the test's temporary folder.
std::filesystem::path temp_file(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("granular-snapshot-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

/// The world after `ticks` ticks of the tool session.
World session_world(const WorldDef& def, int ticks) {
  World w(def, fluid_scene(kSize));
  play(w, ticks);
  return w;
}

/// A small snapshot's encoded bytes.
std::vector<std::uint8_t> small_snapshot_bytes() {
  WorldSnapshot s;
  s.size = {3, 2, 2};
  s.cells = {0, 1, 2, 3, 4, 5, 6, 7, 0x12, 0, 1, 2};
  s.tick = 5;
  s.seed = 9;
  s.tool_calls = 2;
  s.rules = "inertial-24";
  s.rule_fingerprint = 0x1234;
  return encode_snapshot(s);
}

}  // namespace

TEST_CASE("snapshot: a world saved, loaded into a fresh World and stepped on keeps the hash of one that never stopped") {
  for (const bool sparse : {true, false}) {
    CAPTURE(sparse);
    const WorldDef def = snapshot_def(sparse);
    World original = session_world(def, 37);
    const WorldSnapshot captured = original.capture();
    CHECK(captured.tick == 37);
    CHECK(captured.seed == 7);
    CHECK(captured.tool_calls == original.tool_calls());
    CHECK(captured.tool_calls > 10);
    CHECK(captured.rules == "inertial-24");
    CHECK(captured.rule_fingerprint == rule_fingerprint(original.rules()));
    CHECK(captured.hash() == original.hash());
    std::int64_t moving = 0;  // the motion state is kept, not only the materials
    for (const std::uint8_t c : captured.cells) moving += (c >> 3) != 0;
    REQUIRE(moving > 100);
    const MaterialCounts counts = original.count();
    REQUIRE(counts[to_cell(Material::Liquid)] > 0);
    REQUIRE(counts[to_cell(Material::Gas)] > 0);

    const auto file = temp_file(sparse ? "sparse.GSNAP" : "dense.gsnap");
    save_snapshot(captured, file);
    const WorldSnapshot loaded = load_snapshot(file);
    CHECK(loaded.cells == captured.cells);
    WorldDef fresh_def = def;
    fresh_def.seed = 0;  // the snapshot's seed wins
    World continued(fresh_def, loaded);
    CHECK(continued.tick() == 37);
    CHECK(continued.tool_calls() == original.tool_calls());
    CHECK(continued.hash() == original.hash());
    CHECK(continued.def().seed == 7);
    play_alike(original, continued, 45);
  }
}

TEST_CASE("snapshot: restore() puts a captured state back into a world, which continues as the original did") {
  const WorldDef def = snapshot_def(true);
  World original = session_world(def, 21);
  const WorldSnapshot at_21 = original.capture();
  World other = session_world(def, 50);  // the same world further on: other cells, tick and tool calls
  REQUIRE(other.hash() != original.hash());
  const std::uint64_t version = other.change_version();
  other.restore(at_21);
  CHECK(other.tick() == 21);
  CHECK(other.tool_calls() == original.tool_calls());
  CHECK(other.hash() == original.hash());
  CHECK(other.bricks_changed_since(version).size() == std::size_t(brick_counts(kSize).x * brick_counts(kSize).y * brick_counts(kSize).z));
  play_alike(original, other, 30);
}

TEST_CASE("snapshot: the encoded layout is the documented header, the rule set name, then one zstd frame") {
  const std::vector<std::uint8_t> bytes = small_snapshot_bytes();
  REQUIRE(bytes.size() > kSnapshotHeaderSize + 11);
  CHECK(std::string(bytes.begin(), bytes.begin() + 4) == "GSNP");
  const auto u32 = [&](std::size_t at) { return bytes[at] | bytes[at + 1] << 8 | bytes[at + 2] << 16 | std::uint32_t(bytes[at + 3]) << 24; };
  const auto u64 = [&](std::size_t at) { return u32(at) | std::uint64_t(u32(at + 4)) << 32; };
  CHECK(u32(4) == kSnapshotVersion);
  CHECK(u32(8) == 3);
  CHECK(u32(12) == 2);
  CHECK(u32(16) == 2);
  CHECK(u32(20) == 11);
  CHECK(u64(24) == 5);
  CHECK(u64(32) == 9);
  CHECK(u64(40) == 2);
  CHECK(u64(48) == 0x1234);
  CHECK(u64(64) == bytes.size() - kSnapshotHeaderSize - 11);
  CHECK(std::string(bytes.begin() + 72, bytes.begin() + 83) == "inertial-24");
  CHECK(bytes[83] == 0x28);  // the zstd frame's magic, 0xFD2FB528 little-endian
  const WorldSnapshot back = decode_snapshot(bytes, "mem.gsnap");
  CHECK(back.cells == std::vector<std::uint8_t>{0, 1, 2, 3, 4, 5, 6, 7, 0x12, 0, 1, 2});
  CHECK(u64(56) == snapshot_file_hash(back, back.hash(), kSnapshotVersion));
  CHECK(u64(56) != back.hash());  // version 3's hash covers the header too
  CHECK(back.rules == "inertial-24");
}

TEST_CASE("snapshot: bad files are ParseErrors naming the field, offset or value") {
  const std::vector<std::uint8_t> good = small_snapshot_bytes();
  const auto parse_error = [](std::vector<std::uint8_t> bytes) {
    return error_of<ParseError>([&] { decode_snapshot(bytes, "bad.gsnap"); });
  };
  // Every truncation is refused.
  for (std::size_t n = 0; n < good.size(); ++n) {
    CAPTURE(n);
    const std::string m = parse_error(std::vector<std::uint8_t>(good.begin(), good.begin() + std::ptrdiff_t(n)));
    CHECK(m.rfind("bad.gsnap: ", 0) == 0);
  }
  check_has(parse_error({good.begin(), good.begin() + 30}), {"truncated header", "30 bytes", "field tick (bytes 24..31)"});
  check_has(parse_error({good.begin(), good.begin() + 80}), {"truncated rule set name", "11 bytes", "only 8"});
  check_has(parse_error({good.begin(), good.end() - 1}), {"truncated body", "packed_size (bytes 64..71)"});
  auto bad = good;
  bad[1] = 'X';
  check_has(parse_error(bad), {"not a snapshot file", "bad magic \"GXNP\"", "expected \"GSNP\""});
  check_has(parse_error({'G', 'R', 'A', 'W', 1, 0, 0, 0}), {"bad magic \"GRAW\""});
  bad = good;
  bad[4] = 7;
  check_has(parse_error(bad), {"unsupported snapshot version 7", "version (bytes 4..7)", "reads versions 1..6"});
  // A version 3 file relabelled 4 or 5 lacks the side or face plane its frames should hold after
  // the cells.
  for (const std::uint8_t planed : {4, 5}) {
    bad = good;
    bad[4] = planed;
    CHECK_THROWS_AS(decode_snapshot(bad, "bad.gsnap"), ParseError);
  }
  // Versions 2 and 3 hold one or more frames, version 1 one; versions 1 and 2 hash the cells alone.
  const std::uint64_t cells_hash = decode_snapshot(good, "good.gsnap").hash();
  for (const std::uint8_t older : {1, 2}) {
    auto old_file = good;
    old_file[4] = older;
    check_has(parse_error(old_file), {"the cells' hash", "differs from header field hash"});
    put_u64(old_file.data() + 56, cells_hash);
    CHECK(decode_snapshot(old_file, "old.gsnap").hash() == cells_hash);
  }
  const std::size_t body = good.size() - get_u64(good, 64);
  auto doubled = good;
  doubled.insert(doubled.end(), good.begin() + std::ptrdiff_t(body), good.end());
  put_u64(doubled.data() + 64, 2 * get_u64(good, 64));
  doubled[4] = 1;
  check_has(parse_error(doubled), {"bytes follow the zstd frame"});
  doubled[4] = 2;
  check_has(parse_error(doubled), {"frame 1 at byte", "the frames hold more than"});
  bad = good;
  bad[12] = 0;
  check_has(parse_error(bad), {"ny (bytes 12..15) = 0", "outside 1..65536"});
  bad = good;
  bad[20] = 0;
  check_has(parse_error(bad), {"rules_length (bytes 20..23) = 0"});
  bad = good;
  bad[75] = '\n';
  check_has(parse_error(bad), {"rule set name at byte 72", "control character \"\\x0A\" at byte 3"});
  bad = good;
  bad.push_back(0);
  check_has(parse_error(bad), {"1 trailing bytes after the compressed cells", "should be " + std::to_string(good.size())});
  bad = good;
  bad[56] ^= 1;
  check_has(parse_error(bad), {"the hash of the cells and the header's fields", "differs from header field hash (bytes 56..63)",
                               "damaged"});
  bad = good;
  bad[83] = 0;
  check_has(parse_error(bad), {"the compressed cells at byte 83 are not a zstd frame"});
  // A header asking for 65536^3 cells from a few bytes is refused before anything is allocated.
  bad = good;
  for (const std::size_t at : {8, 12, 16}) {
    bad[at] = 0;
    bad[at + 1] = 0;
    bad[at + 2] = 1;
  }
  check_has(parse_error(bad), {"65536x65536x65536", "cannot come from", "expands at most 32768-fold"});
}

TEST_CASE("snapshot: a world of other rules, size or seed refuses it, naming both values") {
  const WorldSnapshot captured = session_world(snapshot_def(true), 5).capture();
  WorldDef paper = snapshot_def(true);
  paper.rules = "paper";
  check_has(error_of<InvalidArgument>([&] { World w(paper, captured); }),
            {"rules 'inertial-24' (fingerprint " + hex64(captured.rule_fingerprint) + ")", "world's rules are 'paper'"});
  // A preset's rule set edited under the same name has another fingerprint.
  RuleSet edited = preset("inertial-24");
  edited.materials[2].grain.roll_cost = 100;
  WorldDef edited_def = snapshot_def(true);
  edited_def.rule_set = std::make_shared<const RuleSet>(edited);
  check_has(error_of<InvalidArgument>([&] { World w(edited_def, captured); }), {"has changed since"});

  World smaller(test_def({20, 20, 20}, "inertial-24", 2, 7));
  check_has(error_of<InvalidArgument>([&] { smaller.restore(captured); }),
            {"World::restore", "snapshot's grid is 40x36x44", "world's is 20x20x20"});
  World other_seed(test_def(kSize, "inertial-24", 2, 8));
  check_has(error_of<InvalidArgument>([&] { other_seed.restore(captured); }), {"seed is 7", "(WorldDef::seed) is 8"});
  World paper_world(test_def(kSize, "paper", 2, 7));
  check_has(error_of<InvalidArgument>([&] { paper_world.restore(captured); }), {"World::restore", "'paper'"});
  const std::uint64_t unchanged = paper_world.hash();
  CHECK(paper_world.tick() == 0);
  CHECK(paper_world.hash() == unchanged);
}

TEST_CASE("snapshot: cell bytes the rule set cannot hold are refused, naming the cell and the byte") {
  WorldSnapshot s = session_world(snapshot_def(true), 3).capture();
  s.cells[5] = 0x21;  // solid (1) with motion level 4
  check_has(error_of<InvalidArgument>([&] { World w(snapshot_def(true), s); }),
            {"cell (5, 0, 0) holds the byte 33", "motion state on solid"});
  s.cells[5] = 1;
  const std::size_t sand = std::size_t(std::find(s.cells.begin(), s.cells.end(), std::uint8_t(2)) - s.cells.begin());
  s.cells[sand] = 2 | (15 << 3);
  check_has(error_of<InvalidArgument>([&] { World w(snapshot_def(true), s); }), {"motion level 15, above the rules' highest, 12"});
}

TEST_CASE("snapshot: files are .gsnap in any case; saving checks the path first") {
  CHECK(is_snapshot_file("a.gsnap"));
  CHECK(is_snapshot_file("dir/B.GSnap"));
  CHECK_FALSE(is_snapshot_file("a.raw"));
  CHECK_FALSE(is_snapshot_file("gsnap"));
  const WorldSnapshot s = decode_snapshot(small_snapshot_bytes(), "mem");
  check_has(error_of<InvalidArgument>([&] { save_snapshot(s, temp_file("x.raw")); }),
            {"cannot save snapshot", "the extension '.raw'", "is .gsnap"});
  check_has(error_of<FileError>([&] { check_snapshot_save_path("/nonexistent-granular-dir/x.gsnap"); }),
            {"/nonexistent-granular-dir"});
  check_has(error_of<FileError>([&] { load_snapshot(temp_file("missing.gsnap")); }), {"missing.gsnap"});
}

TEST_CASE("snapshot: the fuzz corpus's version 2 and 3 files (built by make_corpus.py) load alike") {
  const std::filesystem::path corpus = std::filesystem::path(GRANULAR_TEST_ASSET_DIR) / ".." / "tests" / "fuzz" / "corpus";
  const WorldSnapshot two = load_snapshot(corpus / "snapshot-slab-frames-v2.gsnap");
  const WorldSnapshot three = load_snapshot(corpus / "snapshot-slab-frames-v3.gsnap");
  CHECK(two.size == Int3{4, 3, 64});
  CHECK(three.cells == two.cells);
  CHECK(three.tick == two.tick);
  CHECK(three.rules == "inertial-24");
}
