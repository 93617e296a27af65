#include "world/cell_checks.hpp"

#include "granular/grid.hpp"
#include "granular/material.hpp"
#include "granular/motion.hpp"
#include "granular/rule_set.hpp"
#include "step/carried_cells.hpp"
#include "step/shallow_water.hpp"
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
    // Under trains: a carried grain, and a swept void (carried_cells.hpp).
    if (rules.motion.trains && (carried::is_carried(mats, std::uint8_t(b)) ||
                                (carried::is_swept(mats, std::uint8_t(b)) && (b & kWakeBit) == 0)))
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

void check_side_bytes(std::span<const std::uint8_t> side, std::span<const std::uint8_t> cells, Int3 size,
                      const RuleSet& rules, const std::string& what) {
  if (side.empty()) return;
  if (side.size() != cells.size())
    throw InvalidArgument(what + ": WorldSnapshot::side holds " + std::to_string(side.size()) + " bytes; the " +
                          to_string(size) + " grid has " + std::to_string(cells.size()) + " cells (or 0 bytes: no velocity)");
  const StepMaterials mats = step_materials(rules.materials);
  for (std::size_t i = 0; i < side.size(); ++i) {
    const std::uint8_t v = side[i];
    if (v == 0) continue;
    const std::string at = what + ": WorldSnapshot::side of " + cell_text(i, size) + " is " + std::to_string(unsigned(v));
    if (!rules.motion.momentum)
      throw InvalidArgument(at + ", a velocity, but rule set '" + rules.name +
                            "' has no side plane (RuleSet::motion.momentum = false)");
    if (!mats.is_liquid(cells[i] & kMaterialMask))
      throw InvalidArgument(at + " but the cell holds " + std::to_string(unsigned(cells[i])) +
                            ", not a liquid: only a liquid carries a velocity");
    if ((v & 15u) == 8u || (v >> 4) == 8u)
      throw InvalidArgument(at + ": a component of -8; each lies in -7..7 (granular/step/momentum.hpp)");
  }
}

void check_face_plane(std::span<const std::int32_t> faces, Int3 size, const RuleSet& rules, const std::string& what) {
  if (faces.empty()) return;
  const std::size_t columns = std::size_t(size.x) * std::size_t(size.y);
  if (faces.size() != 4 * columns)
    throw InvalidArgument(what + ": WorldSnapshot::faces holds " + std::to_string(faces.size()) + " values; the " +
                          to_string(size) + " grid's face plane has " + std::to_string(4 * columns) +
                          " (4 per column; or 0: every face at rest)");
  static constexpr const char* kFields[4] = {"x velocity", "y velocity", "x fraction", "y fraction"};
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const std::int32_t v = faces[i];
    if (v == 0) continue;
    const int field = int(i / columns);
    const int x = int((i % columns) % std::size_t(size.x)), y = int((i % columns) / std::size_t(size.x));
    const std::string at = what + ": WorldSnapshot::faces, the " + kFields[field] + " of column (" + std::to_string(x) +
                           ", " + std::to_string(y) + "), is " + std::to_string(v);
    if (!rules.motion.shallow)
      throw InvalidArgument(at + ", but rule set '" + rules.name + "' has no face plane (RuleSet::motion.shallow = false)");
    if ((field % 2 == 0 && x + 1 == size.x) || (field % 2 == 1 && y + 1 == size.y))
      throw InvalidArgument(at + " on the grid's edge, a wall: it must be 0");
    const std::int64_t limit = field < 2 ? shallow::kMaxSpeed : shallow::kVolume - 1;
    if (v > limit || v < -limit)
      throw InvalidArgument(at + "; it lies in -" + std::to_string(limit) + ".." + std::to_string(limit) +
                            (field < 2 ? " (shallow::kMaxSpeed)" : " (less than a cell, shallow::kVolume)"));
  }
}

}  // namespace granular
