/// @file test_pour_choice.cpp
/// keep_smallest, pour's selection of the cells of the smallest keys: the same set as ordering all
/// the candidates by key, for hash keys (the way through a limit), for keys crowded at either end of
/// the range (the way through all of them), and at the edges of `keep`.

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "world/pour_choice.hpp"

using namespace granular;

namespace {

/// The positions of the `keep` candidates of the smallest keys, ascending: the plain statement.
std::vector<std::uint64_t> reference(std::vector<PourCandidate> candidates, std::size_t keep) {
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.key < b.key; });
  candidates.resize(std::min(keep, candidates.size()));
  std::vector<std::uint64_t> positions;
  for (const PourCandidate& c : candidates) positions.push_back(c.position);
  std::sort(positions.begin(), positions.end());
  return positions;
}

/// The positions keep_smallest keeps, ascending.
std::vector<std::uint64_t> kept(std::vector<PourCandidate> candidates, std::size_t keep) {
  std::vector<std::uint64_t> positions;
  for (const PourCandidate& c : keep_smallest(candidates, keep)) positions.push_back(c.position);
  std::sort(positions.begin(), positions.end());
  return positions;
}

}  // namespace

TEST_CASE("pour choice: keep_smallest keeps the candidates of the smallest keys, whatever the keys") {
  std::mt19937_64 rng(7);
  for (int round = 0; round < 600; ++round) {
    CAPTURE(round);
    const std::size_t n = std::size_t(rng() % 3000);
    const int spread = round % 3;  // 0: hash keys; 1: keys crowded near 0; 2: near the top
    const std::uint64_t salt = rng();
    std::vector<PourCandidate> candidates;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t position = pack_position(int(i % 17), int(i / 17 % 17), int(i / 289));
      std::uint64_t key = pour_key(salt, position);
      if (spread == 1) key >>= 20;
      if (spread == 2) key |= ~std::uint64_t(0) << 44;
      candidates.push_back({key, position});
    }
    std::vector<std::size_t> keeps{0, 1, n / 10, n / 3, n, n + 5, std::size_t(rng() % (n + 1))};
    if (n > 0) keeps.push_back(n - 1);
    for (const std::size_t keep : keeps) {
      CAPTURE(keep);
      CHECK(kept(candidates, keep) == reference(candidates, keep));
    }
  }
}
