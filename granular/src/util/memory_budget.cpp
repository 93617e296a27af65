#include "granular/extend/memory_budget.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include "granular/errors.hpp"

namespace granular {

namespace {

/// The first line of a small file ("" when it cannot be read).
std::string first_line(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

/// A decimal unsigned integer at the start of `s` (leading spaces skipped).
std::optional<std::uint64_t> leading_number(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  std::uint64_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr == s.data()) return std::nullopt;
  return v;
}

/// The value of "<key>:  123 kB" in a /proc status-style file, in bytes.
std::optional<std::uint64_t> proc_kib_field(const char* file, std::string_view key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() <= key.size() || line.compare(0, key.size(), key) != 0 || line[key.size()] != ':') continue;
    const auto v = leading_number(std::string_view(line).substr(key.size() + 1));
    if (v && *v <= UINT64_MAX / 1024) return *v * 1024;
    return std::nullopt;
  }
  return std::nullopt;
}

/// The value of "<key> 123" in a cgroup memory.stat file.
std::optional<std::uint64_t> stat_field(const std::filesystem::path& file, std::string_view key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.size() > key.size() && line.compare(0, key.size(), key) == 0 && line[key.size()] == ' ')
      return leading_number(std::string_view(line).substr(key.size() + 1));
  return std::nullopt;
}

/// Usage of a cgroup without the inactive page cache, which the kernel reclaims before failing
/// an allocation (as container runtimes compute a working set).
std::uint64_t working_set(std::uint64_t usage, std::optional<std::uint64_t> inactive_file) {
  return inactive_file && *inactive_file < usage ? usage - *inactive_file : usage;
}

/// The tightest memory limit (limit - usage) on the cgroup path of this process, v2 or v1.
void read_cgroup(MemorySources& s) {
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  std::optional<std::uint64_t> best_room;
  auto consider = [&](std::uint64_t limit, std::uint64_t usage) {
    const std::uint64_t room = usage < limit ? limit - usage : 0;
    if (!best_room || room < *best_room) {
      best_room = room;
      s.cgroup_limit = limit;
      s.cgroup_usage = usage;
    }
  };
  while (std::getline(in, line)) {
    const auto first = line.find(':');
    const auto second = first == std::string::npos ? std::string::npos : line.find(':', first + 1);
    if (second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    const std::filesystem::path rel = std::filesystem::path(line.substr(second + 1)).relative_path();
    const bool v2 = line.compare(0, first, "0") == 0 && controllers.empty();
    const bool v1 = !v2 && ("," + controllers + ",").find(",memory,") != std::string::npos;
    if (!v2 && !v1) continue;
    const std::filesystem::path root = v2 ? "/sys/fs/cgroup" : "/sys/fs/cgroup/memory";
    for (std::filesystem::path dir = root / rel;; dir = dir.parent_path()) {
      if (v2) {
        const auto limit = leading_number(first_line(dir / "memory.max"));  // "max": no limit
        const auto usage = leading_number(first_line(dir / "memory.current"));
        if (limit && usage) consider(*limit, working_set(*usage, stat_field(dir / "memory.stat", "inactive_file")));
      } else {
        const auto limit = leading_number(first_line(dir / "memory.limit_in_bytes"));
        const auto usage = leading_number(first_line(dir / "memory.usage_in_bytes"));
        // v1 reports "no limit" as a huge page-aligned value near 2^63.
        if (limit && usage && *limit < (std::uint64_t(1) << 62))
          consider(*limit, working_set(*usage, stat_field(dir / "memory.stat", "total_inactive_file")));
      }
      if (dir == root || !dir.has_relative_path() || dir.parent_path() == dir) break;
    }
  }
}

/// The name of the variable that caps the budget.
constexpr const char* kLimitVariable = "GRANULAR_MEMORY_LIMIT";

std::optional<std::uint64_t> rlimit_of(int resource) {
  rlimit r{};
  if (getrlimit(resource, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return std::nullopt;
  return std::uint64_t(r.rlim_cur);
}

}  // namespace

std::string format_bytes(double b) {
  std::ostringstream s;
  s.precision(3);
  if (b >= 1024.0 * 1024 * 1024 * 1024) s << b / (1024.0 * 1024 * 1024 * 1024) << " TiB";
  else if (b >= 1024.0 * 1024 * 1024) s << b / (1024.0 * 1024 * 1024) << " GiB";
  else if (b >= 1024.0 * 1024) s << b / (1024.0 * 1024) << " MiB";
  else s << std::uint64_t(b) << " bytes";
  return s.str();
}

MemoryBudget memory_budget(const MemorySources& s) {
  MemoryBudget best;
  auto consider = [&](std::uint64_t room, std::string why) {
    if (best.limited_by.empty() || room < best.bytes) {
      best.bytes = room;
      best.limited_by = std::move(why);
    }
  };
  auto room = [](std::uint64_t limit, std::optional<std::uint64_t> used) {
    return used ? (*used < limit ? limit - *used : 0) : limit;
  };
  auto in_use = [](std::optional<std::uint64_t> used) {
    return used ? ", " + format_bytes(double(*used)) + " in use" : std::string();
  };
  if (s.mem_available)
    consider(*s.mem_available, "the system's available memory (MemAvailable in /proc/meminfo)");
  else if (s.physical)
    consider(*s.physical, "the machine's physical memory");
  if (s.cgroup_limit)
    consider(room(*s.cgroup_limit, s.cgroup_usage),
             "the cgroup's memory limit of " + format_bytes(double(*s.cgroup_limit)) + in_use(s.cgroup_usage));
  if (s.address_space_limit)
    consider(room(*s.address_space_limit, s.address_space_used),
             "ulimit -v (RLIMIT_AS) of " + format_bytes(double(*s.address_space_limit)) + in_use(s.address_space_used));
  if (s.data_limit)
    consider(room(*s.data_limit, s.data_used),
             "ulimit -d (RLIMIT_DATA) of " + format_bytes(double(*s.data_limit)) + in_use(s.data_used));
  if (s.user_limit) consider(*s.user_limit, "$" + std::string(kLimitVariable) + " = " + format_bytes(double(*s.user_limit)));
  return best;
}

std::optional<std::uint64_t> parse_byte_count(std::string_view text) {
  std::uint64_t shift = 0;
  if (!text.empty()) {
    switch (text.back()) {
      case 'K': case 'k': shift = 10; break;
      case 'M': case 'm': shift = 20; break;
      case 'G': case 'g': shift = 30; break;
      case 'T': case 't': shift = 40; break;
      default: break;
    }
    if (shift) text.remove_suffix(1);
  }
  if (text.empty() || text.find_first_not_of("0123456789") != std::string_view::npos) return std::nullopt;
  std::uint64_t v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || v > (UINT64_MAX >> shift)) return std::nullopt;
  return v << shift;
}

MemorySources read_memory_sources() {
  MemorySources s;
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page_size > 0) s.physical = std::uint64_t(pages) * std::uint64_t(page_size);
  s.mem_available = proc_kib_field("/proc/meminfo", "MemAvailable");
  read_cgroup(s);
  s.address_space_limit = rlimit_of(RLIMIT_AS);
  if (s.address_space_limit) s.address_space_used = proc_kib_field("/proc/self/status", "VmSize");
  s.data_limit = rlimit_of(RLIMIT_DATA);
  if (s.data_limit) s.data_used = proc_kib_field("/proc/self/status", "VmData");
  if (const char* env = std::getenv(kLimitVariable); env && *env) {
    s.user_limit = parse_byte_count(env);
    if (!s.user_limit)
      throw InvalidArgument(std::string(kLimitVariable) + "='" + std::string(env).substr(0, 40) +
                            "' is not a byte count; use a number of bytes with an optional K, M, G or T suffix");
  }
  return s;
}

MemoryBudget available_memory() { return memory_budget(read_memory_sources()); }

}  // namespace granular
