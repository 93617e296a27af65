#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>

#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "granular/extend/memory_budget.hpp"
#include "io/file_names.hpp"
#include "granular/vox_io.hpp"
#include "io/little_endian.hpp"
#include "io/regular_file.hpp"

namespace granular {

namespace {

std::string system_reason(int err) { return std::strerror(err); }

constexpr const char* kHeaderFields[5] = {"magic", "version", "nx", "ny", "nz"};

/// Validates the raw header held in the first bytes of `head` for a file of `total` bytes and
/// returns the grid size it declares.
Int3 parse_raw_header(std::span<const std::uint8_t> head, std::uint64_t total, const std::string& src) {
  const std::size_t magic_have = std::size_t(std::min<std::uint64_t>(total, 4));
  if (!std::equal(head.begin(), head.begin() + std::ptrdiff_t(magic_have), kRawMagic)) {
    throw ParseError(src + ": not a raw grid file: bad magic " + printable_bytes(head.first(magic_have)) +
                     " at byte 0 (expected \"GRAW\")");
  }
  if (total < kRawHeaderSize) {
    const std::size_t field = std::size_t(total / 4);
    throw ParseError(src + ": truncated header: the file has " + std::to_string(total) +
                     " bytes and ends inside field " + kHeaderFields[field] + " (bytes " + std::to_string(field * 4) +
                     ".." + std::to_string(field * 4 + 3) + "); a raw grid header is " +
                     std::to_string(kRawHeaderSize) + " bytes (magic, version, nx, ny, nz)");
  }
  const std::uint32_t version = get_u32(head, 4);
  if (version != kRawVersion)
    throw ParseError(src + ": unsupported raw grid version " + std::to_string(version) +
                     " (field version, bytes 4..7); this build reads version " + std::to_string(kRawVersion));
  std::uint32_t dims[3];
  for (int a = 0; a < 3; ++a) {
    dims[a] = get_u32(head, 8 + 4 * std::size_t(a));
    if (dims[a] > std::uint32_t(INT_MAX))
      throw ParseError(src + ": header field " + kHeaderFields[2 + a] + " (bytes " + std::to_string(8 + 4 * a) + ".." +
                       std::to_string(11 + 4 * a) + ") = " + std::to_string(dims[a]) + " exceeds the maximum extent " +
                       std::to_string(kMaxGridExtent));
  }
  const Int3 size{int(dims[0]), int(dims[1]), int(dims[2])};
  const std::string fields = src + ": header fields nx, ny, nz (bytes 8..19)";
  try {
    check_grid_extents(size, fields);  // the body's length is checked before the memory
  } catch (const InvalidArgument& e) {
    throw ParseError(e.what());
  }
  const std::uint64_t cells = std::uint64_t(dims[0]) * dims[1] * dims[2];
  const std::uint64_t body = total - kRawHeaderSize;
  if (body < cells)
    throw ParseError(src + ": truncated body: header says " + to_string(size) + " = " + std::to_string(cells) +
                     " cells but only " + std::to_string(body) + " bytes follow the " + std::to_string(kRawHeaderSize) +
                     "-byte header");
  if (body > cells)
    throw ParseError(src + ": " + std::to_string(body - cells) + " trailing bytes after the last cell: header says " +
                     to_string(size) + " = " + std::to_string(cells) + " cells, so the file should be " +
                     std::to_string(cells + kRawHeaderSize) + " bytes but it is " + std::to_string(total));
  check_grid_size(size, fields);
  return size;
}

/// Throws ParseError naming the first cell whose value is not a material.
void check_raw_cells(std::span<const std::uint8_t> cells, Int3 size, const std::string& src) {
  const auto bad = [](std::uint8_t v) { return !is_valid_material_value(v); };
  const auto first = std::find_if(cells.begin(), cells.end(), bad);
  if (first == cells.end()) return;
  const std::size_t i = std::size_t(first - cells.begin());
  const std::size_t plane = std::size_t(size.x) * std::size_t(size.y);
  const std::size_t x = i % std::size_t(size.x), y = (i / std::size_t(size.x)) % std::size_t(size.y), z = i / plane;
  const auto total = std::count_if(first, cells.end(), bad);
  throw ParseError(src + ": invalid cell value " + std::to_string(unsigned(*first)) + " at byte offset " +
                   std::to_string(kRawHeaderSize + i) + " (cell x=" + std::to_string(x) + ", y=" + std::to_string(y) +
                   ", z=" + std::to_string(z) + "); cell values must be 0.." + std::to_string(kMaterialCount - 1) +
                   " (" + std::to_string(total) + " invalid cells in total)");
}

std::array<std::uint8_t, kRawHeaderSize> raw_header(const Grid& grid, const char* caller) {
  if (grid.cell_count() == 0)
    throw InvalidArgument(std::string(caller) + ": the grid is empty (" + to_string(grid.size()) +
                          "); there is nothing to encode");
  std::array<std::uint8_t, kRawHeaderSize> h{};
  std::copy(std::begin(kRawMagic), std::end(kRawMagic), h.begin());
  put_u32(h.data() + 4, kRawVersion);
  put_u32(h.data() + 8, std::uint32_t(grid.size().x));
  put_u32(h.data() + 12, std::uint32_t(grid.size().y));
  put_u32(h.data() + 16, std::uint32_t(grid.size().z));
  return h;
}

/// Removes the temporary file of a failed atomic write and throws the FileError describing it.
[[noreturn]] void fail_atomic_write(const std::filesystem::path& path, const std::filesystem::path& tmp,
                                    const std::string& step, int err) {
  std::error_code ignored;
  std::filesystem::remove(tmp, ignored);
  const bool kept = std::filesystem::exists(path, ignored);
  throw FileError("cannot write " + quoted(path) + ": " + step + ": " + system_reason(err) +
                  (kept ? " (the existing file was left untouched)" : ""));
}

enum class GridFormat { Raw, Vox };

GridFormat format_of(const std::filesystem::path& path, const char* action) {
  const std::string ext = lower_extension(path);
  if (ext == ".raw") return GridFormat::Raw;
  if (ext == ".vox") return GridFormat::Vox;
  const std::string what =
      ext.empty() ? "has no extension" : "has the unknown extension '" + path.extension().string() + "'";
  throw InvalidArgument(std::string("cannot ") + action + " grid " + quoted(path) + ": the file name " + what +
                        "; accepted grid file extensions are .raw and .vox");
}

/// Symbolic links followed in a row before giving up (the kernel's limit, ELOOP).
constexpr int kMaxSymlinkHops = 40;

/// Temporary files of atomic writes in progress, for remove_pending_temporaries(), which a signal
/// handler calls: fixed slots, no allocation, lock-free atomics only.
constexpr int kSlotFree = 0, kSlotClaimed = 1, kSlotActive = 2;
constexpr std::size_t kTempPathMax = 4096;
struct TempSlot {
  std::atomic<int> state{kSlotFree};
  char path[kTempPathMax] = {};
};
TempSlot g_temp_slots[8];
static_assert(std::atomic<int>::is_always_lock_free, "signal handlers need lock-free atomics");

/// Registers a temporary path for the lifetime of the object (nothing when every slot is taken or
/// the path is too long: the write still works, only a signal would leave the file behind).
class TempRegistration {
 public:
  explicit TempRegistration(const std::filesystem::path& tmp) {
    const std::string& s = tmp.native();
    if (s.size() >= kTempPathMax) return;
    for (TempSlot& slot : g_temp_slots) {
      int expected = kSlotFree;
      if (!slot.state.compare_exchange_strong(expected, kSlotClaimed, std::memory_order_acq_rel)) continue;
      std::memcpy(slot.path, s.c_str(), s.size() + 1);
      slot.state.store(kSlotActive, std::memory_order_release);
      slot_ = &slot;
      return;
    }
  }
  ~TempRegistration() {
    if (slot_) slot_->state.store(kSlotFree, std::memory_order_release);
  }
  TempRegistration(const TempRegistration&) = delete;
  TempRegistration& operator=(const TempRegistration&) = delete;

 private:
  TempSlot* slot_ = nullptr;
};

}  // namespace

std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path, std::uint64_t max_bytes) {
  const ReadableFile file(path);
  const std::uint64_t size = file.size();
  if (size > max_bytes)
    throw FileError("cannot read " + quoted(path) + ": it is " + std::to_string(size) + " bytes (" +
                    format_bytes(double(size)) + "), more than the " + format_bytes(double(max_bytes)) +
                    " this reader accepts");
  const MemoryBudget budget = available_memory();
  if (!budget.limited_by.empty() && size > budget.bytes)
    throw OutOfMemory("cannot read " + quoted(path) + ": its " + std::to_string(size) + " bytes (" +
                      format_bytes(double(size)) + ") exceed the " + format_bytes(double(budget.bytes)) +
                      " that can be allocated (limited by " + budget.limited_by + ")");
  std::vector<std::uint8_t> bytes;
  try {
    bytes.resize(std::size_t(size));
  } catch (const std::exception&) {
    throw OutOfMemory("cannot read " + quoted(path) + ": not enough memory to hold its " + std::to_string(size) +
                      " bytes");
  }
  file.read_at(0, bytes);
  return bytes;
}

bool is_grid_file(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".raw" || ext == ".vox";
}

std::filesystem::path resolve_symlinks(const std::filesystem::path& path) {
  std::filesystem::path p = path;
  for (int hops = 0; hops <= kMaxSymlinkHops; ++hops) {
    struct stat info {};
    if (::lstat(p.c_str(), &info) != 0 || !S_ISLNK(info.st_mode)) return p;
    std::error_code ec;
    const std::filesystem::path target = std::filesystem::read_symlink(p, ec);
    if (ec) throw FileError("cannot resolve the symbolic link " + quoted(p) + ": " + ec.message());
    p = target.is_absolute() ? target : p.parent_path() / target;
  }
  throw FileError("cannot resolve " + quoted(path) + ": more than " + std::to_string(kMaxSymlinkHops) +
                  " symbolic links in a row (" + system_reason(ELOOP) + ")");
}

void check_grid_save_path(const std::filesystem::path& path) {
  format_of(path, "save");
  check_save_target(path);
}

void remove_pending_temporaries() noexcept {
  for (TempSlot& slot : g_temp_slots)
    if (slot.state.load(std::memory_order_acquire) == kSlotActive) ::unlink(slot.path);
}

void write_file_atomic(const std::filesystem::path& path, std::initializer_list<std::span<const std::uint8_t>> parts) {
  // Through a symbolic link the link stays and its target is replaced, beside which the temporary lies.
  const std::filesystem::path target = resolve_symlinks(path);
  check_replaceable(path, target);
  std::filesystem::path tmp = target;
  tmp += ".tmp-" + std::to_string(getpid());
  struct stat old {};
  const bool replacing = ::stat(target.c_str(), &old) == 0 && S_ISREG(old.st_mode);
  const TempRegistration registration(tmp);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) {
    const int err = errno;
    if (err == EEXIST)  // not ours: a leftover of another process; leave it alone
      throw FileError("cannot write " + quoted(path) + ": the temporary file " + quoted(tmp) +
                      " already exists (a leftover of an interrupted write? remove it)");
    fail_atomic_write(path, tmp, "cannot create the temporary file " + quoted(tmp), err);
  }
  if (replacing) (void)::fchmod(fd, old.st_mode & 07777);  // keep the replaced file's permissions
  std::FILE* f = fdopen(fd, "wb");
  if (!f) {
    const int err = errno;
    ::close(fd);
    fail_atomic_write(path, tmp, "cannot open the temporary file " + quoted(tmp), err);
  }
  for (std::span<const std::uint8_t> part : parts) {
    if (part.empty()) continue;
    if (std::fwrite(part.data(), 1, part.size(), f) != part.size()) {
      const int err = errno;
      std::fclose(f);
      fail_atomic_write(path, tmp, "writing the temporary file " + quoted(tmp) + " failed", err);
    }
  }
  if (std::fflush(f) != 0 || fsync(fileno(f)) != 0) {
    const int err = errno;
    std::fclose(f);
    fail_atomic_write(path, tmp, "flushing the temporary file " + quoted(tmp) + " failed", err);
  }
  if (std::fclose(f) != 0) {
    const int err = errno;
    fail_atomic_write(path, tmp, "closing the temporary file " + quoted(tmp) + " failed", err);
  }
  if (std::rename(tmp.c_str(), target.c_str()) != 0) {
    const int err = errno;
    fail_atomic_write(path, tmp, "renaming the temporary file " + quoted(tmp) + " over it failed", err);
  }
}

std::vector<std::uint8_t> encode_raw(const Grid& grid) {
  const auto header = raw_header(grid, "encode_raw");
  const auto cells = grid.cells();
  std::vector<std::uint8_t> out;
  try {
    out.resize(header.size() + cells.size());
  } catch (const std::bad_alloc&) {
    throw OutOfMemory("encode_raw: could not allocate " + std::to_string(header.size() + cells.size()) +
                      " bytes for a " + to_string(grid.size()) + " grid");
  }
  std::memcpy(out.data(), header.data(), header.size());
  if (!cells.empty()) std::memcpy(out.data() + header.size(), cells.data(), cells.size());
  return out;
}

Grid decode_raw(std::span<const std::uint8_t> bytes, const std::string& source_name) {
  const Int3 size = parse_raw_header(bytes.first(std::min(bytes.size(), kRawHeaderSize)), bytes.size(), source_name);
  const auto body = bytes.subspan(kRawHeaderSize);
  check_raw_cells(body, size, source_name);
  Grid grid(size);
  std::copy(body.begin(), body.end(), grid.cells().begin());
  return grid;
}

void save_raw(const Grid& grid, const std::filesystem::path& path) {
  const auto header = raw_header(grid, "save_raw");
  write_file_atomic(path, {std::span<const std::uint8_t>(header), grid.cells()});
}

Grid load_raw(const std::filesystem::path& path) {
  const ReadableFile file(path);
  const std::string src = path.string();
  const std::uint64_t total = file.size();
  std::array<std::uint8_t, kRawHeaderSize> head{};
  const std::size_t head_size = std::size_t(std::min<std::uint64_t>(total, kRawHeaderSize));
  file.read_at(0, std::span(head).first(head_size));
  const Int3 size = parse_raw_header(std::span<const std::uint8_t>(head).first(head_size), total, src);
  Grid grid(size);
  file.read_at(kRawHeaderSize, grid.cells());
  check_raw_cells(grid.cells(), size, src);
  return grid;
}

void save_grid(const Grid& grid, const std::filesystem::path& path) {
  switch (format_of(path, "save")) {
    case GridFormat::Raw:
      save_raw(grid, path);
      return;
    case GridFormat::Vox:
      save_vox(grid, path);
      return;
  }
}

Grid load_grid(const std::filesystem::path& path, std::vector<std::string>* notices) {
  switch (format_of(path, "load")) {
    case GridFormat::Raw:
      return load_raw(path);
    case GridFormat::Vox: {
      VoxImportReport report;
      Grid grid = load_vox(path, &report);
      const std::string notice = vox_import_notice(report, path.string());
      if (notices && !notice.empty()) notices->push_back(notice);
      return grid;
    }
  }
  return Grid();
}

}  // namespace granular
