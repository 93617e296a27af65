#include "granular/accuracy/tilted_bed.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "granular/accuracy/fit.hpp"

namespace granular::accuracy {

namespace {

constexpr double kDegree = std::numbers::pi / 180;

}  // namespace

Int3 TiltedBed::size() const {
  return {slope_length + runout + 2, width + 2, base + int(std::ceil(slope_length * std::tan(max_deg * kDegree))) + 4};
}

Grid TiltedBed::build(double deg) const {
  const Int3 s = size();
  Grid g(s);
  g.fill(Box{{0, 0, 0}, {s.x, s.y, 1}}, Material::Solid);
  g.fill(Box{{0, 0, 0}, {1, s.y, s.z}}, Material::Solid);
  g.fill(Box{{s.x - 1, 0, 0}, {s.x, s.y, s.z}}, Material::Solid);
  g.fill(Box{{0, 0, 0}, {s.x, 1, s.z}}, Material::Solid);
  g.fill(Box{{0, s.y - 1, 0}, {s.x, s.y, s.z}}, Material::Solid);
  const double t = std::tan(deg * kDegree);
  for (int i = 0; i < slope_length; ++i) {
    const int h = base + int(std::lround((slope_length - i - 0.5) * t));
    g.fill(Box{{1 + i, 1, 1}, {2 + i, s.y - 1, 1 + h}}, Material::Granular);
  }
  return g;
}

double tilted_bed_slope_deg(const Grid& grid, const TiltedBed& bed) {
  std::vector<double> h(std::size_t(grid.size().x), 0);
  for (int x = 0; x < grid.size().x; ++x) {
    double sum = 0;
    for (int y = 1; y <= bed.width; ++y)
      for (int z = 1; z < grid.size().z; ++z) sum += grid.at({x, y, z}) == Material::Granular;
    h[std::size_t(x)] = sum / bed.width;
  }
  const double top = *std::max_element(h.begin(), h.end());
  std::vector<double> xs, hs;
  for (std::size_t x = 0; x < h.size(); ++x)
    if (h[x] >= 0.2 * top && h[x] <= 0.8 * top) {
      xs.push_back(double(x));
      hs.push_back(h[x]);
    }
  const LineFit f = fit_line(xs, hs);
  return f.ok ? std::atan(-f.slope) / kDegree : std::nan("");
}

double moved_fraction(const Grid& before, const Grid& after) {
  const std::uint8_t sand = to_cell(Material::Granular);
  double grains = 0, moved = 0;
  for (std::size_t i = 0; i < before.cells().size(); ++i) {
    if (before.cells()[i] != sand) continue;
    grains += 1;
    moved += after.cells()[i] != sand;
  }
  return grains > 0 ? moved / grains : 0;
}

}  // namespace granular::accuracy
