#pragma once
/// @file brick_set.hpp
/// Lists of brick indices (granular/bricks.hpp numbering): all of them, a changed set grown by its
/// 26 neighbours (a brick's surface depends on its neighbours' boundary cells), and two lists united.

#include <cstdint>
#include <span>
#include <vector>

#include "granular/geometry.hpp"

namespace viewer {

/// Every brick of a grid with `counts` bricks per axis, in index order.
std::vector<std::uint32_t> all_bricks(granular::Int3 counts);

/// `changed` plus every brick touching one of them (faces, edges, corners), sorted, without
/// duplicates; every brick when that is most of them.
std::vector<std::uint32_t> with_neighbours(std::span<const std::uint32_t> changed, granular::Int3 counts);

/// Every brick in `a` or in `b` (either may hold duplicates), sorted, without duplicates.
std::vector<std::uint32_t> united(std::span<const std::uint32_t> a, std::span<const std::uint32_t> b,
                                  granular::Int3 counts);

}  // namespace viewer
