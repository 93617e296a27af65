#include <cstdint>
#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "cells/cell_buffer.hpp"
#include "vulkan/gpu_buffer.hpp"
#include "granular/bricks.hpp"
#include "granular/world.hpp"
#include "viewer_test_support.hpp"

using namespace viewer;

namespace {

std::vector<std::uint8_t> download(const CellBuffer& cells) {
  VulkanContext& context = test::context();
  GpuBuffer host(context, cells.bytes(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryKind::HostVisible);
  context.run_once([&](VkCommandBuffer commands) {
    const VkBufferCopy region{0, 0, cells.bytes()};
    vkCmdCopyBuffer(commands, cells.buffer(), host.buffer(), 1, &region);
  });
  const granular::Int3 n = cells.size();
  std::vector<std::uint8_t> bytes(std::size_t(n.x) * n.y * n.z);
  std::memcpy(bytes.data(), host.mapped(), bytes.size());
  return bytes;
}

}  // namespace

TEST_CASE("cell buffer: brick uploads and brick copies between buffers land exactly where they belong") {
  // An odd size, so bricks at the far faces are partial and rows are not word aligned.
  auto world = test::bowl_world(37);
  const granular::Int3 size = world->size();
  const granular::Int3 counts = world->brick_counts();
  CellBuffer source(test::context(), size);
  CellBuffer target(test::context(), size);
  std::vector<std::uint32_t> every;
  for (std::uint32_t b = 0; b < std::uint32_t(counts.x * counts.y * counts.z); ++b) every.push_back(b);
  test::context().run_once([&](VkCommandBuffer commands) { source.record_upload(commands, 0, *world, every); });
  const granular::Grid start = world->read_grid();
  CHECK(download(source) == std::vector<std::uint8_t>(start.cells().begin(), start.cells().end()));

  // Copy two bricks (one partial) from `source` into the empty `target`: only their cells change.
  const std::vector<std::uint32_t> some{0, std::uint32_t(counts.x * counts.y * counts.z - 1)};
  test::context().run_once([&](VkCommandBuffer commands) { target.record_copy_from(commands, 0, source.buffer(), some); });
  const std::vector<std::uint8_t> copied = download(target);
  const granular::Grid grid = world->read_grid();
  std::vector<std::uint8_t> expected(copied.size(), 0);
  for (std::uint32_t b : some) {
    const granular::Box box = granular::brick_box(size, b);
    for (int z = box.min.z; z < box.max.z; ++z)
      for (int y = box.min.y; y < box.max.y; ++y)
        for (int x = box.min.x; x < box.max.x; ++x) expected[grid.index({x, y, z})] = std::uint8_t(grid.at({x, y, z}));
  }
  CHECK(copied == expected);

  // A few changed bricks through the scatter path after a tool call.
  world->dig({{18, 18, 30}, 4.0});
  const std::vector<std::uint32_t> changed = world->bricks_changed_since(0);
  REQUIRE(changed.size() < every.size() / 2);
  test::context().run_once([&](VkCommandBuffer commands) { source.record_upload(commands, 1, *world, changed); });
  const granular::Grid after = world->read_grid();
  CHECK(download(source) == std::vector<std::uint8_t>(after.cells().begin(), after.cells().end()));
  CHECK(test::context().validation_messages() == 0);
}
