#pragma once
/// @file world_def_validation.hpp
/// The checks of the WorldDef fields a World reads when it creates its backend.

#include "granular/geometry.hpp"
#include "granular/world_def.hpp"

namespace granular {

/// Throws InvalidArgument naming the field and its value unless `def` can make a world of a grid of
/// `size` cells: WorldDef::threads, task_system (its thread_count()), backend, cuda's fractions,
/// cell_metres, body_material (a state; World::add_body checks that it is static) and domain_origin.
/// Returns the CPU threads the world steps with: the task system's thread count when
/// def.task_system is set, else WorldDef::threads resolved (threads.hpp).
int validate_world_def(const WorldDef& def, Int3 size);

}  // namespace granular
