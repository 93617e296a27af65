#include "section/see_inside.hpp"

namespace viewer {

std::int32_t see_inside_word(const SeeInside& inside, granular::Int3 size, glm::vec3 eye) {
  std::uint32_t word = inside.xray ? 8u : 0u;
  if (const auto cut = inside.section.cut(size, eye))
    word |= std::uint32_t(cut->axis + 1) | (cut->keeps_high ? 4u : 0u) | (std::uint32_t(cut->plane) << 8);
  return std::int32_t(word);
}

std::int32_t for_draw(std::int32_t word, DrawPass pass, bool cut_faces_only) {
  return std::int32_t((std::uint32_t(word) & ~0x70u) | (std::uint32_t(pass) << 4) | (cut_faces_only ? 64u : 0u));
}

}  // namespace viewer
