/// @file test_hostile_files.cpp
/// Files that are not what they claim (issue 34, round three): saving onto a FIFO or a device (or a
/// link to one) is refused and the node stays; every reader, single-domain and distributed, checks a
/// regular file, then the header, then sizes against the file and the memory budget, and only then
/// reads: a FIFO cannot hang it, a zstd bomb is refused before it is decompressed, a sparse file's
/// header is refused before the file is read; a snapshot's hash covers its header (tick, seed, tool
/// calls); ranks given different worlds are told so on every rank; and the slab layout refuses a
/// sub-step count it cannot hold.

#include <doctest/doctest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "granular/distributed/distributed_world.hpp"
#include "granular/distributed/local_group.hpp"
#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/world.hpp"
#include "granular/world_snapshot.hpp"
#include "io/little_endian.hpp"
#include "io/snapshot_header.hpp"
#include "test_support.hpp"

using namespace granular;
using namespace granular::test;

namespace {

namespace fs = std::filesystem;

/// A fresh temporary folder, removed at the end of the scope.
struct TempDir {
  fs::path path;
  explicit TempDir(const char* name) : path(fs::temp_directory_path() / name) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

bool is_fifo_node(const fs::path& p) {
  struct stat info {};
  return ::lstat(p.c_str(), &info) == 0 && S_ISFIFO(info.st_mode);
}

/// A zstd frame of `content` zero bytes made of RLE blocks (4 bytes per 128 KiB), stating its
/// content size when `state_size`.
std::vector<std::uint8_t> zero_frame(std::uint64_t content, bool state_size) {
  std::vector<std::uint8_t> f = {0x28, 0xB5, 0x2F, 0xFD};
  if (state_size) {
    f.push_back(0xE0);  // 8-byte content size, single segment
    for (int i = 0; i < 8; ++i) f.push_back(std::uint8_t(content >> (8 * i)));
  } else {
    f.push_back(0x00);
    f.push_back(0x38);  // window 128 KiB
  }
  constexpr std::uint64_t kBlock = 128 * 1024;
  for (std::uint64_t left = content; left > 0;) {
    const std::uint64_t n = std::min(left, kBlock);
    left -= n;
    const std::uint32_t header = (left == 0 ? 1u : 0u) | (1u << 1) | std::uint32_t(n << 3);
    f.insert(f.end(), {std::uint8_t(header), std::uint8_t(header >> 8), std::uint8_t(header >> 16), 0});
  }
  return f;
}

/// A snapshot file of `version` whose header declares `size` and holds `body` as its cells.
std::vector<std::uint8_t> snapshot_file(std::uint32_t version, Int3 size, const std::vector<std::uint8_t>& body) {
  WorldSnapshot meta;
  meta.size = size;
  meta.rules = "inertial-24";
  std::vector<std::uint8_t> out = snapshot_header_bytes(meta, version, 0, body.size());
  out.insert(out.end(), body.begin(), body.end());
  return out;
}

void write_bytes(const fs::path& p, const std::vector<std::uint8_t>& bytes) {
  write_file_atomic(p, {std::span<const std::uint8_t>(bytes)});
}

/// Runs `fn` on 2 in-process ranks and returns the message of the error every rank threw (checking
/// that each threw an E).
template <class E, class F>
std::string error_on_every_rank(int ranks, F&& fn) {
  std::mutex m;
  std::vector<std::string> messages;
  int threw = 0;
  run_local_ranks(ranks, [&](Communicator& comm) {
    try {
      fn(comm);
    } catch (const E& e) {
      const std::lock_guard lock(m);
      ++threw;
      messages.push_back(e.what());
    }
  });
  CHECK(threw == ranks);
  return messages.empty() ? std::string() : messages.front();
}

/// $GRANULAR_MEMORY_LIMIT set for the scope.
struct MemoryLimit {
  explicit MemoryLimit(const char* bytes) { ::setenv("GRANULAR_MEMORY_LIMIT", bytes, 1); }
  ~MemoryLimit() { ::unsetenv("GRANULAR_MEMORY_LIMIT"); }
};

/// Seconds `fn` takes.
template <class F>
double seconds_of(F&& fn) {
  const auto start = std::chrono::steady_clock::now();
  fn();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

TEST_CASE("saving refuses a FIFO, a device or a link to one, and leaves the node; a link to a file writes its target") {
  const TempDir dir("granular_hostile_save");
  const Grid grid = random_grid({8, 8, 8}, 3);
  const fs::path fifo = dir.path / "pipe.raw";
  REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
  const fs::path link = dir.path / "link.gsnap";
  fs::create_symlink(fifo, link);
  check_has(error_of<FileError>([&] { save_grid(grid, fifo); }), {"pipe.raw", "FIFO", "not a regular file"});
  CHECK(is_fifo_node(fifo));
  check_has(error_of<FileError>([&] { check_grid_save_path(fifo); }), {"pipe.raw", "FIFO"});
  World world(test_def({8, 8, 8}, "inertial-24"), grid);
  check_has(error_of<FileError>([&] { save_snapshot(world.capture(), link); }),
            {"link.gsnap", "symbolic link to", "pipe.raw", "FIFO"});
  CHECK(is_fifo_node(fifo));
  CHECK(fs::is_symlink(link));
  check_has(error_of<FileError>([&] { check_snapshot_save_path(link); }), {"link.gsnap", "FIFO"});
  // A character device node of our own (root only: CI's container), never the system's.
  const fs::path device = dir.path / "null.vox";
  if (::mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0) {
    check_has(error_of<FileError>([&] { save_grid(grid, device); }), {"null.vox", "character device"});
    struct stat info {};
    CHECK((::lstat(device.c_str(), &info) == 0 && S_ISCHR(info.st_mode)));
  }
  // Through a link to a regular file: the target is replaced, the link stays.
  const fs::path target = dir.path / "target.raw", to_target = dir.path / "to_target.raw";
  save_grid(Grid({2, 2, 2}), target);
  fs::create_symlink(target, to_target);
  save_grid(grid, to_target);
  CHECK(fs::is_symlink(to_target));
  CHECK(load_raw(target).hash() == grid.hash());
  for (const auto& e : fs::directory_iterator(dir.path))
    CHECK_MESSAGE(e.path().string().find(".tmp-") == std::string::npos, e.path().string());
}

TEST_CASE("the distributed snapshot reader refuses a FIFO without hanging and names a device") {
  const TempDir dir("granular_hostile_fifo");
  const fs::path fifo = dir.path / "pipe.gsnap";
  REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
  const WorldDef def = test_def({16, 16, 32}, "inertial-24");
  auto reading = std::async(std::launch::async, [&] {
    return error_on_every_rank<FileError>(2, [&](Communicator& comm) { DistributedWorld w(def, comm, fifo); });
  });
  if (reading.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    FAIL_CHECK("DistributedWorld hangs on a FIFO");
    // Unblock the ranks waiting in open(): a writer that opens and leaves.
    for (int i = 0; i < 2; ++i) {
      const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd >= 0) ::close(fd);
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
  check_has(reading.get(), {"pipe.gsnap", "FIFO", "not a regular file"});
  check_has(error_on_every_rank<FileError>(2, [&](Communicator& comm) { DistributedWorld w(def, comm, "/dev/zero"); }),
            {"/dev/zero", "character device"});
  check_has(error_on_every_rank<FileError>(2, [&](Communicator& comm) { DistributedWorld w(def, comm, dir.path / "none.gsnap"); }),
            {"none.gsnap"});
}

TEST_CASE("a zstd bomb is refused before it is decompressed, by the single-domain and the distributed reader") {
  const TempDir dir("granular_hostile_bomb");
  const WorldDef def = test_def({16, 16, 64}, "inertial-24");
  // 512 KiB of frame stating 16 GiB, under a header of 16x16x64 cells (2 slabs of inertial-24's halo).
  const std::uint64_t bomb = std::uint64_t(16) << 30;
  for (const std::uint32_t version : {1u, 2u, kSnapshotVersion}) {
    CAPTURE(version);
    const fs::path stated = dir.path / "stated.gsnap", unstated = dir.path / "unstated.gsnap";
    write_bytes(stated, snapshot_file(version, {16, 16, 64}, zero_frame(bomb, true)));
    write_bytes(unstated, snapshot_file(version, {16, 16, 64}, zero_frame(bomb, false)));
    std::string message;
    double took = seconds_of([&] { message = error_of<ParseError>([&] { (void)load_snapshot(stated); }); });
    check_has(message, {"stated.gsnap", std::to_string(bomb)});
    CHECK(took < 2.0);
    took = seconds_of([&] {
      message = error_on_every_rank<ParseError>(2, [&](Communicator& comm) { DistributedWorld w(def, comm, stated); });
    });
    check_has(message, {"stated.gsnap", std::to_string(bomb)});
    CHECK(took < 2.0);
    took = seconds_of([&] {
      message = error_on_every_rank<ParseError>(2, [&](Communicator& comm) { DistributedWorld w(def, comm, unstated); });
    });
    check_has(message, {"unstated.gsnap", "does not state its content size"});
    CHECK(took < 2.0);
  }
}

TEST_CASE("a snapshot header over a sparse file is refused from its header, before the file is read or the slab allocated") {
  const TempDir dir("granular_hostile_sparse");
  // 65536^3 cells need over 8 GiB of compressed cells at zstd's largest expansion: a sparse file.
  const std::uint64_t packed = (std::uint64_t(8) << 30) + 4096;
  WorldSnapshot meta;
  meta.size = {65536, 65536, 65536};
  meta.rules = "inertial-24";
  const fs::path sparse = dir.path / "sparse.gsnap";
  write_bytes(sparse, snapshot_header_bytes(meta, kSnapshotVersion, 0, packed));
  // A budget below the file's size: a reader that read the file first would be refused for that.
  const MemoryLimit limit("1G");
  REQUIRE(::truncate(sparse.c_str(), off_t(fs::file_size(sparse) + packed)) == 0);
  std::string message;
  const double took = seconds_of([&] { message = error_of<OutOfMemory>([&] { (void)load_snapshot(sparse); }); });
  check_has(message, {"sparse.gsnap", "nx, ny, nz", "65536x65536x65536"});
  CHECK(took < 2.0);
  const WorldDef def = test_def({16, 16, 32}, "inertial-24");
  check_has(error_on_every_rank<OutOfMemory>(2, [&](Communicator& comm) { DistributedWorld w(def, comm, sparse); }),
            {"sparse.gsnap", "65536x65536x"});
}

TEST_CASE("a snapshot's hash covers its header: a flipped tick, seed or tool-call bit is refused; version 1 files still load") {
  const TempDir dir("granular_hostile_header_hash");
  const WorldDef def = test_def({12, 10, 56}, "inertial-24", 1, 5);
  World world(def, mixed_material_grid({12, 10, 56}, 4));
  world.step(3);
  (void)world.pour({6, 5, 15}, 2.0, Material::Granular, 5);
  const std::vector<std::uint8_t> good = encode_snapshot(world.capture());
  CHECK(get_u32(good, 4) == kSnapshotVersion);
  for (const std::size_t field : {48u, 72u}) {  // the rule fingerprint, the rule set's name
    CAPTURE(field);
    std::vector<std::uint8_t> bad = good;
    bad[field] ^= 0x02;
    check_has(error_of<ParseError>([&] { (void)decode_snapshot(bad, "flipped.gsnap"); }), {"flipped.gsnap", "hash"});
  }
  for (const std::size_t field : {24u, 32u, 40u}) {  // tick, seed, tool_calls
    CAPTURE(field);
    std::vector<std::uint8_t> bad = good;
    bad[field] ^= 0x02;
    check_has(error_of<ParseError>([&] { (void)decode_snapshot(bad, "flipped.gsnap"); }), {"flipped.gsnap", "hash"});
    const fs::path file = dir.path / "flipped.gsnap";
    write_bytes(file, bad);
    check_has(error_on_every_rank<ParseError>(2, [&](Communicator& comm) { DistributedWorld w(def, comm, file); }),
              {"flipped.gsnap", "hash"});
  }
  // A version 1 file (the hash of the cells alone) still loads, and its header is not covered.
  WorldSnapshot s = world.capture();
  const std::vector<std::uint8_t> packed(good.begin() + std::ptrdiff_t(kSnapshotHeaderSize + s.rules.size()), good.end());
  std::vector<std::uint8_t> v1 = snapshot_header_bytes(s, 1, s.hash(), packed.size());
  v1.insert(v1.end(), packed.begin(), packed.end());
  const WorldSnapshot back = decode_snapshot(v1, "v1.gsnap");
  CHECK(back.tick == s.tick);
  CHECK(back.cells == s.cells);
  v1[32] ^= 0x02;
  CHECK(decode_snapshot(v1, "v1.gsnap").seed == (s.seed ^ 0x02));
}

TEST_CASE("distributed world: ranks given different worlds are told so on every rank") {
  const std::string sizes = error_on_every_rank<InvalidArgument>(2, [&](Communicator& comm) {
    DistributedWorld w(test_def({16, 16, comm.rank() == 0 ? 64 : 80}, "inertial-24"), comm);
  });
  check_has(sizes, {"rank 0", "16x16x64", "rank 1", "16x16x80"});
  const std::string seeds = error_on_every_rank<InvalidArgument>(2, [&](Communicator& comm) {
    DistributedWorld w(test_def({16, 16, 64}, "inertial-24", 1, std::uint64_t(comm.rank())), comm);
  });
  check_has(seeds, {"seed", "rank 1"});
  const std::string rules = error_on_every_rank<InvalidArgument>(2, [&](Communicator& comm) {
    DistributedWorld w(test_def({16, 16, 64}, comm.rank() == 0 ? "inertial-24" : "paper"), comm);
  });
  check_has(rules, {"rules", "paper"});
  // A rule set name only one rank cannot make fails every rank, none waits.
  CHECK_THROWS(run_local_ranks(2, [&](Communicator& comm) {
    DistributedWorld w(test_def({16, 16, 64}, comm.rank() == 0 ? "inertial-24" : "no-such-rules"), comm);
  }));
}

TEST_CASE("slab layout: the halo of a sub-step count the rules refuse is a RuleError, not an overflow") {
  RuleSet rules = *make_rule_set("inertial-24");
  rules.motion.substeps = INT_MAX;
  check_has(error_of<RuleError>([&] { (void)SlabLayout::halo_for(rules); }), {"substeps", std::to_string(INT_MAX)});
  WorldDef def = test_def({16, 16, 32}, "inertial-24");
  def.rule_set = std::make_shared<const RuleSet>(rules);
  CHECK_THROWS_AS(run_local_ranks(2, [&](Communicator& comm) { DistributedWorld w(def, comm); }), RuleError);
}
