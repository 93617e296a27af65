#include "step/inert_keys.hpp"

#include "cpu/thread_pool.hpp"

namespace granular {

std::vector<std::uint64_t> derive_inert_table(std::span<const BlockKey> result, bool random_symmetry, int threads) {
  std::vector<std::uint64_t> table(kInertTableWords, 0);
  ThreadPool pool(threads);
  constexpr int kChunks = 64;
  pool.run(kChunks, [&](int chunk) {
    const std::uint32_t first = kInertTableWords / kChunks * std::uint32_t(chunk);
    const std::uint32_t last = first + kInertTableWords / kChunks;
    for (std::uint32_t w = first; w < last; ++w) {
      std::uint64_t bits = 0;
      for (std::uint32_t b = 0; b < 64; ++b)
        if (key_is_inert(BlockKey(w * 64 + b), random_symmetry, result.data())) bits |= std::uint64_t(1) << b;
      table[w] = bits;
    }
  });
  return table;
}

std::vector<std::uint64_t> derive_rest_inert_table(std::span<const Transition> lut, bool random_symmetry) {
  std::vector<std::uint64_t> table(kInertTableWords, 0);
  const auto result = [&](BlockKey k) { return encode_key(apply_transition(decode_key(k), lut[k])); };
  for (std::uint32_t n = 0; n < 6561; ++n) {
    BlockKey key = 0;
    for (std::uint32_t i = 0, v = n; i < 8; ++i, v /= 3) key |= (v % 3) << (3 * i);
    if (key_is_inert_by(key, random_symmetry, result)) table[key >> 6] |= std::uint64_t(1) << (key & 63u);
  }
  return table;
}

}  // namespace granular
