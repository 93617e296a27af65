#pragma once
/// @file view_constants.hpp
/// The push constants every viewer shader reads (mirrors shaders/view.glsl).

#include <glm/glm.hpp>

namespace viewer {

/// 128 bytes of push constants: the most every Vulkan device guarantees.
struct ViewConstants {
  glm::mat4 matrix{1.0f};  ///< raster: view-projection; ray march: its inverse
  glm::vec4 eye{0.0f};     ///< camera position in cells; w: brush radius (0: no brush highlight)
  glm::ivec4 grid{0};      ///< grid extent; w: the section and x-ray (see_inside_word, see_inside.hpp)
  glm::ivec4 bricks{0};    ///< bricks per axis; w: image width
  glm::vec4 brush{0.0f};   ///< brush centre in cells; w: image height
};
static_assert(sizeof(ViewConstants) == 128);

}  // namespace viewer
