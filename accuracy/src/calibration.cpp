#include "granular/accuracy/calibration.hpp"

#include <cmath>
#include <cstdio>

#include "granular/time_scale.hpp"

namespace granular::accuracy {

double Calibration::tick_s() const { return std::sqrt(2 * cell_m / (gravity * calibration_cells)); }

double Calibration::cell_kg() const { return bulk_density * cell_m * cell_m * cell_m; }

double Calibration::gravity_cells() const { return gravity * tick_s() * tick_s() / cell_m; }

std::string Calibration::describe() const {
  char line[256];
  std::snprintf(line, sizeof line,
                "cell d = %.4g m, tick dt = %.4g ms (a fall of H_c = %.0f cells takes sqrt(2 H_c d / g) with g = %.3g m/s^2), "
                "grain cell = %.4g g (bulk density %.0f kg/m^3)",
                cell_m, tick_s() * 1000, calibration_cells, gravity, cell_kg() * 1000, bulk_density);
  return line;
}

Calibration calibration_for(const RuleSet& rules) {
  Calibration c;
  c.calibration_cells = 2 / gravity_cells_per_tick2(rules);  // 64 cells, or 1 with the motion model
  return c;
}

}  // namespace granular::accuracy
