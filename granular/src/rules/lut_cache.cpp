#include <unistd.h>
#include <zstd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include "granular/errors.hpp"
#include "granular/extend/hex.hpp"
#include "granular/extend/lut.hpp"

namespace granular {

namespace {

constexpr char kMagic[4] = {'G', 'L', 'U', 'T'};
constexpr std::uint32_t kFormatVersion = 1;

/// On-disk header, little-endian, followed by one zstd frame of the uint32 entries.
struct CacheHeader {
  char magic[4];
  std::uint32_t format_version;
  std::uint64_t rule_fingerprint;
  std::uint64_t content_hash;
  std::uint64_t entry_count;
  std::uint64_t compressed_bytes;
};
static_assert(sizeof(CacheHeader) == 40);

/// Reads and checks a cache file; returns nullptr (with `why`) when it cannot be trusted.
std::shared_ptr<const Lut> read_cache(const std::filesystem::path& file, std::uint64_t fingerprint, std::uint8_t fixed,
                                      int threads, std::string& why) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return nullptr;  // no cache yet: not worth a notice
  CacheHeader h{};
  if (!in.read(reinterpret_cast<char*>(&h), sizeof h) || std::memcmp(h.magic, kMagic, 4) != 0 ||
      h.format_version != kFormatVersion) {
    why = "bad header";
    return nullptr;
  }
  if (h.rule_fingerprint != fingerprint || h.entry_count != kBlockKeyCount || h.compressed_bytes > (1ull << 31)) {
    why = "header does not match this rule set";
    return nullptr;
  }
  std::vector<char> packed(h.compressed_bytes);
  if (!in.read(packed.data(), std::streamsize(packed.size()))) {
    why = "truncated";
    return nullptr;
  }
  std::vector<Transition> entries(kBlockKeyCount);
  const std::size_t got = ZSTD_decompress(entries.data(), entries.size() * sizeof(Transition), packed.data(), packed.size());
  if (ZSTD_isError(got) || got != entries.size() * sizeof(Transition)) {
    why = "corrupt compressed data";
    return nullptr;
  }
  try {
    auto lut = std::make_shared<const Lut>(Lut::from_entries(std::move(entries), fingerprint, threads, fixed));
    if (lut->content_hash() != h.content_hash) {
      why = "content hash mismatch";
      return nullptr;
    }
    return lut;
  } catch (const RuleError& e) {
    why = e.what();
    return nullptr;
  }
}

/// Writes the cache atomically (temp file + rename). Returns an error description or "".
std::string write_cache(const std::filesystem::path& file, const Lut& lut) {
  std::error_code ec;
  std::filesystem::create_directories(file.parent_path(), ec);
  if (ec) return "cannot create " + file.parent_path().string() + ": " + ec.message();
  const auto entries = lut.entries();
  std::vector<char> packed(ZSTD_compressBound(entries.size_bytes()));
  const std::size_t n = ZSTD_compress(packed.data(), packed.size(), entries.data(), entries.size_bytes(), 3);
  if (ZSTD_isError(n)) return std::string("compression failed: ") + ZSTD_getErrorName(n);
  CacheHeader h{};
  std::memcpy(h.magic, kMagic, 4);
  h.format_version = kFormatVersion;
  h.rule_fingerprint = lut.rule_fingerprint();
  h.content_hash = lut.content_hash();
  h.entry_count = entries.size();
  h.compressed_bytes = n;
  const auto tmp = std::filesystem::path(file.string() + ".tmp-" + std::to_string(::getpid()));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
    out.write(packed.data(), std::streamsize(n));
    out.close();
    if (!out) {
      std::filesystem::remove(tmp, ec);
      return "cannot write " + tmp.string();
    }
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    return "cannot rename into " + file.string();
  }
  return {};
}

}  // namespace

std::filesystem::path default_lut_cache_dir() {
  if (const char* d = std::getenv("GRANULAR_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return std::filesystem::path(d) / "granular";
  if (const char* d = std::getenv("HOME"); d && *d) return std::filesystem::path(d) / ".cache" / "granular";
  return {};
}

namespace {

/// The cache file of a rule set named `name`: "lut-NAME-FINGERPRINT.zst" in `dir`, where NAME keeps
/// the name's letters, digits, '-', '_' and '.' (every other byte is '_') up to 64 bytes, so no name
/// reaches outside `dir` ('/' and "\0" never appear); the fingerprint, which covers the whole name,
/// keeps two names that read alike apart.
std::filesystem::path cache_file(const std::string& name, std::uint64_t fingerprint, const std::filesystem::path& dir) {
  std::string readable = name.substr(0, 64);
  for (char& c : readable)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '.')) c = '_';
  return dir / ("lut-" + readable + "-" + hex64(fingerprint) + ".zst");
}

}  // namespace

std::filesystem::path lut_cache_file(const RuleSet& rules, const std::filesystem::path& directory) {
  return cache_file(rules.name, rule_fingerprint(rules), directory);
}

LutObtained obtain_lut(const RuleSet& rules, const LutCacheOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  validate_rule_set(rules);  // before its name becomes part of a file name
  LutObtained result;
  const std::uint64_t fingerprint = rule_fingerprint(rules);
  std::filesystem::path dir = options.directory.empty() ? default_lut_cache_dir() : options.directory;
  if (options.enabled && !dir.empty()) {
    result.cache_file = cache_file(rules.name, fingerprint, dir);
    std::string why;
    result.lut = read_cache(result.cache_file, fingerprint, fixed_states(rules), options.threads, why);
    if (result.lut) {
      result.from_cache = true;
      result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
      return result;
    }
    if (!why.empty()) result.notice = "transition table cache " + result.cache_file.string() + " ignored (" + why + "); rebuilt";
  }
  result.lut = std::make_shared<const Lut>(Lut::build(rules, options.threads));
  if (options.enabled && !result.cache_file.empty()) {
    const std::string err = write_cache(result.cache_file, *result.lut);
    if (!err.empty()) {
      result.notice = "transition table not cached: " + err;
      result.cache_file.clear();
    }
  }
  result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace granular
