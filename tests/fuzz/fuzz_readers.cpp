#include "fuzz_readers.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <cctype>
#include <span>
#include <string_view>

#ifndef GRANULAR_FUZZ_READERS_ONLY
#include "granular/distributed/distributed_world.hpp"
#include "granular/distributed/local_group.hpp"
#endif
#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "granular/scene.hpp"
#include "granular/vox_io.hpp"
#include "granular/world_snapshot.hpp"

namespace {

std::string g_outcome;

/// A granular error's message with digits and quoted text dropped, cut to 48 characters: inputs
/// failing the same check with other values still count as one outcome.
std::string outcome_of(std::string_view message) {
  std::string out;
  char quote = 0;
  for (char c : message) {
    if (out.size() >= 48) break;
    if (quote) {
      if (c == quote) quote = 0;
      continue;
    }
    if (c == '\'' || c == '"') {
      quote = c;
      continue;
    }
    if (std::isdigit(static_cast<unsigned char>(c))) continue;
    out += c;
  }
  return out;
}

/// Runs one reader; granular::Error is an expected outcome, anything else propagates.
template <class F>
void read_with(const char* reader, F&& f) {
  g_outcome += reader;
  try {
    f();
    g_outcome += ": ok; ";
  } catch (const granular::Error& e) {
    const std::string_view m = e.what();
    // Messages start with the source name; the outcome is what follows it.
    const auto colon = m.find(": ");
    g_outcome += ": " + outcome_of(colon == std::string_view::npos ? m : m.substr(colon + 2)) + "; ";
  }
}

/// A memory file holding the input, read through /proc/self/fd like a path (a regular file).
class MemoryFile {
 public:
  MemoryFile(const std::uint8_t* data, std::size_t size) {
    fd_ = memfd_create("granular-fuzz", MFD_CLOEXEC);
    if (fd_ < 0) return;
    std::size_t done = 0;
    while (done < size) {
      const ssize_t n = ::write(fd_, data + done, size - done);
      if (n <= 0) break;
      done += std::size_t(n);
    }
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  ~MemoryFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;
  bool ok() const { return fd_ >= 0; }
  const std::string& path() const { return path_; }

 private:
  int fd_ = -1;
  std::string path_;
};

/// Instantiates a parsed scene at its smallest N when that grid is small (bounded time per input).
void instantiate_small(const granular::Scene& scene) {
  const granular::Int3 s = granular::scene_size(scene, scene.min_n);
  if (std::int64_t(s.x) * s.y * s.z <= (std::int64_t(1) << 18)) granular::instantiate(scene, scene.min_n);
}

#ifndef GRANULAR_FUZZ_READERS_ONLY
/// The grid a snapshot's header declares, in cells (0 when the input is too short to say).
std::uint64_t declared_snapshot_cells(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 20) return 0;
  std::uint64_t cells = 1;
  for (std::size_t at = 8; at < 20; at += 4)
    cells *= std::uint64_t(bytes[at]) | std::uint64_t(bytes[at + 1]) << 8 | std::uint64_t(bytes[at + 2]) << 16 |
             std::uint64_t(bytes[at + 3]) << 24;
  return cells;
}

/// Reads a snapshot file over 2 in-process ranks (DistributedWorld's reader: each rank checks the
/// file and header and decompresses its slab's part), when its header declares a small grid
/// (bounded time per input).
void read_split(std::span<const std::uint8_t> bytes, const std::string& path) {
  const std::uint64_t cells = declared_snapshot_cells(bytes);
  if (cells == 0 || cells > (std::uint64_t(1) << 18)) return;
  granular::WorldDef def;
  def.rules = "inertial-24";
  def.threads = 1;
  granular::run_local_ranks(2, [&](granular::Communicator& comm) { granular::DistributedWorld world(def, comm, path); });
}
#endif

}  // namespace

const std::string& fuzz_last_outcome() { return g_outcome; }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  g_outcome.clear();
  const std::span<const std::uint8_t> bytes(data, size);
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  read_with("decode_raw", [&] { granular::decode_raw(bytes, "fuzz.raw"); });
  read_with("decode_vox", [&] {
    granular::VoxImportReport report;
    granular::decode_vox(bytes, "fuzz.vox", &report);
    granular::vox_import_notice(report, "fuzz.vox");
  });
  read_with("parse_scene", [&] { instantiate_small(granular::parse_scene(text, "fuzz.json")); });
  read_with("decode_snapshot", [&] { granular::decode_snapshot(bytes, "fuzz.gsnap"); });
  const MemoryFile file(data, size);
  if (file.ok()) {
    read_with("load_raw", [&] { granular::load_raw(file.path()); });
    read_with("load_vox", [&] { granular::load_vox(file.path()); });
    read_with("load_scene", [&] { granular::load_scene(file.path()); });
    read_with("load_snapshot", [&] { granular::load_snapshot(file.path()); });
#ifndef GRANULAR_FUZZ_READERS_ONLY
    read_with("distributed_snapshot", [&] { read_split(bytes, file.path()); });
#endif
  }
  return 0;
}
