#pragma once
/// @file world_scratch.hpp
/// World's scratch for its tools and load (world.cpp, world_tools.cpp): the region being edited and
/// pour's choice of cells, kept from call to call so that their buffers are reused.

#include "granular/world.hpp"
#include "world/pour_choice.hpp"
#include "world/region_edit.hpp"

namespace granular {

/// The scratch of the tools and load.
struct World::Scratch {
  RegionEdit edit;  ///< the region a tool or load edits
  PourChoice pour;  ///< pour's choice of cells
};

}  // namespace granular
