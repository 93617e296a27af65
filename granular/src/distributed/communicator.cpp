#include "granular/distributed/communicator.hpp"

#include <algorithm>

namespace granular {

namespace {

/// The words of every rank, `words` per rank, in rank order.
std::vector<std::uint64_t> gather_words(Communicator& comm, std::span<const std::uint64_t> words) {
  std::vector<std::uint64_t> all(words.size() * std::size_t(comm.size()));
  comm.all_gather({reinterpret_cast<const std::uint8_t*>(words.data()), words.size_bytes()},
                  {reinterpret_cast<std::uint8_t*>(all.data()), all.size() * sizeof(std::uint64_t)});
  return all;
}

}  // namespace

std::uint64_t all_sum(Communicator& comm, std::uint64_t value) {
  const std::uint64_t one[1] = {value};
  return all_sum(comm, one)[0];
}

std::vector<std::uint64_t> all_sum(Communicator& comm, std::span<const std::uint64_t> values) {
  const std::vector<std::uint64_t> all = gather_words(comm, values);
  std::vector<std::uint64_t> sum(values.size(), 0);
  for (std::size_t r = 0; r < std::size_t(comm.size()); ++r)
    for (std::size_t i = 0; i < values.size(); ++i) sum[i] += all[r * values.size() + i];
  return sum;
}

bool all_true(Communicator& comm, bool ok) { return all_sum(comm, ok ? 0u : 1u) == 0; }

std::vector<std::vector<std::uint8_t>> all_gather_bytes(Communicator& comm, std::span<const std::uint8_t> mine) {
  const std::uint64_t size[1] = {mine.size()};
  const std::vector<std::uint64_t> sizes = gather_words(comm, size);
  const std::uint64_t longest = *std::max_element(sizes.begin(), sizes.end());
  std::vector<std::uint8_t> padded(longest, 0), all(longest * sizes.size());
  std::copy(mine.begin(), mine.end(), padded.begin());
  comm.all_gather(padded, all);
  std::vector<std::vector<std::uint8_t>> out(sizes.size());
  for (std::size_t r = 0; r < sizes.size(); ++r)
    out[r].assign(all.begin() + std::ptrdiff_t(r * longest), all.begin() + std::ptrdiff_t(r * longest + sizes[r]));
  return out;
}

}  // namespace granular
