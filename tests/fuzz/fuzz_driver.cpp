/// @file fuzz_driver.cpp
/// `granular_fuzz`: a deterministic, time-boxed mutation fuzzer for the readers (fuzz_readers.hpp)
/// that needs no libFuzzer, so it builds with GCC in every build. From a seed corpus it applies
/// seeded mutations (bit flips, byte sets, inserts, deletes, duplications, splices with other
/// inputs, interesting integers written over header and chunk-size fields, JSON, .vox and snapshot
/// tokens)
/// and keeps mutants whose outcome (which readers accepted them, which check refused them) it has
/// not seen before. Memory is capped ($GRANULAR_MEMORY_LIMIT for the library's checks, RLIMIT_AS
/// without AddressSanitizer, max_allocation_size_mb with it) and every input has a time limit.
///
///   granular_fuzz [--seconds S] [--runs N] [--corpus DIR]... [--seed N] [--max-len BYTES]
///                 [--memory-mib M] [--timeout S] [--crash-dir DIR] [FILE...]
///
/// With FILE arguments it runs just those inputs (to reproduce a finding). It ends with
/// "fuzz: <inputs> inputs in <s> s (<rate> inputs/s), ..., <n> crashes" and exits 1 when an input
/// crashed, hung or threw anything but a granular::Error (each saved to the crash folder).

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <typeinfo>
#include <unordered_set>
#include <vector>

#include "fuzz_readers.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define GRANULAR_FUZZ_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GRANULAR_FUZZ_ASAN 1
#endif
#endif

#ifdef GRANULAR_FUZZ_ASAN
#include <sanitizer/common_interface_defs.h>
/// Allocations larger than the fuzzer's cap are reported as findings (see --memory-mib).
extern "C" const char* __asan_default_options() { return "max_allocation_size_mb=2048"; }
#endif

namespace fs = std::filesystem;

namespace {

using Bytes = std::vector<std::uint8_t>;

struct Options {
  double seconds = 10;
  std::uint64_t runs = 0;  // 0: until the time is up
  std::vector<fs::path> corpus;
  std::uint64_t seed = 1;
  std::size_t max_len = 1 << 16;
  std::uint64_t memory_mib = 2048;
  unsigned timeout = 10;
  fs::path crash_dir = ".";
  std::vector<fs::path> files;
};

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "error: %s\nusage: granular_fuzz [--seconds S] [--runs N] [--corpus DIR]... [--seed N] [--max-len BYTES] "
               "[--memory-mib M] [--timeout S] [--crash-dir DIR] [FILE...]\n",
               why.c_str());
  std::exit(2);
}

std::uint64_t number(const char* option, const char* text) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text, &end, 10);
  if (!*text || *end || errno || text[0] == '-') usage(std::string(option) + " " + text + ": not a whole number");
  return v;
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) usage(std::string(a) + " needs a value");
      return argv[++i];
    };
    if (a == "--seconds") o.seconds = double(number("--seconds", value()));
    else if (a == "--runs") o.runs = number("--runs", value());
    else if (a == "--corpus") o.corpus.emplace_back(value());
    else if (a == "--seed") o.seed = number("--seed", value());
    else if (a == "--max-len") o.max_len = std::max<std::size_t>(1, number("--max-len", value()));
    else if (a == "--memory-mib") o.memory_mib = std::max<std::uint64_t>(64, number("--memory-mib", value()));
    else if (a == "--timeout") o.timeout = unsigned(std::max<std::uint64_t>(1, number("--timeout", value())));
    else if (a == "--crash-dir") o.crash_dir = value();
    else if (a.starts_with("--")) usage("unknown option " + std::string(a));
    else o.files.emplace_back(a);
  }
  return o;
}

// --- the input being run, for the crash handlers ------------------------------------------------

const std::uint8_t* g_input = nullptr;
std::size_t g_input_size = 0;
char g_crash_path[4096] = {};

/// Async-signal-safe: writes the current input to g_crash_path.
void save_current_input() {
  if (!g_input || !g_crash_path[0]) return;
  const int fd = ::open(g_crash_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return;
  std::size_t done = 0;
  while (done < g_input_size) {
    const ssize_t n = ::write(fd, g_input + done, g_input_size - done);
    if (n <= 0) break;
    done += std::size_t(n);
  }
  ::close(fd);
  const char note[] = "granular_fuzz: the input that crashed or hung is saved as ";
  (void)!::write(2, note, sizeof note - 1);
  (void)!::write(2, g_crash_path, std::strlen(g_crash_path));
  (void)!::write(2, "\n", 1);
}

extern "C" void on_fatal_signal(int sig) {
  if (sig == SIGALRM) {
    const char note[] = "granular_fuzz: an input ran past the --timeout\n";
    (void)!::write(2, note, sizeof note - 1);
  }
  save_current_input();
  signal(sig == SIGALRM ? SIGABRT : sig, SIG_DFL);
  raise(sig == SIGALRM ? SIGABRT : sig);
}

void install_crash_handlers() {
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM}) {
    struct sigaction action {};
    action.sa_handler = on_fatal_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;
    sigaction(sig, &action, nullptr);
  }
#ifdef GRANULAR_FUZZ_ASAN
  __sanitizer_set_death_callback(save_current_input);
#endif
}

/// Caps memory: the library's checks at half the cap, the address space (without ASan) at the cap
/// above what is mapped now.
void cap_memory(std::uint64_t mib) {
  const std::uint64_t bytes = mib << 20;
  if (!std::getenv("GRANULAR_MEMORY_LIMIT"))
    setenv("GRANULAR_MEMORY_LIMIT", (std::to_string(mib / 2) + "M").c_str(), 1);
#ifndef GRANULAR_FUZZ_ASAN
  std::uint64_t mapped = 0;
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmSize:", 0) == 0) mapped = std::strtoull(line.c_str() + 7, nullptr, 10) << 10;
  const rlimit limit{rlim_t(mapped + bytes), rlim_t(mapped + bytes)};
  setrlimit(RLIMIT_AS, &limit);
#endif
}

// --- mutations ------------------------------------------------------------------------------------

/// splitmix64: a small, fast, seeded generator (the same sequence on every platform).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, n), n >= 1.
  std::size_t below(std::size_t n) { return std::size_t(next() % n); }
  bool one_in(std::size_t n) { return below(n) == 0; }

 private:
  std::uint64_t state_;
};

constexpr std::uint32_t kInteresting32[] = {0,          1,          2,          3,          4,          7,
                                            8,          16,         255,        256,        257,        4096,
                                            65535,      65536,      65537,      0x7FFF,     0x8000,     0xFFFF,
                                            0x7FFFFFFF, 0x80000000, 0xFFFFFFFF, 0xFFFFFFFE, 150,        200,
                                            1u << 24,   (1u << 24) + 1, 0x40000000, 20,    12,         24};
constexpr std::uint8_t kInteresting8[] = {0, 1, 2, 7, 8, 9, 0x7F, 0x80, 0xFF, '[', ']', '{', '}', '"', ',', ':', '0', '-'};
constexpr const char* kTokens[] = {
    "[",      "]",        "{",        "}",        "\"",         ",",        ":",          "1e999",     "-1",
    "-0",     "0.5",      "1e308",    "null",     "true",       "65536",    "2147483648", "\\u0000",   "\\ud800",
    "\"name\"", "\"size\"", "\"default_n\"", "\"min_n\"", "\"shapes\"", "\"emitters\"", "\"type\"", "\"box\"",
    "\"sphere\"", "\"cylinder\"", "\"cone\"", "\"bowl\"", "\"material\"", "\"only\"", "\"void\"", "\"radius\"",
    "\"thickness_cells\"", "\"rate_per_n2\"", "\"stop_per_n\"", "\"center\"", "[0.5,0.5,0.5]", "1000",
    "SIZE",   "XYZI",     "nTRN",     "nGRP",     "nSHP",       "MAIN",     "RGBA",       "LAYR",      "VOX ",
    "GRAW",   "_t",       "_r",       "2000 2000 2000", "-2147483648 0 0", "4", "\xC3\xA9", "\xFF\xFE",
    "GSNP",   "\x28\xB5\x2F\xFD", "inertial-24"};

void put_u32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (std::size_t i = 0; i < 4 && at + i < b.size(); ++i) b[at + i] = std::uint8_t(v >> (8 * i));
}

/// Offsets of 32-bit fields worth hitting: the raw and snapshot headers (a snapshot's name length
/// and both halves of its compressed size), and the sizes and first fields after every 4-letter
/// chunk id found in the input.
std::vector<std::size_t> field_offsets(const Bytes& b) {
  std::vector<std::size_t> at = {4, 8, 12, 16, 20, 64, 68};
  for (std::size_t i = 0; i + 12 <= b.size() && at.size() < 64; ++i) {
    const bool id = std::isalpha(b[i]) && std::isalpha(b[i + 1]) && std::isalpha(b[i + 2]) &&
                    (std::isalpha(b[i + 3]) || b[i + 3] == ' ');
    if (!id) continue;
    for (std::size_t k = 4; k <= 24 && i + k + 4 <= b.size(); k += 4) at.push_back(i + k);
  }
  return at;
}

void mutate_once(Bytes& b, const std::vector<Bytes>& corpus, Rng& rng) {
  switch (rng.below(12)) {
    case 0:  // flip a bit
      if (!b.empty()) b[rng.below(b.size())] ^= std::uint8_t(1u << rng.below(8));
      break;
    case 1:  // a random byte
      if (!b.empty()) b[rng.below(b.size())] = std::uint8_t(rng.next());
      break;
    case 2:  // an interesting byte
      if (!b.empty()) b[rng.below(b.size())] = kInteresting8[rng.below(std::size(kInteresting8))];
      break;
    case 3: {  // an interesting integer over a header or chunk field
      const auto fields = field_offsets(b);
      put_u32(b, fields[rng.below(fields.size())], kInteresting32[rng.below(std::size(kInteresting32))]);
      break;
    }
    case 4:  // an interesting integer anywhere
      if (!b.empty()) put_u32(b, rng.below(b.size()), kInteresting32[rng.below(std::size(kInteresting32))]);
      break;
    case 5: {  // insert random bytes
      const std::size_t n = 1 + rng.below(16);
      const std::size_t at = rng.below(b.size() + 1);
      Bytes ins(n);
      for (auto& c : ins) c = std::uint8_t(rng.next());
      b.insert(b.begin() + std::ptrdiff_t(at), ins.begin(), ins.end());
      break;
    }
    case 6: {  // delete a range
      if (b.empty()) break;
      const std::size_t at = rng.below(b.size());
      const std::size_t n = std::min(b.size() - at, 1 + rng.below(64));
      b.erase(b.begin() + std::ptrdiff_t(at), b.begin() + std::ptrdiff_t(at + n));
      break;
    }
    case 7: {  // duplicate a range
      if (b.empty()) break;
      const std::size_t at = rng.below(b.size());
      const std::size_t n = std::min(b.size() - at, 1 + rng.below(256));
      const Bytes copy(b.begin() + std::ptrdiff_t(at), b.begin() + std::ptrdiff_t(at + n));
      const std::size_t to = rng.below(b.size() + 1);
      b.insert(b.begin() + std::ptrdiff_t(to), copy.begin(), copy.end());
      break;
    }
    case 8: {  // splice in a piece of another input
      const Bytes& other = corpus[rng.below(corpus.size())];
      if (other.empty()) break;
      const std::size_t from = rng.below(other.size());
      const std::size_t n = std::min(other.size() - from, 1 + rng.below(512));
      const std::size_t to = rng.below(b.size() + 1);
      if (rng.one_in(2)) b.resize(to);  // replace the tail
      b.insert(b.begin() + std::ptrdiff_t(std::min(to, b.size())), other.begin() + std::ptrdiff_t(from),
               other.begin() + std::ptrdiff_t(from + n));
      break;
    }
    case 9: {  // a token, inserted or written over
      const std::string_view t = kTokens[rng.below(std::size(kTokens))];
      const std::size_t at = rng.below(b.size() + 1);
      if (rng.one_in(2) || at + t.size() > b.size()) {
        b.insert(b.begin() + std::ptrdiff_t(at), t.begin(), t.end());
      } else {
        std::copy(t.begin(), t.end(), b.begin() + std::ptrdiff_t(at));
      }
      break;
    }
    case 10:  // truncate
      b.resize(rng.below(b.size() + 1));
      break;
    default: {  // repeat a bracket or a range many times (nesting, long values)
      const std::string_view t = kTokens[rng.below(7)];
      const std::size_t times = 1 + rng.below(rng.one_in(16) ? 100000 : 200);  // sometimes past any stack
      const std::size_t at = rng.below(b.size() + 1);
      std::string run;
      for (std::size_t i = 0; i < times; ++i) run += t;
      b.insert(b.begin() + std::ptrdiff_t(at), run.begin(), run.end());
      break;
    }
  }
}

// --- running inputs -------------------------------------------------------------------------------

struct Stats {
  std::uint64_t inputs = 0;
  std::uint64_t failures = 0;
  double slowest = 0;
};

std::uint64_t fnv1a(const Bytes& b) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::uint8_t c : b) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

void save(const fs::path& dir, const std::string& kind, const Bytes& b) {
  char name[64];
  std::snprintf(name, sizeof name, "%s-%016llx.bin", kind.c_str(), static_cast<unsigned long long>(fnv1a(b)));
  const fs::path p = dir / name;
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
  std::fprintf(stderr, "granular_fuzz: saved as %s\n", p.c_str());
}

/// Runs one input; returns false (and saves it) when it threw anything but a granular::Error.
bool run_one(const Bytes& input, const Options& o, Stats& stats) {
  g_input = input.data();
  g_input_size = input.size();
  alarm(o.timeout);
  const auto start = std::chrono::steady_clock::now();
  std::string failure;
  try {
    LLVMFuzzerTestOneInput(input.data(), input.size());
  } catch (const std::exception& e) {
    failure = std::string(typeid(e).name()) + ": " + e.what();
  } catch (...) {
    failure = "an exception not derived from std::exception";
  }
  alarm(0);
  stats.slowest = std::max(stats.slowest, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  ++stats.inputs;
  g_input = nullptr;
  if (failure.empty()) return true;
  ++stats.failures;
  std::fprintf(stderr, "granular_fuzz: FAIL: input %llu (%zu bytes) threw %s\n",
               static_cast<unsigned long long>(stats.inputs), input.size(), failure.c_str());
  save(o.crash_dir, "exception", input);
  return false;
}

std::vector<Bytes> load_corpus(const std::vector<fs::path>& dirs) {
  std::vector<fs::path> files;
  for (const fs::path& d : dirs) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(d, ec))
      if (entry.is_regular_file()) files.push_back(entry.path());
    if (ec) usage("--corpus " + d.string() + ": " + ec.message());
  }
  std::sort(files.begin(), files.end());
  std::vector<Bytes> corpus;
  for (const fs::path& f : files) {
    std::ifstream in(f, std::ios::binary);
    corpus.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return corpus;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse_options(argc, argv);
  std::error_code ec;
  fs::create_directories(o.crash_dir, ec);
  const std::string crash = (o.crash_dir / ("crash-" + std::to_string(getpid()) + ".bin")).string();
  std::snprintf(g_crash_path, sizeof g_crash_path, "%s", crash.c_str());
  cap_memory(o.memory_mib);
  install_crash_handlers();
  Stats stats;
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };

  if (!o.files.empty()) {
    for (const fs::path& f : o.files) {
      std::ifstream in(f, std::ios::binary);
      if (!in) usage("cannot read " + f.string());
      const Bytes input{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      run_one(input, o, stats);
      std::printf("%s: %s\n", f.c_str(), fuzz_last_outcome().c_str());
    }
  } else {
    std::vector<Bytes> corpus = load_corpus(o.corpus);
    const std::size_t seeds = corpus.size();
    if (corpus.empty()) corpus.push_back({});
    std::unordered_set<std::string> outcomes;
    for (std::size_t i = 0; i < corpus.size(); ++i) {
      run_one(corpus[i], o, stats);
      outcomes.insert(fuzz_last_outcome());
    }
    Rng rng(o.seed);
    constexpr std::size_t kMaxKept = 4096;
    while (o.runs ? stats.inputs < o.runs : elapsed() < o.seconds) {
      Bytes input = corpus[rng.below(corpus.size())];
      const std::size_t rounds = 1 + rng.below(4);
      for (std::size_t r = 0; r < rounds; ++r) mutate_once(input, corpus, rng);
      if (input.size() > o.max_len) input.resize(o.max_len);
      if (run_one(input, o, stats) && corpus.size() < kMaxKept && outcomes.insert(fuzz_last_outcome()).second)
        corpus.push_back(std::move(input));
    }
    const double s = elapsed();
    std::printf("fuzz: %llu inputs in %.1f s (%.0f inputs/s), %zu seeds, %zu kept, %zu outcomes, slowest %.1f ms, "
                "%llu crashes\n",
                static_cast<unsigned long long>(stats.inputs), s, s > 0 ? double(stats.inputs) / s : 0.0, seeds,
                corpus.size() - std::max<std::size_t>(seeds, 1), outcomes.size(), stats.slowest * 1000.0,
                static_cast<unsigned long long>(stats.failures));
  }
  return stats.failures == 0 ? 0 : 1;
}
