#pragma once
/// @file quick_u_tube.hpp
/// The accuracy suite's quick U-tube (accuracy/src/communicating_vessels_test.cpp) for the tests of
/// the liquid levers: a solid floor, a channel 4 cells high full of liquid under a solid wall 8 thick
/// that reaches the top of the grid, and two legs of 8 x 8 cells, the left full 40 cells above the
/// channel, the right empty.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "granular/grid.hpp"
#include "granular/world.hpp"

namespace granular::test {

/// The quick U-tube.
struct QuickUTube {
  static constexpr int kLeg = 8, kWall = 8, kChannelTop = 5, kHead = 40;
  /// The x of the right leg's first column.
  static constexpr int kRight = kLeg + kWall;
  /// The grid's extent.
  static Int3 size() { return {2 * kLeg + kWall, kLeg, kChannelTop + kHead + 4}; }
  /// The tube at its start.
  static Grid build() {
    const Int3 s = size();
    Grid g(s);
    g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
    g.fill(Box{{kLeg, 0, kChannelTop}, {kLeg + kWall, s.y, s.z}}, Material::Solid);
    g.fill(Box{{0, 0, 1}, {s.x, s.y, kChannelTop}}, Material::Liquid);
    g.fill(Box{{0, 0, kChannelTop}, {kLeg, s.y, kChannelTop + kHead}}, Material::Liquid);
    return g;
  }
  /// The mean level of the leg whose first column is x0, in cells above the channel.
  static double level(const World& w, int x0) {
    const std::vector<std::uint8_t> cells = w.read_region(Box{{x0, 0, kChannelTop}, {x0 + kLeg, kLeg, w.size().z}});
    return double(std::count(cells.begin(), cells.end(), to_cell(Material::Liquid))) / (kLeg * kLeg);
  }
  /// The liquid cells of the channel under the wall.
  static long channel(const World& w) {
    const std::vector<std::uint8_t> cells = w.read_region(Box{{kLeg, 0, 1}, {kLeg + kWall, kLeg, kChannelTop}});
    return long(std::count(cells.begin(), cells.end(), to_cell(Material::Liquid)));
  }
};

}  // namespace granular::test
