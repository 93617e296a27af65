#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular/grid_io.hpp"
#include "granular/extend/memory_budget.hpp"
#include "granular/vox_io.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace granular;

using granular::test::check_has;
using granular::test::error_of;

namespace {

/// A fresh directory under the system temp dir, removed with everything in it at scope exit.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ =
        fs::temp_directory_path() / ("granular_grid_io_" + std::to_string(getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ignored);
    fs::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  fs::path operator/(const std::string& name) const { return path_ / name; }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

Grid random_grid(Int3 size, unsigned seed) {
  Grid g(size);
  std::mt19937 rng(seed);
  for (auto& c : g.cells()) c = std::uint8_t(rng() % kMaterialCount);
  return g;
}

std::vector<std::uint8_t> file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

void put_u32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + std::size_t(i)] = std::uint8_t(v >> (8 * i));
}

std::vector<std::uint8_t> raw_header(std::uint32_t nx, std::uint32_t ny, std::uint32_t nz) {
  std::vector<std::uint8_t> b(20);
  std::memcpy(b.data(), "GRAW", 4);
  put_u32(b, 4, 1);
  put_u32(b, 8, nx);
  put_u32(b, 12, ny);
  put_u32(b, 16, nz);
  return b;
}


/// Checks that `bytes` fail with a ParseError naming the source and `parts`, both in memory and
/// from a file (which takes load_raw's streaming path).
void check_raw_rejected(const std::vector<std::uint8_t>& bytes, std::initializer_list<std::string_view> parts) {
  const std::string mem = error_of<ParseError>([&] { decode_raw(bytes, "memory-grid.raw"); });
  check_has(mem, {"memory-grid.raw"});
  check_has(mem, parts);
  TempDir dir;
  const fs::path p = dir / "bad_input.raw";
  write_bytes(p, bytes);
  const std::string file = error_of<ParseError>([&] { load_raw(p); });
  check_has(file, {p.string()});
  check_has(file, parts);
  const std::string dispatched = error_of<ParseError>([&] { load_grid(p); });
  check_has(dispatched, {p.string()});
}

}  // namespace

TEST_CASE("raw: encoded layout is the documented header then one byte per cell") {
  Grid g({7, 5, 3});
  g.set({2, 3, 1}, Material::Granular);
  g.set({6, 4, 2}, Material::State7);
  const auto b = encode_raw(g);
  REQUIRE(b.size() == 20 + 7 * 5 * 3);
  CHECK(std::string(b.begin(), b.begin() + 4) == "GRAW");
  const std::vector<std::uint8_t> fields(b.begin() + 4, b.begin() + 20);
  CHECK(fields == std::vector<std::uint8_t>{1, 0, 0, 0, 7, 0, 0, 0, 5, 0, 0, 0, 3, 0, 0, 0});
  CHECK(b[20 + 2 + 7 * (3 + 5 * 1)] == 2);
  CHECK(b[20 + 6 + 7 * (4 + 5 * 2)] == 7);
  CHECK(b[20] == 0);
  CHECK(std::count(b.begin() + 20, b.end(), 0) == 7 * 5 * 3 - 2);
}

TEST_CASE("raw: random grids round-trip exactly, in memory and through files") {
  TempDir dir;
  const Int3 sizes[] = {{1, 1, 1}, {7, 5, 3}, {16, 16, 16}, {33, 1, 9}, {2, 300, 2}};
  unsigned seed = 1;
  for (Int3 s : sizes) {
    CAPTURE(to_string(s));
    const Grid g = random_grid(s, seed++);
    const Grid mem = decode_raw(encode_raw(g), "mem");
    CHECK(mem.size() == s);
    CHECK(std::equal(mem.cells().begin(), mem.cells().end(), g.cells().begin(), g.cells().end()));
    const fs::path p = dir / ("grid_" + to_string(s) + ".raw");
    save_raw(g, p);
    CHECK(file_bytes(p) == encode_raw(g));
    const Grid back = load_raw(p);
    CHECK(back.size() == s);
    CHECK(back.hash() == g.hash());
    CHECK(std::equal(back.cells().begin(), back.cells().end(), g.cells().begin(), g.cells().end()));
  }
}

TEST_CASE("raw: missing or unreadable files raise FileError with the path and the reason") {
  TempDir dir;
  const fs::path missing = dir / "does_not_exist.raw";
  const std::string m = error_of<FileError>([&] { load_raw(missing); });
  check_has(m, {missing.string(), std::strerror(ENOENT)});
  const std::string d = error_of<FileError>([&] { load_raw(dir.path()); });
  check_has(d, {dir.path().string(), std::strerror(EISDIR)});
  const std::string r = error_of<FileError>([&] { read_file_bytes(missing); });
  check_has(r, {missing.string(), std::strerror(ENOENT)});
}

TEST_CASE("raw: malformed headers are rejected with the field at fault") {
  const auto valid = encode_raw(random_grid({7, 5, 3}, 9));

  SUBCASE("bad magic") {
    auto b = valid;
    b[3] = 'X';
    check_raw_rejected(b, {"bad magic", "\"GRAX\"", "expected \"GRAW\""});
  }
  SUBCASE("a file of another format") {
    check_raw_rejected({'V', 'O', 'X', ' ', 150, 0, 0, 0}, {"not a raw grid file", "\"VOX \""});
  }
  SUBCASE("empty file") { check_raw_rejected({}, {"truncated header", "has 0 bytes", "magic"}); }
  SUBCASE("unsupported version") {
    auto b = valid;
    put_u32(b, 4, 2);
    check_raw_rejected(b, {"unsupported raw grid version 2", "bytes 4..7", "version 1"});
  }
  SUBCASE("truncated header") {
    const std::vector<std::uint8_t> b(valid.begin(), valid.begin() + 14);
    check_raw_rejected(b, {"truncated header", "has 14 bytes", "field ny", "bytes 12..15"});
  }
  SUBCASE("zero extent") {
    auto b = valid;
    put_u32(b, 8, 0);
    check_raw_rejected(b, {"nx, ny, nz", "0x5x3", "zero extent along x"});
  }
  SUBCASE("extent over the maximum") {
    auto b = raw_header(7, 100000, 3);
    check_raw_rejected(b, {"100000", "exceeds the maximum extent 65536", "along y"});
  }
  SUBCASE("extent that does not fit an int") {
    auto b = raw_header(7, 5, 0xFFFFFFFFu);
    check_raw_rejected(b, {"field nz", "bytes 16..19", "4294967295", "maximum extent"});
  }
}

TEST_CASE("raw: malformed bodies are rejected with sizes, offsets and values") {
  SUBCASE("truncated body") {
    auto b = raw_header(64, 64, 64);
    b.resize(20 + 1000, 1);
    check_raw_rejected(b, {"truncated body", "header says 64x64x64 = 262144 cells but only 1000 bytes follow"});
  }
  SUBCASE("trailing bytes") {
    auto b = encode_raw(random_grid({7, 5, 3}, 3));
    b.insert(b.end(), {0, 0, 0});
    check_raw_rejected(b, {"3 trailing bytes", "7x5x3 = 105 cells", "should be 125 bytes but it is 128"});
  }
  SUBCASE("cell value out of range") {
    auto b = encode_raw(random_grid({7, 5, 3}, 4));
    b[20 + 2 + 7 * (3 + 5 * 1)] = 9;
    b[20 + 104] = 200;
    check_raw_rejected(b, {"invalid cell value 9", "byte offset 78", "x=2, y=3, z=1", "2 invalid cells"});
  }
  SUBCASE("value 8 is the first invalid one") {
    auto b = encode_raw(Grid({2, 2, 2}));
    b[20] = 8;
    check_raw_rejected(b, {"invalid cell value 8", "byte offset 20", "x=0, y=0, z=0"});
  }
}

TEST_CASE("raw: a truncated file with a header larger than memory is a truncated body, found before allocating") {
  auto b = raw_header(65536, 65536, 65536);
  b.resize(b.size() + 10, 0);
  check_raw_rejected(b, {"truncated body", "65536x65536x65536 = 281474976710656 cells but only 10 bytes follow"});
}

TEST_CASE("raw: a complete grid larger than the memory budget is OutOfMemory naming the size and the limit") {
  // memory_budget is pure: a 1 GiB RLIMIT_AS with 900 MiB mapped leaves 124 MiB.
  MemorySources s;
  s.mem_available = std::uint64_t(8) << 30;
  s.address_space_limit = std::uint64_t(1) << 30;
  s.address_space_used = std::uint64_t(900) << 20;
  const MemoryBudget b = memory_budget(s);
  CHECK(b.bytes == (std::uint64_t(124) << 20));
  check_has(b.limited_by, {"ulimit -v (RLIMIT_AS) of 1 GiB", "900 MiB in use"});
  const std::string m = error_of<OutOfMemory>([] { check_grid_size({65536, 65536, 4096}, "big.raw", 1.0); });
  check_has(m, {"big.raw", "65536x65536x4096", "17592186044416 cells", "16 TiB", "limited by"});
}

TEST_CASE("memory_budget takes the least of MemAvailable, the cgroup limit and the rlimits") {
  MemorySources s;
  CHECK(memory_budget(s).limited_by.empty());
  CHECK(memory_budget(s).bytes == UINT64_MAX);
  s.physical = 64ull << 30;
  CHECK(memory_budget(s).bytes == 64ull << 30);
  check_has(memory_budget(s).limited_by, {"physical memory"});
  s.mem_available = 20ull << 30;
  CHECK(memory_budget(s).bytes == 20ull << 30);
  check_has(memory_budget(s).limited_by, {"MemAvailable"});
  s.cgroup_limit = 4ull << 30;
  s.cgroup_usage = 1ull << 30;
  CHECK(memory_budget(s).bytes == 3ull << 30);
  check_has(memory_budget(s).limited_by, {"cgroup", "4 GiB", "1 GiB in use"});
  s.data_limit = 2ull << 30;
  CHECK(memory_budget(s).bytes == 2ull << 30);
  check_has(memory_budget(s).limited_by, {"ulimit -d (RLIMIT_DATA)"});
  s.user_limit = 1ull << 30;
  CHECK(memory_budget(s).bytes == 1ull << 30);
  check_has(memory_budget(s).limited_by, {"$GRANULAR_MEMORY_LIMIT = 1 GiB"});
  s.data_used = 3ull << 30;  // more in use than the limit: nothing left
  CHECK(memory_budget(s).bytes == 0);
  // This process: the budget is known (at least MemAvailable or the physical memory) and positive.
  const MemoryBudget here = available_memory();
  CHECK_FALSE(here.limited_by.empty());
  CHECK(here.bytes > 0);
}

TEST_CASE("parse_byte_count reads bytes with binary suffixes; $GRANULAR_MEMORY_LIMIT caps the budget") {
  CHECK(parse_byte_count("0") == 0u);
  CHECK(parse_byte_count("4096") == 4096u);
  CHECK(parse_byte_count("64K") == 65536u);
  CHECK(parse_byte_count("512m") == 512ull << 20);
  CHECK(parse_byte_count("2G") == 2ull << 30);
  CHECK(parse_byte_count("1T") == 1ull << 40);
  for (const char* bad : {"", "G", "-1", "1.5G", "1GB", "1 G", "99999999999999999999", "20000000000T"})
    CHECK_FALSE(parse_byte_count(bad).has_value());
  const char* old = std::getenv("GRANULAR_MEMORY_LIMIT");
  const std::string saved = old ? old : "";
  setenv("GRANULAR_MEMORY_LIMIT", "1M", 1);
  CHECK(available_memory().bytes <= (1u << 20));
  check_has(error_of<OutOfMemory>([] { Grid({128, 128, 128}); }), {"2 MiB", "$GRANULAR_MEMORY_LIMIT = 1 MiB"});
  setenv("GRANULAR_MEMORY_LIMIT", "lots", 1);
  check_has(error_of<InvalidArgument>([] { check_grid_size({1, 1, 1}, "x"); }), {"GRANULAR_MEMORY_LIMIT='lots'"});
  if (old) setenv("GRANULAR_MEMORY_LIMIT", saved.c_str(), 1);
  else unsetenv("GRANULAR_MEMORY_LIMIT");
}

TEST_CASE("check_grid_size counts every byte per cell and the extra bytes against the budget") {
  const MemoryBudget here = available_memory();
  REQUIRE(here.bytes > (std::uint64_t(64) << 20));
  // A grid whose one-byte copy fits but whose two-byte run does not.
  const std::int64_t cells = std::int64_t(here.bytes / 3 * 2);
  const int side = int(std::cbrt(double(cells))) + 1;
  if (side > kMaxGridExtent) {
    MESSAGE("too much memory available to find a grid that fits once but not twice");
    return;
  }
  const Int3 size{side, side, side};
  if (double(side) * side * side > double(here.bytes)) {
    MESSAGE("no side fits once at this budget's granularity");
    return;
  }
  CHECK_NOTHROW(check_grid_size(size, "once", 1.0));
  const std::string m = error_of<OutOfMemory>([&] { check_grid_size(size, "twice", 2.0); });
  check_has(m, {"twice", to_string(size), "2 bytes per cell"});
  const std::string e = error_of<OutOfMemory>([&] { check_grid_size({1, 1, 1}, "extra", 1.0, double(here.bytes) * 2); });
  check_has(e, {"extra", "1x1x1", "1 byte per cell + "});
}

TEST_CASE("raw: a failed save leaves an existing file untouched") {
  TempDir dir;
  const Grid g = random_grid({7, 5, 3}, 5);

  SUBCASE("target directory does not exist") {
    const fs::path p = dir / "no_such_dir" / "out.raw";
    const std::string m = error_of<FileError>([&] { save_raw(g, p); });
    check_has(m, {p.string(), std::strerror(ENOENT), "temporary file"});
    CHECK_FALSE(fs::exists(p.parent_path()));
  }
  SUBCASE("target is an existing directory: refused before writing, directory and its content stay") {
    const fs::path target = dir / "occupied.raw";
    fs::create_directory(target);
    write_bytes(target / "keep.txt", {'k'});
    const std::string m = error_of<FileError>([&] { save_raw(g, target); });
    check_has(m, {target.string(), "it is a directory, not a regular file"});
    CHECK(fs::is_directory(target));
    CHECK(file_bytes(target / "keep.txt") == std::vector<std::uint8_t>{'k'});
    CHECK(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()) == 1);
  }
  SUBCASE("read-only directory: existing file keeps its bytes") {
    const fs::path sub = dir / "readonly";
    fs::create_directory(sub);
    const fs::path target = sub / "existing.raw";
    const std::vector<std::uint8_t> before = {'o', 'l', 'd'};
    write_bytes(target, before);
    fs::permissions(sub, fs::perms::owner_read | fs::perms::owner_exec);
    if (access(sub.c_str(), W_OK) == 0) {
      MESSAGE("running with privileges that ignore directory permissions; read-only case not checkable");
    } else {
      const std::string m = error_of<FileError>([&] { save_raw(g, target); });
      check_has(m, {target.string(), std::strerror(EACCES), "left untouched"});
      CHECK(file_bytes(target) == before);
    }
    fs::permissions(sub, fs::perms::owner_all);
  }
  SUBCASE("empty grid: InvalidArgument, nothing written") {
    const fs::path target = dir / "existing.raw";
    write_bytes(target, {'o', 'l', 'd'});
    const std::string m = error_of<InvalidArgument>([&] { save_raw(Grid(), target); });
    check_has(m, {"empty", "0x0x0"});
    CHECK(file_bytes(target) == std::vector<std::uint8_t>{'o', 'l', 'd'});
  }
}

TEST_CASE("raw: saving over an existing file replaces it and leaves no temporary") {
  TempDir dir;
  const fs::path p = dir / "over.raw";
  write_bytes(p, std::vector<std::uint8_t>(5000, 0xAB));
  const Grid g = random_grid({3, 4, 5}, 6);
  save_raw(g, p);
  CHECK(file_bytes(p) == encode_raw(g));
  CHECK(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()) == 1);
}

TEST_CASE("write_file_atomic concatenates its parts and read_file_bytes reads them back") {
  TempDir dir;
  const fs::path p = dir / "parts.bin";
  const std::vector<std::uint8_t> a = {1, 2, 3}, b = {}, c = {4, 5};
  write_file_atomic(p, {a, b, c});
  CHECK(read_file_bytes(p) == std::vector<std::uint8_t>{1, 2, 3, 4, 5});
  write_file_atomic(p, {});
  CHECK(read_file_bytes(p).empty());
}

TEST_CASE("load_grid / save_grid dispatch on the extension") {
  TempDir dir;
  const Grid g = random_grid({9, 4, 6}, 7);

  SUBCASE(".raw") {
    const fs::path p = dir / "scene.raw";
    save_grid(g, p);
    CHECK(file_bytes(p) == encode_raw(g));
    CHECK(load_grid(p).hash() == g.hash());
  }
  SUBCASE(".vox") {
    const fs::path p = dir / "scene.vox";
    save_grid(g, p);
    const auto b = file_bytes(p);
    REQUIRE(b.size() > 8);
    CHECK(std::string(b.begin(), b.begin() + 4) == "VOX ");
    const Grid back = load_grid(p);
    CHECK(back.size() == g.size());
    CHECK(back.hash() == g.hash());
  }
  SUBCASE("upper-case extension") {
    const fs::path p = dir / "SCENE.RAW";
    save_grid(g, p);
    const auto b = file_bytes(p);
    REQUIRE(b.size() > 4);
    CHECK(std::string(b.begin(), b.begin() + 4) == "GRAW");
    CHECK(load_grid(p).hash() == g.hash());
  }
  SUBCASE("unknown extension") {
    const fs::path p = dir / "scene.png";
    const std::string s = error_of<InvalidArgument>([&] { save_grid(g, p); });
    check_has(s, {p.string(), "'.png'", ".raw", ".vox"});
    CHECK_FALSE(fs::exists(p));
    write_bytes(p, {1, 2, 3});
    const std::string l = error_of<InvalidArgument>([&] { load_grid(p); });
    check_has(l, {p.string(), "'.png'", ".raw", ".vox"});
  }
  SUBCASE("no extension") {
    const fs::path p = dir / "scene";
    const std::string s = error_of<InvalidArgument>([&] { save_grid(g, p); });
    check_has(s, {p.string(), "no extension", ".raw", ".vox"});
  }
}

TEST_CASE("readers read only regular files: a FIFO or a link to a device is a FileError naming what it is") {
  TempDir dir;
  SUBCASE("a FIFO named x.raw is refused at once instead of blocking") {
    const fs::path fifo = dir / "x.raw";
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    const auto start = std::chrono::steady_clock::now();
    auto result = std::async(std::launch::async, [&] { return error_of<FileError>([&] { load_grid(fifo); }); });
    if (result.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
      // Unblock the reader (a writer opening the FIFO ends its open) before failing.
      const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd >= 0) ::close(fd);
      FAIL("load_grid blocked on a FIFO");
    }
    check_has(result.get(), {fifo.string(), "FIFO", "not a regular file"});
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(10));
    check_has(error_of<FileError>([&] { read_file_bytes(fifo); }), {"FIFO"});
  }
  SUBCASE("a symbolic link to /dev/zero named z.raw or z.vox is not read until memory runs out") {
    if (!fs::exists("/dev/zero")) return;
    for (const char* name : {"z.raw", "z.vox", "z.RAW"}) {
      const fs::path link = dir / name;
      fs::create_symlink("/dev/zero", link);
      const std::string m = error_of<FileError>([&] { load_grid(link); });
      check_has(m, {link.string(), "a symbolic link to '/dev/zero'", "a character device", "not a regular file"});
    }
  }
  SUBCASE("a directory") {
    check_has(error_of<FileError>([&] { read_file_bytes(dir.path()); }), {"a directory", std::strerror(EISDIR)});
  }
  SUBCASE("a file larger than the reader's limit") {
    const fs::path p = dir / "big.bin";
    write_bytes(p, std::vector<std::uint8_t>(100, 1));
    check_has(error_of<FileError>([&] { read_file_bytes(p, 99); }), {p.string(), "100 bytes", "more than"});
    CHECK(read_file_bytes(p, 100).size() == 100);
  }
}

TEST_CASE("is_grid_file and check_grid_save_path judge the path before any work") {
  TempDir dir;
  CHECK(is_grid_file("a.raw"));
  CHECK(is_grid_file("dir/A.VOX"));
  CHECK(is_grid_file("b.Raw"));
  CHECK_FALSE(is_grid_file("a.json"));
  CHECK_FALSE(is_grid_file("raw"));
  CHECK_NOTHROW(check_grid_save_path(dir / "out.raw"));
  CHECK_NOTHROW(check_grid_save_path(dir / "OUT.VOX"));
  check_has(error_of<InvalidArgument>([&] { check_grid_save_path(dir / "out.txt"); }), {"'.txt'", ".raw and .vox"});
  check_has(error_of<FileError>([&] { check_grid_save_path(dir / "missing" / "out.raw"); }),
            {"missing", std::strerror(ENOENT)});
  fs::create_directory(dir / "taken.raw");
  check_has(error_of<FileError>([&] { check_grid_save_path(dir / "taken.raw"); }), {"taken.raw", "is a directory"});
  const fs::path ro = dir / "readonly";
  fs::create_directory(ro);
  fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
  if (access(ro.c_str(), W_OK) != 0)
    check_has(error_of<FileError>([&] { check_grid_save_path(ro / "out.raw"); }), {"not writable"});
  fs::permissions(ro, fs::perms::owner_all);
}

TEST_CASE("saving through a symbolic link writes its target and keeps the link") {
  TempDir dir;
  const Grid g = random_grid({5, 4, 3}, 11);
  fs::create_directory(dir / "real");
  const fs::path target = dir / "real" / "target.raw";
  write_bytes(target, {'o', 'l', 'd'});
  fs::permissions(target, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  const fs::path link = dir / "link.raw";
  fs::create_symlink(fs::path("real") / "target.raw", link);  // relative, from the link's directory
  save_grid(g, link);
  CHECK(fs::is_symlink(link));
  CHECK(fs::read_symlink(link) == fs::path("real") / "target.raw");
  CHECK(file_bytes(target) == encode_raw(g));
  CHECK(fs::status(target).permissions() == (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read));
  CHECK(std::distance(fs::directory_iterator(dir / "real"), fs::directory_iterator()) == 1);  // no temporary left
  CHECK(load_grid(link).hash() == g.hash());

  SUBCASE("a chain of links and a dangling link") {
    const fs::path chain = dir / "chain.vox";
    fs::create_symlink(dir / "dangling.vox", chain);
    save_grid(g, chain);
    CHECK(fs::is_symlink(chain));
    CHECK(fs::is_regular_file(fs::symlink_status(dir / "dangling.vox")));
    CHECK(load_grid(chain).hash() == g.hash());
  }
  SUBCASE("a loop of links is a FileError") {
    fs::create_symlink(dir / "b.raw", dir / "a.raw");
    fs::create_symlink(dir / "a.raw", dir / "b.raw");
    check_has(error_of<FileError>([&] { save_grid(g, dir / "a.raw"); }), {"a.raw", "symbolic links"});
  }
}

TEST_CASE("remove_pending_temporaries removes the temporary of a write interrupted by a signal") {
  // A child process writes more than its RLIMIT_FSIZE allows: the kernel sends SIGXFSZ in the
  // middle of write_file_atomic, whose handler calls remove_pending_temporaries and exits 3.
  TempDir dir;
  const fs::path target = dir / "interrupted.raw";
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    struct sigaction action {};
    action.sa_handler = [](int) {
      remove_pending_temporaries();
      _exit(3);
    };
    sigemptyset(&action.sa_mask);
    sigaction(SIGXFSZ, &action, nullptr);
    const rlimit limit{1 << 16, 1 << 16};
    setrlimit(RLIMIT_FSIZE, &limit);
    const std::vector<std::uint8_t> big(std::size_t(1) << 20, 1);
    try {
      write_file_atomic(target, {big});
    } catch (...) {
      _exit(4);
    }
    _exit(5);
  }
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 3);
  CHECK(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()) == 0);
}

TEST_CASE("load_grid reports a lossy .vox import as a notice") {
  TempDir dir;
  Grid g({4, 4, 4});
  g.set({0, 0, 0}, Material::Solid);
  g.set({1, 0, 0}, Material::Granular);
  auto bytes = encode_vox(g);
  // Rewrite the two voxels' palette indices to 0 and 200 (XYZI content follows its 12-byte header and count).
  const std::string xyzi = "XYZI";
  const auto at = std::search(bytes.begin(), bytes.end(), xyzi.begin(), xyzi.end());
  REQUIRE(at != bytes.end());
  const std::size_t first = std::size_t(at - bytes.begin()) + 12 + 4;
  bytes[first + 3] = 0;
  bytes[first + 7] = 200;
  const fs::path p = dir / "lossy.vox";
  write_bytes(p, bytes);
  std::vector<std::string> notices;
  const Grid back = load_grid(p, &notices);
  CHECK(back.count()[to_cell(Material::Solid)] == 2);
  REQUIRE(notices.size() == 1);
  check_has(notices[0], {p.string(), "2 of 2 voxels", "(0, 200)", "imported as solid", "1..7"});
  std::vector<std::string> none;
  save_grid(g, dir / "clean.vox");
  load_grid(dir / "clean.vox", &none);
  CHECK(none.empty());
}
