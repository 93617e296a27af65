#pragma once
/// @file tool_region.hpp
/// The argument checks of the tools (World::dig, pour, paint) and the region of cells a sphere
/// touches: one implementation for the tools and for the scene emitters, which check every pour
/// before making any.

#include <cstdint>
#include <string>

#include "granular/geometry.hpp"
#include "granular/material.hpp"

namespace granular {

struct RuleSet;

/// A box as "[x,y,z)-[x,y,z)", for messages.
std::string box_string(const Box& b);

/// Throws InvalidArgument naming `tool` when `m` is not one of the 8 states.
void check_tool_material(Material m, const char* tool);

/// The in-grid box of cells whose centres lie in `sphere`, computed in doubles until it is known to
/// lie inside the grid, so no centre or radius overflows an int. Sets `clipped` when the sphere
/// reaches past the grid. Throws InvalidArgument naming `tool` for a non-finite centre, a radius
/// that is not finite and > 0, or a sphere that covers no cell of a grid of `size`.
Box sphere_region(const Sphere& sphere, Int3 size, const char* tool, bool& clipped);

/// The checks of World::pour (material valid and not void, amount >= 0, a sphere covering a cell
/// of a grid of `size`): throws InvalidArgument as pour does, else returns the sphere's region.
Box check_pour(const Sphere& sphere, Material material, std::int64_t amount, Int3 size, bool& clipped);

/// The checks of World::shake: `rules` has a motion model and `level` is one of its levels
/// (1..max_level); throws InvalidArgument as shake does.
void check_shake(const RuleSet& rules, int level);

/// The checks of World::paint of a box (material valid, box not empty and meeting a grid of
/// `size`): throws InvalidArgument as paint does, else returns the box's in-grid part, setting
/// `clipped` when that is not the whole box.
Box check_paint_box(const Box& box, Material material, Int3 size, bool& clipped);

}  // namespace granular
