#include "world/cell_checks.hpp"

#include "granular/material.hpp"
#include "granular/motion.hpp"
#include "granular/rule_set.hpp"
#include "step/step_materials.hpp"

namespace granular {

std::string cell_text(std::size_t i, Int3 size) {
  const std::size_t x = i % std::size_t(size.x), y = (i / std::size_t(size.x)) % std::size_t(size.y),
                    z = i / (std::size_t(size.x) * std::size_t(size.y));
  return "cell (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) + ")";
}

void check_cells(std::span<const std::uint8_t> cells, Int3 size, const char* what) {
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (!is_valid_material_value(cells[i]))
      throw InvalidArgument(std::string(what) + ": " + cell_text(i, size) + " holds " + std::to_string(unsigned(cells[i])) +
                            ", not a valid state (0..7)");
}

std::array<std::string, 256> cell_byte_problems(const RuleSet& rules) {
  const StepMaterials mats = step_materials(rules.materials);
  std::array<std::string, 256> problems;
  for (unsigned b = 0; b < 256; ++b) {
    const std::uint8_t m = cell_material(std::uint8_t(b));
    if ((b >> kMotionShift) == 0) continue;
    if (rules.motion.columns && is_wake(std::uint8_t(b)) && cell_motion(std::uint8_t(b)) <= rules.motion.max_level())
      continue;
    if (!rules.motion.enabled())
      problems[b] = "a motion state, but rules '" + rules.name + "' have no motion model";
    else if (!mats.is_faller(m))
      problems[b] = "a motion state on " + rules.materials[m].name + ", which is neither granular nor liquid";
    else if (cell_motion(std::uint8_t(b)) > rules.motion.max_level())
      problems[b] = "motion level " + std::to_string(cell_motion(std::uint8_t(b))) + ", above the rules' highest, " +
                    std::to_string(rules.motion.max_level());
  }
  return problems;
}

}  // namespace granular
