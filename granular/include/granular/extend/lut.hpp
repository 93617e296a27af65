#pragma once
/// @file extend/lut.hpp
/// The transition table: one Transition per block key, all 8^8 keys (64 MiB as uint32).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "granular/extend/block.hpp"
#include "granular/rule_set.hpp"

namespace granular {

/// A built, validated transition table for one rule set.
class Lut {
 public:
  /// Evaluates the rule on all 16,777,216 keys with `threads` threads (0 = all; InvalidArgument
  /// past max_threads(), threads.hpp) and validates the result. Throws RuleError naming the first
  /// offending key.
  static Lut build(const RuleSet& rules, int threads = 0);
  /// Wraps entries read from elsewhere (the cache, a GPU build); validates them (RuleError) with
  /// `fixed` the states that must not move (fixed_states of the rule set; the default: solid only).
  static Lut from_entries(std::vector<Transition> entries, std::uint64_t rule_fingerprint, int threads = 0,
                          std::uint8_t fixed = kSolidFixed);
  /// The fixed states of a table whose only static material is solid.
  static constexpr std::uint8_t kSolidFixed = 1u << 1;

  /// The transition of a key.
  Transition operator[](BlockKey key) const { return entries_[key]; }
  /// All entries, indexed by key.
  std::span<const Transition> entries() const { return entries_; }
  /// Bytes the table occupies.
  std::size_t size_bytes() const { return entries_.size() * sizeof(Transition); }
  /// 64-bit hash of the table's content.
  std::uint64_t content_hash() const { return content_hash_; }
  /// Fingerprint of the rule set the table was built from (rule_fingerprint).
  std::uint64_t rule_fingerprint() const { return rule_fingerprint_; }
  /// Keys whose transition is not the identity.
  std::uint64_t moving_keys() const { return moving_keys_; }

 private:
  Lut() = default;
  void validate_and_summarise(int threads, std::uint8_t fixed);

  std::vector<Transition> entries_;
  std::uint64_t rule_fingerprint_ = 0;
  std::uint64_t content_hash_ = 0;
  std::uint64_t moving_keys_ = 0;
};

/// Checks one entry: a permutation that keeps every cell of a fixed state (bit s of `fixed` for state
/// s; fixed_states) in place. Returns an empty string when valid, else what is wrong.
std::string check_transition(BlockKey key, Transition t, std::uint8_t fixed = Lut::kSolidFixed);

/// Where and whether to cache tables on disk.
struct LutCacheOptions {
  bool enabled = true;             ///< read and write the cache
  std::filesystem::path directory; ///< empty = default_lut_cache_dir()
  int threads = 0;                 ///< threads for a build (0 = all)
};

/// How a table was obtained.
struct LutObtained {
  std::shared_ptr<const Lut> lut;       ///< the table
  bool from_cache = false;              ///< loaded rather than built
  double seconds = 0;                   ///< wall time to load or build (and validate)
  std::filesystem::path cache_file;     ///< the cache file used or written (empty when disabled)
  std::string notice;                   ///< a line for the user when the cache could not be used
};

/// $GRANULAR_CACHE_DIR, else $XDG_CACHE_HOME/granular, else $HOME/.cache/granular, else empty.
std::filesystem::path default_lut_cache_dir();

/// The cache file of `rules` in `directory`: lut-<name>-<fingerprint as hex64>.zst, where <name> is
/// the rule set's name cut to 64 bytes with every byte but letters, digits, '-', '_' and '.' made '_'
/// (always a file directly in `directory`).
std::filesystem::path lut_cache_file(const RuleSet& rules, const std::filesystem::path& directory);

/// Loads the table for `rules` from the cache when a valid entry exists, else builds, validates
/// and stores it (atomically; a cache that cannot be written is reported in `notice`, not fatal).
/// A corrupt or stale cache file is rebuilt, never trusted. Throws RuleError (validate_rule_set)
/// before any file is touched when `rules` cannot be stepped.
LutObtained obtain_lut(const RuleSet& rules, const LutCacheOptions& options = {});

}  // namespace granular
