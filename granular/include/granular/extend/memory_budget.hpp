#pragma once
/// @file extend/memory_budget.hpp
/// How many bytes this process may still allocate: the least of the system's available memory
/// (MemAvailable), the cgroup's memory limit (v2 memory.max, v1 memory.limit_in_bytes, minus what
/// the cgroup uses), the process's RLIMIT_AS and RLIMIT_DATA (minus what it has mapped) and
/// $GRANULAR_MEMORY_LIMIT (a cap a user or test sets without ulimit, which sanitizers cannot
/// run under). Grid sizes are checked against it before anything is allocated (check_grid_size).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace granular {

/// The figures memory_budget() combines, each absent when unknown or unlimited.
struct MemorySources {
  std::optional<std::uint64_t> physical;            ///< installed memory (sysconf pages x page size)
  std::optional<std::uint64_t> mem_available;       ///< MemAvailable of /proc/meminfo
  std::optional<std::uint64_t> cgroup_limit;        ///< the tightest cgroup memory limit on this process's path
  std::optional<std::uint64_t> cgroup_usage;        ///< that cgroup's current usage
  std::optional<std::uint64_t> address_space_limit; ///< RLIMIT_AS (ulimit -v)
  std::optional<std::uint64_t> address_space_used; ///< this process's mapped address space (VmSize)
  std::optional<std::uint64_t> data_limit;          ///< RLIMIT_DATA (ulimit -d)
  std::optional<std::uint64_t> data_used;           ///< this process's data mappings (VmData)
  std::optional<std::uint64_t> user_limit;          ///< $GRANULAR_MEMORY_LIMIT
};

/// The bytes that may still be allocated, and which limit decides it.
struct MemoryBudget {
  std::uint64_t bytes = UINT64_MAX;  ///< UINT64_MAX when nothing is known
  std::string limited_by;            ///< e.g. "ulimit -v (RLIMIT_AS) of 400 MiB, 12.5 MiB in use"; "" when unknown
};

/// The least of: mem_available (else physical), cgroup_limit - cgroup_usage, address_space_limit -
/// address_space_used, data_limit - data_used (each floored at 0), user_limit. A limit whose usage
/// is unknown counts as fully available.
MemoryBudget memory_budget(const MemorySources& sources);

/// Parses a byte count: decimal digits with an optional binary suffix K, M, G or T ("512M" is
/// 512 MiB); nullopt when malformed or too large.
std::optional<std::uint64_t> parse_byte_count(std::string_view text);

/// Reads the sources of this process from sysconf, /proc and /sys/fs/cgroup, getrlimit and
/// $GRANULAR_MEMORY_LIMIT. Throws InvalidArgument when that variable is set but not a byte count.
MemorySources read_memory_sources();

/// memory_budget(read_memory_sources()).
MemoryBudget available_memory();

/// Bytes for messages: "512 bytes", "1.5 MiB", "3.22 GiB", "16 TiB" (3 significant digits).
std::string format_bytes(double bytes);

}  // namespace granular
