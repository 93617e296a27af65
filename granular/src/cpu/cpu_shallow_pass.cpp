#include "cpu/cpu_shallow_pass.hpp"

#include <algorithm>
#include <atomic>

#include "granular/bricks.hpp"
#include "granular/errors.hpp"
#include "step/brick_grid.hpp"

namespace granular {

namespace {

/// The grid as move_face reads and writes it, noting each column's changed cells.
struct HostColumns {
  std::uint8_t* cells;
  std::size_t layer;  // cells per layer
  std::int32_t* lo;   // per column: the lowest changed cell
  std::int32_t* hi;   // per column: the highest changed cell
  std::uint8_t get(std::int64_t column, int z) const { return cells[std::size_t(column) + std::size_t(z) * layer]; }
  void set(std::int64_t column, int z, std::uint8_t byte) const {
    cells[std::size_t(column) + std::size_t(z) * layer] = byte;
    lo[column] = std::min(lo[column], z);
    hi[column] = std::max(hi[column], z);
  }
};

}  // namespace

CpuShallowPass::CpuShallowPass(Int3 size)
    : size_(size),
      columns_(std::size_t(size.x) * std::size_t(size.y)),
      column_(columns_),
      surface_(columns_),
      limit_(2 * columns_),
      faces_(4 * columns_, 0),
      next_u_(2 * columns_, 0),
      cells_(2 * columns_, 0),
      volume_(2 * columns_, 0),
      changed_lo_(columns_, size.z),
      changed_hi_(columns_, -1) {}

shallow::Plane CpuShallowPass::plane() {
  return shallow::plane_over(size_, shallow::PlaneBuffers{column_.data(), surface_.data(), limit_.data(), faces_.data(),
                                                          next_u_.data(), volume_.data(), cells_.data()});
}

std::vector<std::uint32_t> CpuShallowPass::run(std::uint8_t* cells, const StepMaterials& m, TaskSystem& tasks) {
  const shallow::Plane p = plane();
  const int nx = size_.x, ny = size_.y;
  const std::size_t layer = columns_;
  // Rows of columns per task. A pass is up to 290 parallel loops a tick, so a grid of fewer columns
  // than kParallelColumns runs them on the calling thread, where a hand-off would outweigh a loop.
  constexpr std::size_t kParallelColumns = 32768;
  const int chunks = columns_ < kParallelColumns ? 1 : std::max(1, std::min(ny, tasks.thread_count() * 4));
  auto rows = [&](auto&& body) {
    tasks.run(chunks, [&](int t) {
      for (int y = ny * t / chunks; y < ny * (t + 1) / chunks; ++y) body(y);
    });
  };
  // The columns, layer by layer so each read walks a row of cells.
  tasks.run(chunks, [&](int t) {
    std::vector<shallow::ColumnScan> scans(static_cast<std::size_t>(nx));
    for (int y = ny * t / chunks; y < ny * (t + 1) / chunks; ++y) {
      std::fill(scans.begin(), scans.end(), shallow::ColumnScan{});
      const std::uint8_t* row = cells + std::size_t(nx) * std::size_t(y);
      for (int z = 0; z < size_.z; ++z)
        for (int x = 0; x < nx; ++x) scans[std::size_t(x)].visit(z, row[std::size_t(z) * layer + std::size_t(x)], m);
      for (int x = 0; x < nx; ++x) column_[std::size_t(p.at(x, y))] = scans[std::size_t(x)].result();
    }
  });
  rows([&](int y) {
    for (int x = 0; x < nx; ++x) shallow::settle_column(p.columns, nx, ny, x, y);
  });
  // Pipes' heads, only in a grid with a covered column (whose columns are fixed for the tick).
  const bool covered = std::any_of(column_.begin(), column_.end(), [](const shallow::Column& c) { return c.covered(); });
  bool changed_any = false;
  HostColumns grid{cells, layer, changed_lo_.data(), changed_hi_.data()};
  for (int i = 0; i < shallow::kIterations; ++i) {
    std::atomic<bool> changed{false};
    rows([&](int y) {
      for (int x = 0; x < nx; ++x) shallow::surface_of(p, x, y);
    });
    if (covered)
      rows([&](int y) {
        for (int x = 0; x < nx; ++x) shallow::head_of(p, x, y);
      });
    rows([&](int y) {
      for (int x = 0; x < nx; ++x)
        for (int a = 0; a < shallow::kAxes; ++a) shallow::update_face(p, x, y, a);
    });
    rows([&](int y) {
      for (int x = 0; x < nx; ++x) shallow::limit_column(p, x, y);
    });
    rows([&](int y) {
      bool any = false;
      for (int x = 0; x < nx; ++x)
        for (int a = 0; a < shallow::kAxes; ++a) {
          const std::int64_t c = p.at(x, y);
          const std::int32_t u = p.u[a][c], f = p.fraction[a][c];
          shallow::split_face(p, x, y, a);
          any = any || u != p.u[a][c] || f != p.fraction[a][c] || p.cells[a][c] != 0;
        }
      if (any) changed.store(true, std::memory_order_relaxed);
    });
    for (int phase = 0; phase < 4; ++phase)
      rows([&](int y) {
        for (int x = 0; x < nx; ++x)
          if (shallow::in_phase(x, y, phase)) shallow::move_face(p, grid, x, y, shallow::phase_axis(phase), m);
      });
    // An iteration is a function of the cells and the faces: one that changed neither leaves the
    // rest of the tick's iterations nothing to do either.
    if (!changed.load()) break;
    changed_any = true;
  }
  at_rest_ = !changed_any;
  // The bricks of the changed cells, and the record cleared for the next run.
  const Int3 bricks = brick_counts(size_);
  std::vector<std::uint32_t> woken;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const std::size_t c = std::size_t(p.at(x, y));
      if (changed_lo_[c] > changed_hi_[c]) continue;
      for (int bz = brick_of(changed_lo_[c]); bz <= brick_of(changed_hi_[c]); ++bz)
        woken.push_back(brick_index(bricks, brick_of(x), brick_of(y), bz));
      changed_lo_[c] = size_.z;
      changed_hi_[c] = -1;
    }
  std::sort(woken.begin(), woken.end());
  woken.erase(std::unique(woken.begin(), woken.end()), woken.end());
  return woken;
}

std::vector<std::int32_t> CpuShallowPass::faces() const {
  if (std::all_of(faces_.begin(), faces_.end(), [](std::int32_t f) { return f == 0; })) return {};
  return faces_;
}

void CpuShallowPass::set_faces(std::span<const std::int32_t> faces) {
  if (faces.empty())
    std::fill(faces_.begin(), faces_.end(), 0);
  else
    std::copy(faces.begin(), faces.end(), faces_.begin());
  at_rest_ = false;
}

}  // namespace granular
