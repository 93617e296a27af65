#include "orifice_tank.hpp"

#include <cmath>

namespace granular::accuracy {

bool OrificeTank::inside(int x, int y) const {
  const double c = size().x / 2.0;
  return std::hypot(x + 0.5 - c, y + 0.5 - c) <= radius;
}

int OrificeTank::area() const {
  const Int3 s = size();
  int n = 0;
  for (int y = 0; y < s.y; ++y)
    for (int x = 0; x < s.x; ++x) n += inside(x, y);
  return n;
}

Grid OrificeTank::build(Material material) const {
  const Int3 s = size();
  Grid g(s);
  const double c = s.x / 2.0;
  for (int y = 0; y < s.y; ++y)
    for (int x = 0; x < s.x; ++x) {
      const bool in_hole = std::hypot(x + 0.5 - c, y + 0.5 - c) <= orifice / 2.0;
      if (!inside(x, y)) g.fill(Box{{x, y, kSink}, {x + 1, y + 1, s.z}}, Material::Solid);
      else if (!in_hole) g.fill(Box{{x, y, kSink}, {x + 1, y + 1, plate_top()}}, Material::Solid);
      if (inside(x, y)) g.fill(Box{{x, y, plate_top()}, {x + 1, y + 1, plate_top() + fill}}, material);
    }
  return g;
}

}  // namespace granular::accuracy
