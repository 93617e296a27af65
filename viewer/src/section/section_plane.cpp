#include "section/section_plane.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace viewer {

bool SectionCut::removes(granular::Int3 p) const {
  const int coordinate = axis == 0 ? p.x : (axis == 1 ? p.y : p.z);
  return keeps_high ? coordinate < plane : coordinate >= plane;
}

SectionPlane SectionPlane::cycled() const {
  SectionPlane next = *this;
  next.axis = axis >= 2 ? -1 : axis + 1;
  return next;
}

SectionPlane SectionPlane::moved(int steps) const {
  SectionPlane next = *this;
  if (on()) next.fraction = std::clamp(fraction + steps * kStep, 0.0, 1.0);
  return next;
}

std::optional<SectionCut> SectionPlane::cut(granular::Int3 size, glm::vec3 eye) const {
  if (!on()) return std::nullopt;
  const int extent = axis == 0 ? size.x : (axis == 1 ? size.y : size.z);
  SectionCut cut;
  cut.axis = axis;
  cut.plane = int(std::lround(fraction * extent));
  cut.keeps_high = eye[axis] < float(cut.plane);
  return cut;
}

std::string SectionPlane::describe() const {
  if (!on()) return "off";
  char text[32];
  std::snprintf(text, sizeof(text), "%c %.2f", "xyz"[axis], fraction);
  return text;
}

SectionPlane parse_section(const std::string& text) {
  const auto fail = [&] {
    return std::invalid_argument("--section '" + text + "': expected AXIS:FRACTION, AXIS x, y or z and FRACTION in 0..1 (e.g. y:0.5)");
  };
  if (text.size() < 3 || text[1] != ':') throw fail();
  SectionPlane section;
  switch (text[0]) {
    case 'x': case 'X': section.axis = 0; break;
    case 'y': case 'Y': section.axis = 1; break;
    case 'z': case 'Z': section.axis = 2; break;
    default: throw fail();
  }
  const std::string number = text.substr(2);
  try {
    std::size_t used = 0;
    section.fraction = std::stod(number, &used);
    if (used != number.size()) throw fail();
  } catch (const std::logic_error&) {
    throw fail();
  }
  if (!(section.fraction >= 0.0 && section.fraction <= 1.0)) throw fail();
  return section;
}

}  // namespace viewer
