#include "cpu_backend.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <mutex>

#include "cpu_step.hpp"

namespace granular {

namespace {

/// Result tables are 64 MiB: backends of one process share them per transition table.
std::shared_ptr<const std::vector<BlockKey>> shared_result_table(const Lut& lut, int threads) {
  static std::mutex mutex;
  static std::map<std::uint64_t, std::weak_ptr<const std::vector<BlockKey>>> live;
  std::lock_guard lock(mutex);
  auto& slot = live[lut.content_hash()];
  if (auto table = slot.lock()) return table;
  auto table = std::make_shared<const std::vector<BlockKey>>(derive_result_table(lut.entries(), threads));
  slot = table;
  return table;
}

}  // namespace

CpuBackend::CpuBackend(const Grid& initial, std::shared_ptr<const Lut> lut, bool random_symmetry, bool random_axis_order,
                       std::uint64_t seed, int threads)
    : grid_(initial),
      lut_(std::move(lut)),
      result_(shared_result_table(*lut_, threads)),
      random_symmetry_(random_symmetry),
      random_axis_order_(random_axis_order),
      seed_(seed),
      pool_(threads) {}

std::string CpuBackend::description() const {
  return "cpu (" + std::to_string(pool_.size()) + (pool_.size() == 1 ? " thread)" : " threads)");
}

void CpuBackend::step(std::uint64_t first_tick, int ticks) {
  for (int i = 0; i < ticks; ++i) step_tick(first_tick + std::uint64_t(i));
}

void CpuBackend::step_tick(std::uint64_t tick) {
  StepContext c;
  c.cells = grid_.cells().data();
  c.size = grid_.size();
  c.result = result_->data();
  c.seed = seed_;
  c.tick = tick;
  c.random_symmetry = random_symmetry_;
  c.random_axis_order = random_axis_order_;
  const int layers = block_layers(c);
  // Several layer ranges per thread so that uneven layers (sand vs. air) still balance.
  const int tasks = std::min(layers, pool_.size() == 1 ? 1 : pool_.size() * 8);
  pool_.run(tasks, [&](int task) {
    const int first = int(std::int64_t(layers) * task / tasks);
    const int last = int(std::int64_t(layers) * (task + 1) / tasks);
    for (int layer = first; layer < last; ++layer) step_block_layer(c, layer);
  });
}

void CpuBackend::read(const Box& box, std::span<std::uint8_t> out) const {
  const int w = box.max.x - box.min.x;
  std::size_t o = 0;
  for (int z = box.min.z; z < box.max.z; ++z)
    for (int y = box.min.y; y < box.max.y; ++y, o += std::size_t(w))
      std::memcpy(out.data() + o, grid_.cells().data() + grid_.index({box.min.x, y, z}), std::size_t(w));
}

void CpuBackend::write(const Box& box, std::span<const std::uint8_t> in) {
  const int w = box.max.x - box.min.x;
  std::size_t o = 0;
  for (int z = box.min.z; z < box.max.z; ++z)
    for (int y = box.min.y; y < box.max.y; ++y, o += std::size_t(w))
      std::memcpy(grid_.cells().data() + grid_.index({box.min.x, y, z}), in.data() + o, std::size_t(w));
}

MaterialCounts CpuBackend::count() const {
  const auto cells = grid_.cells();
  const int tasks = pool_.size();
  std::vector<std::array<std::uint64_t, 256>> hist(std::size_t(tasks), std::array<std::uint64_t, 256>{});
  pool_.run(tasks, [&](int t) {
    const std::size_t first = cells.size() * std::size_t(t) / std::size_t(tasks);
    const std::size_t last = cells.size() * std::size_t(t + 1) / std::size_t(tasks);
    auto& h = hist[std::size_t(t)];
    for (std::size_t i = first; i < last; ++i) ++h[cells[i]];
  });
  MaterialCounts counts{};
  for (const auto& h : hist)
    for (int m = 0; m < kMaterialCount; ++m) counts[m] += h[m];
  return counts;
}

std::uint64_t CpuBackend::hash() const {
  const auto cells = grid_.cells();
  const std::size_t words = (cells.size() + 7) / 8;
  const int tasks = pool_.size() * 4;
  std::vector<std::uint64_t> partial(std::size_t(tasks), 0);
  pool_.run(tasks, [&](int t) {
    const std::size_t first = words * std::size_t(t) / std::size_t(tasks);
    const std::size_t last = words * std::size_t(t + 1) / std::size_t(tasks);
    partial[std::size_t(t)] = hash_words(cells, first, last - first);
  });
  std::uint64_t sum = 0;
  for (auto p : partial) sum += p;
  return finish_hash(grid_.size(), sum);
}

}  // namespace granular
