#pragma once
/// @file see_inside.hpp
/// How a frame shows the inside of the world: a section plane (section_plane.hpp) and x-ray, which
/// draws static materials translucent. Every renderer applies both when it draws, from one word of
/// its push constants (ViewConstants::grid.w, read by shaders/see_inside.glsl), so changing either
/// rebuilds nothing.

#include <cstdint>

#include <glm/glm.hpp>

#include "granular/geometry.hpp"
#include "section/section_plane.hpp"

namespace viewer {

/// The section plane and x-ray of a frame.
struct SeeInside {
  SectionPlane section;  ///< the plane (off by default)
  bool xray = false;     ///< static materials drawn translucent
};

/// Which of a raster renderer's draws the shaders are running (see_inside.glsl).
enum class DrawPass : std::uint32_t {
  Opaque = 0,       ///< opaque surfaces (static ones only without x-ray)
  Translucent = 1,  ///< liquids and gases, blended
  Xray = 2,         ///< the static materials' opaque surfaces again, blended (x-ray only)
};

/// The push-constant word of `inside` for a grid of `size` seen from `eye` (cells), for the opaque
/// pass: bits 0-1 the section's axis + 1 (0: none), bit 2 set when it keeps the cells at or above
/// the plane, bit 3 x-ray, bits 4-5 the pass, bit 6 the cap's `cut_faces_only` (for_draw), bits
/// 8-31 the plane (SectionCut::plane).
std::int32_t see_inside_word(const SeeInside& inside, granular::Int3 size, glm::vec3 eye);

/// `word` for the draw of `pass`; `cut_faces_only` tells the section's cap (section_cap.frag) to
/// cover only the kept cells whose neighbour across the plane is not void (the instanced cubes
/// draw the other faces at the plane themselves).
std::int32_t for_draw(std::int32_t word, DrawPass pass, bool cut_faces_only = false);

}  // namespace viewer
