#include "granular/extend/lut.hpp"

#include <atomic>
#include <sstream>

#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "cpu/thread_pool.hpp"
#include "rules/block_rule_call.hpp"

namespace granular {

namespace {

constexpr int kChunks = 256;  // the key space is split in this many equal chunks for threading
constexpr std::uint32_t kChunkKeys = kBlockKeyCount / kChunks;

}  // namespace

std::string check_transition(BlockKey key, Transition t, std::uint8_t fixed) {
  if (!is_permutation(t)) return "is not a permutation of the 8 cells";
  const BlockCells cells = decode_key(key);
  for (int i = 0; i < 8; ++i)
    if (((fixed >> cells[i]) & 1u) != 0 && destination(t, i) != i)
      return "moves the fixed (static) cell " + std::to_string(i) + " to " + std::to_string(destination(t, i));
  return {};
}

Lut Lut::build(const RuleSet& rules, int threads) {
  validate_rule_set(rules);
  threads = resolve_threads(threads, "Lut::build threads");
  Lut lut;
  lut.entries_.resize(kBlockKeyCount);
  lut.rule_fingerprint_ = granular::rule_fingerprint(rules);
  ThreadPool pool(threads);
  Transition* out = lut.entries_.data();
  pool.run(kChunks, [&](int chunk) {
    const BlockKey first = BlockKey(chunk) * kChunkKeys;
    BlockKey k = first;
    try {
      for (; k < first + kChunkKeys; ++k) out[k] = rules.transition(decode_key(k), rules.materials);
    } catch (...) {
      throw block_rule_error(rules, k, std::current_exception());
    }
  });
  try {
    lut.validate_and_summarise(threads, fixed_states(rules));
  } catch (const RuleError& e) {
    throw RuleError("rule set " + shown_rule_set_name(rules.name) + ": " + e.what());
  }
  return lut;
}

Lut Lut::from_entries(std::vector<Transition> entries, std::uint64_t rule_fingerprint, int threads, std::uint8_t fixed) {
  if (entries.size() != kBlockKeyCount)
    throw RuleError("transition table has " + std::to_string(entries.size()) + " entries; expected " +
                    std::to_string(kBlockKeyCount));
  threads = resolve_threads(threads, "Lut::from_entries threads");
  Lut lut;
  lut.entries_ = std::move(entries);
  lut.rule_fingerprint_ = rule_fingerprint;
  lut.validate_and_summarise(threads, fixed);
  return lut;
}

void Lut::validate_and_summarise(int threads, std::uint8_t fixed) {
  std::vector<std::uint64_t> hashes(kChunks), moving(kChunks);
  std::vector<std::string> errors(kChunks);
  ThreadPool pool(threads);
  const Transition* e = entries_.data();
  pool.run(kChunks, [&](int chunk) {
    const BlockKey first = BlockKey(chunk) * kChunkKeys;
    std::uint64_t h = 0, m = 0;
    for (BlockKey k = first; k < first + kChunkKeys; ++k) {
      const Transition t = e[k];
      // Fast path: the identity is always valid.
      if (t != kIdentityTransition) {
        ++m;
        if (errors[chunk].empty()) {
          std::string why = check_transition(k, t, fixed);
          if (!why.empty()) errors[chunk] = "key " + block_key_text(k) + ": transition 0" + [&] {
            std::ostringstream s;
            s << std::oct << t;
            return s.str();
          }() + " " + why;
        }
      }
      h += mix64(t + (std::uint64_t(k) << 32));
    }
    hashes[chunk] = h;
    moving[chunk] = m;
  });
  for (const auto& err : errors)
    if (!err.empty()) throw RuleError("invalid transition table: " + err);
  std::uint64_t h = 0, m = 0;
  for (int c = 0; c < kChunks; ++c) {
    h += hashes[c];
    m += moving[c];
  }
  content_hash_ = mix64(h);
  moving_keys_ = m;
}

}  // namespace granular
