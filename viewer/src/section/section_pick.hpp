#pragma once
/// @file section_pick.hpp
/// The cursor's pick when a section plane removes half of the cells: the tools act on what the
/// player sees, the first kept cell along the ray, not on a removed one in front of the cut.

#include <optional>

#include <glm/glm.hpp>

#include "granular/raycast.hpp"
#include "section/section_plane.hpp"

namespace granular {
class World;
}

namespace viewer {

/// granular::raycast from `origin` along `direction` (cells) over the cells `cut` keeps (all of
/// them without a cut): the ray starts where it enters the kept side, and a cell it meets right at
/// the plane is entered through the plane (its normal points to the removed side). Nothing when the
/// ray meets no kept cell.
std::optional<granular::RayHit> pick_kept_cell(const granular::World& world, const std::optional<SectionCut>& cut,
                                               glm::vec3 origin, glm::vec3 direction);

}  // namespace viewer
