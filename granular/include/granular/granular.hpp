#pragma once
/// @file granular.hpp
/// Everything a game needs to embed granular: World and its definition, materials and rule sets,
/// tools and what they report, scenes, grid and snapshot files, undo, ray picking, the game's task
/// system and the tick's physical length.
///
/// Two further levels are included on their own:
/// - <granular/extend/...>: what a new backend or a tool built on the table needs (the Backend
///   interface and its factory and registry, the block and transition table, memory budget,
///   thread limits, hash printing);
/// - <granular/distributed/...>: a world split into slabs over ranks (DistributedWorld, the
///   Communicator interface, in-process ranks).

#include "granular/body.hpp"
#include "granular/bricks.hpp"
#include "granular/change_report.hpp"
#include "granular/cuda_options.hpp"
#include "granular/errors.hpp"
#include "granular/external_memory.hpp"
#include "granular/geometry.hpp"
#include "granular/grid.hpp"
#include "granular/grid_io.hpp"
#include "granular/material.hpp"
#include "granular/motion.hpp"
#include "granular/raycast.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/scene.hpp"
#include "granular/step_profile.hpp"
#include "granular/stroke_history.hpp"
#include "granular/task_system.hpp"
#include "granular/time_scale.hpp"
#include "granular/vox_io.hpp"
#include "granular/world.hpp"
#include "granular/world_def.hpp"
#include "granular/world_snapshot.hpp"
