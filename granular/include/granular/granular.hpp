#pragma once
/// @file granular.hpp
/// Everything a game needs to embed granular: World, its definition, materials, tools, scenes and
/// grid files, and what plugs into a World (backends, the game's task system).

#include "granular/activity.hpp"
#include "granular/backend.hpp"
#include "granular/backend_factory.hpp"
#include "granular/backend_registry.hpp"
#include "granular/cuda_options.hpp"
#include "granular/errors.hpp"
#include "granular/geometry.hpp"
#include "granular/grid.hpp"
#include "granular/grid_io.hpp"
#include "granular/hex.hpp"
#include "granular/material.hpp"
#include "granular/motion.hpp"
#include "granular/raycast.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/scene.hpp"
#include "granular/stroke_history.hpp"
#include "granular/task_system.hpp"
#include "granular/time_scale.hpp"
#include "granular/tools.hpp"
#include "granular/vox_io.hpp"
#include "granular/world.hpp"
#include "granular/world_def.hpp"
#include "granular/world_snapshot.hpp"
