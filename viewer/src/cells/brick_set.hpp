#pragma once
/// @file brick_set.hpp
/// Lists of brick indices (granular/bricks.hpp numbering, whose all_bricks lists all of them): a
/// changed set grown by its 26 neighbours (a brick's surface depends on its neighbours' boundary
/// cells), and two lists united.

#include <cstdint>
#include <span>
#include <vector>

#include "granular/bricks.hpp"

namespace viewer {

/// `changed` plus every brick touching one of them (faces, edges, corners), sorted, without
/// duplicates; every brick when that is most of them.
std::vector<std::uint32_t> with_neighbours(std::span<const std::uint32_t> changed, granular::Int3 counts);

/// Every brick in `a` or in `b` (either may hold duplicates), sorted, without duplicates.
std::vector<std::uint32_t> united(std::span<const std::uint32_t> a, std::span<const std::uint32_t> b,
                                  granular::Int3 counts);

}  // namespace viewer
