#include "granular/time_scale.hpp"

#include <cmath>

namespace granular {

double gravity_cells_per_tick2(const RuleSet& rules) { return rules.motion.enabled() ? 2.0 : 2.0 / 64.0; }

double tick_seconds(const RuleSet& rules, double cell_m, double gravity) {
  return std::sqrt(gravity_cells_per_tick2(rules) * cell_m / gravity);
}

}  // namespace granular
