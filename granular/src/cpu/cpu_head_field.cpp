#include "cpu/cpu_head_field.hpp"

#include <algorithm>
#include <atomic>

#include "granular/bricks.hpp"
#include "step/brick_grid.hpp"
#include "step/head_field.hpp"

namespace granular {

CpuHeadField::CpuHeadField(Int3 size)
    : size_(size),
      coarse_(head::coarse_size(size)),
      heads_(std::size_t(coarse_.x) * std::size_t(coarse_.y) * std::size_t(coarse_.z), head::kDry),
      links_(heads_.size(), 0) {
  const Int3 b = brick_counts(size);
  pressing_.assign(std::size_t(b.x) * std::size_t(b.y) * std::size_t(b.z), 0);
}

std::vector<std::uint32_t> CpuHeadField::solve(const std::uint8_t* cells, const StepMaterials& materials,
                                               TaskSystem& tasks) {
  const Int3 s = size_, c = coarse_;
  const auto at = [cells, s](int x, int y, int z) {
    return cells[std::size_t(x) + std::size_t(s.x) * (std::size_t(y) + std::size_t(s.y) * std::size_t(z))];
  };
  const int layers = c.z;
  const int chunks = std::max(1, std::min(layers, tasks.thread_count() * 4));
  // Seeds and links, a range of coarse layers per task.
  tasks.run(chunks, [&](int t) {
    for (int k = layers * t / chunks; k < layers * (t + 1) / chunks; ++k)
      for (int j = 0; j < c.y; ++j)
        for (int i = 0; i < c.x; ++i) {
          const std::size_t n = std::size_t(head::coarse_index(c, i, j, k));
          heads_[n] = head::seed(at, s, materials, i, j, k, links_[n]);
        }
  });
  // Sweeps: each pass carries the head along every line of one axis, lines spread over the tasks.
  std::int32_t* heads = heads_.data();
  const std::uint8_t* links = links_.data();
  struct Axis {
    std::int64_t stride;
    int count;
    std::uint8_t link;
  };
  const Axis axes[3] = {{1, c.x, head::kLinkX}, {c.x, c.y, head::kLinkY}, {std::int64_t(c.x) * c.y, c.z, head::kLinkZ}};
  for (int n = 0; n < head::kPassCount; ++n) {
    const head::SweepPass pass = head::sweep_pass(n);
    const Axis& axis = axes[pass.axis];
    // The lines of this axis: every coarse cell whose coordinate along it is 0.
    const int a = pass.axis, u = a == 0 ? c.y : c.x, v = a == 2 ? c.y : c.z;
    const int line_chunks = std::max(1, std::min(v, tasks.thread_count() * 4));
    tasks.run(line_chunks, [&, u, v, a](int t) {
      for (int q = v * t / line_chunks; q < v * (t + 1) / line_chunks; ++q)
        for (int p = 0; p < u; ++p) {
          const std::int64_t first = a == 0   ? head::coarse_index(c, 0, p, q)
                                     : a == 1 ? head::coarse_index(c, p, 0, q)
                                              : head::coarse_index(c, p, q, 0);
          head::sweep_line(heads, links, first, axis.stride, axis.count, axis.link, pass.forward, pass.dry);
        }
    });
  }
  // The bricks where a pressure move may start.
  const Int3 bricks = brick_counts(s);
  std::fill(pressing_.begin(), pressing_.end(), std::uint8_t(0));
  tasks.run(chunks, [&](int t) {
    for (int k = layers * t / chunks; k < layers * (t + 1) / chunks; ++k)
      for (int j = 0; j < c.y; ++j)
        for (int i = 0; i < c.x; ++i) {
          const std::int32_t h = heads_[std::size_t(head::coarse_index(c, i, j, k))];
          if (h <= head::kSunk || !head::may_press(at, s, materials, i, j, k, h)) continue;
          const std::uint32_t b = brick_index(bricks, 2 * i / kBrickSize, 2 * j / kBrickSize, 2 * k / kBrickSize);
          std::atomic_ref<std::uint8_t>(pressing_[b]).store(1, std::memory_order_relaxed);  // a brick spans tasks' layers
        }
  });
  std::vector<std::uint32_t> out;
  for (std::size_t b = 0; b < pressing_.size(); ++b)
    if (pressing_[b]) out.push_back(std::uint32_t(b));
  return out;
}

}  // namespace granular
