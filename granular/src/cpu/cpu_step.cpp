#include "cpu/cpu_step.hpp"

#include "cpu/cpu_block_ops.hpp"
#include "cpu/cpu_block_row.hpp"
#include "cpu/thread_pool.hpp"

namespace granular {

namespace {

using namespace cpu_ops;

/// Steps one row of blocks, x from -offset.x: an edge block at each end whose cell column lies
/// outside the grid, the blocks between eight at a time (cpu_block_row.hpp).
template <bool kWhole, class Rule>
void step_row(const StepContext& c, const Rule& rule, const BlockRow& row, int y0, int z0) {
  NoNotes notes;
  int x = -rule.offset.x;
  if (x < 0) {
    step_edge_block(rule, row, -1, y0, z0, notes);
    x += 2;
  }
  const int x_end = inside_end(c, x, c.size.x);
  step_blocks<kWhole>(rule, row, x, x_end, y0, z0, notes);
  if (x_end < c.size.x) step_edge_block(rule, row, x_end, y0, z0, notes);
}

template <class Rule>
void step_layer(const StepContext& c, const Rule& rule, int layer) {
  const BlockOffset o = rule.offset;
  const int z0 = 2 * layer - o.z;
  const int blocks_y = block_count(c.size.y, o.y);
  for (int by = 0; by < blocks_y; ++by) {
    const int y0 = 2 * by - o.y;
    const BlockRow row = block_row(c, y0, z0);
    if (row.inside == kWholeBlock)
      step_row<true>(c, rule, row, y0, z0);
    else
      step_row<false>(c, rule, row, y0, z0);
  }
}

}  // namespace

std::vector<BlockKey> derive_result_table(std::span<const Transition> lut, int threads) {
  std::vector<BlockKey> result(lut.size());
  ThreadPool pool(threads);
  constexpr int kChunks = 64;
  pool.run(kChunks, [&](int chunk) {
    const std::size_t first = lut.size() * std::size_t(chunk) / kChunks, last = lut.size() * std::size_t(chunk + 1) / kChunks;
    for (std::size_t k = first; k < last; ++k)
      result[k] = encode_key(apply_transition(decode_key(BlockKey(k)), lut[k]));
  });
  return result;
}

int block_layers(const StepContext& context) { return block_count(context.size.z, context_offset(context).z); }

void step_block_layer(const StepContext& context, int layer) {
  with_host_rule(context, [&](const auto& rule) { step_layer(context, rule, layer); });
}

}  // namespace granular
