#include "granular/rule_set.hpp"

#include <set>
#include <sstream>

#include "granular/errors.hpp"
#include "granular/grid.hpp"
#include "granular/material.hpp"
#include "io/file_names.hpp"
#include "rules/block_rule_call.hpp"
#include "step/step_materials.hpp"
#include "util/number_text.hpp"

namespace granular {

const char* behaviour_name(Behaviour b) noexcept {
  switch (b) {
    case Behaviour::Void: return "void";
    case Behaviour::Static: return "static";
    case Behaviour::Granular: return "granular";
    case Behaviour::Liquid: return "liquid";
    case Behaviour::Gas: return "gas";
  }
  return "invalid";
}

std::uint8_t fixed_states(const RuleSet& rules) {
  // The motion model's table is indexed by codes: obstacle (1) and the unused codes 4..7 never move.
  if (rules.motion.enabled()) return std::uint8_t(0xF0u | (1u << kCodeObstacle));
  std::uint8_t fixed = 0;
  for (int s = 0; s < kMaterialCount; ++s)
    if (rules.materials[std::size_t(s)].behaviour == Behaviour::Static) fixed = std::uint8_t(fixed | (1u << s));
  return fixed;
}

std::string block_key_text(BlockKey key) {
  std::ostringstream s;
  s << "0" << std::oct << key << " (cells";
  for (auto c : decode_key(key)) s << " " << material_name(Material(c));
  s << ")";
  return s.str();
}

std::string shown_rule_set_name(const std::string& name) {
  constexpr std::size_t kShown = 40;
  const auto bytes = std::span(reinterpret_cast<const std::uint8_t*>(name.data()), std::min(name.size(), kShown));
  std::string text(1, '\'');  // built by appending: GCC 12 warns falsely on "'" + string (-Wrestrict)
  text.append(escaped_bytes(bytes, '\''));
  text.push_back('\'');
  if (name.size() > kShown) text += "... (" + std::to_string(name.size()) + " bytes)";
  return text;
}

RuleError block_rule_error(const RuleSet& rules, BlockKey key, std::exception_ptr thrown) {
  std::string what = "an exception that is not a std::exception";
  try {
    std::rethrow_exception(thrown);
  } catch (const std::exception& e) {
    what = e.what();
  } catch (...) {
  }
  return RuleError("rule set " + shown_rule_set_name(rules.name) + ": RuleSet::transition threw on block key " +
                   block_key_text(key) + ": " + what);
}

void validate_rule_set(const RuleSet& rules) {
  const std::string who = "rule set " + shown_rule_set_name(rules.name) + ": ";
  if (rules.name.empty()) throw RuleError("RuleSet::name is empty; a rule set needs a name (it keys the table cache)");
  if (rules.name.size() > kMaxRuleSetNameBytes)
    throw RuleError(who + "RuleSet::name has " + std::to_string(rules.name.size()) + " bytes; at most " +
                    std::to_string(kMaxRuleSetNameBytes) + " are allowed");
  for (std::size_t i = 0; i < rules.name.size(); ++i)
    if (const auto c = std::uint8_t(rules.name[i]); c < 0x20 || c > 0x7E)
      throw RuleError(who + "RuleSet::name byte " + std::to_string(i) + " is " + escaped_bytes({&c, 1}, '\'') +
                      "; a name is printable ASCII (space to '~')");
  if (!rules.transition) throw RuleError(who + "RuleSet::transition is null; give it a block rule");
  std::set<std::string> names;
  bool any_static = false;
  for (int s = 0; s < kMaterialCount; ++s) {
    const MaterialDef& d = rules.materials[std::size_t(s)];
    const std::string field = "RuleSet::materials[" + std::to_string(s) + "]";
    if (std::uint8_t(d.behaviour) > std::uint8_t(Behaviour::Gas))
      throw RuleError(who + field + ".behaviour = " + std::to_string(int(d.behaviour)) +
                      " is not a Behaviour; use Void, Static, Granular, Liquid or Gas");
    if (d.name.empty()) throw RuleError(who + field + ".name is empty; every state needs a name");
    if (!names.insert(d.name).second) throw RuleError(who + field + ".name = '" + d.name + "' is used twice");
    if ((s == 0) != (d.behaviour == Behaviour::Void))
      throw RuleError(who + field + ".behaviour = " + behaviour_name(d.behaviour) +
                      (s == 0 ? "; state 0 must be void (new grids and dug cells are state 0)"
                              : "; only state 0 may be void"));
    any_static = any_static || d.behaviour == Behaviour::Static;
    auto chance = [&](int c, const char* what) {
      if (c < 0 || c > 256)
        throw RuleError(who + field + ".grain." + what + " = " + std::to_string(c) + "; chances are out of 256 (0..256)");
    };
    chance(d.grain.topple_gain, "topple_gain");
    chance(d.grain.roll_cost, "roll_cost");
    chance(d.grain.roll_chance, "roll_chance");
    chance(d.grain.entrain, "entrain");
    if (d.grain.flow_level < 0 || d.grain.flow_level > int(kMotionLevelMask))
      throw RuleError(who + field + ".grain.flow_level = " + std::to_string(d.grain.flow_level) +
                      "; a motion level is 0..15 (0: no limit)");
    if (d.spread < 0 || d.spread > 256)
      throw RuleError(who + field + ".spread = " + std::to_string(d.spread) + "; chances are out of 256 (0..256)");
    if (d.colour > 0xFFFFFFu)
      throw RuleError(who + field + ".colour = " + std::to_string(d.colour) + "; a colour is 0xRRGGBB (0..16777215)");
    auto coupling = [&](double v, double most, const char* what) {
      if (!(v >= 0 && v <= most))
        throw RuleError(who + field + ".body." + what + " = " + number_text(v) + "; it must be 0 .. " +
                        number_text(most));
    };
    coupling(d.body.bulk_density, 1e5, "bulk_density");
    coupling(d.body.drag, 100, "drag");
    coupling(d.body.push, 1, "push");
    if (d.density < -64 || d.density > 64)
      throw RuleError(who + field + ".density = " + std::to_string(d.density) + "; densities are -64..64");
    const bool mobile = d.behaviour == Behaviour::Granular || d.behaviour == Behaviour::Liquid;
    if ((d.behaviour == Behaviour::Void && d.density != 0) || (d.behaviour == Behaviour::Gas && d.density >= 0) ||
        (mobile && d.density <= 0))
      throw RuleError(who + field + ".density = " + std::to_string(d.density) + " for a " + behaviour_name(d.behaviour) +
                      " material; void is 0, a gas below 0 and a granular or liquid material above 0");
  }
  if (!any_static)
    throw RuleError(who + "RuleSet::materials has no static material; cells outside the grid read as one");
  const int n = rules.motion.substeps;
  if (n != 1 && (n < 8 || n % 8 != 0 || n > 32))
    throw RuleError(who + "RuleSet::motion.substeps = " + std::to_string(n) +
                    "; use 1 (no motion model) or a multiple of 8 up to 32");
  if (rules.motion.pressure && !rules.motion.enabled())
    throw RuleError(who + "RuleSet::motion.pressure = true with motion.substeps = 1; pressure is a lever of the "
                          "motion model: set substeps to a multiple of 8 up to 32, or pressure to false");
  if (rules.motion.momentum && !rules.motion.pressure)
    throw RuleError(who + "RuleSet::motion.momentum = true with motion.pressure = false; momentum is a lever of "
                          "pressure (the head sets a liquid's speed): set pressure to true, or momentum to false");
  if (rules.motion.columns && !rules.motion.enabled())
    throw RuleError(who + "RuleSet::motion.columns = true with motion.substeps = 1; columns are a lever of the motion "
                          "model: set substeps to a multiple of 8 up to 32, or columns to false");
  if (rules.motion.shallow && !rules.motion.enabled())
    throw RuleError(who + "RuleSet::motion.shallow = true with motion.substeps = 1; shallow is a lever of the motion "
                          "model: set substeps to a multiple of 8 up to 32, or shallow to false");
  if (rules.motion.shallow && rules.motion.pressure)
    throw RuleError(who + "RuleSet::motion.shallow = true with motion.pressure = true; the head's pushes and the "
                          "shallow-water pass work against each other (docs/design/shallow-water.md): set one of "
                          "them to false");
  if (rules.motion.trains && !rules.motion.columns)
    throw RuleError(who + "RuleSet::motion.trains = true with motion.columns = false; trains are a lever of columns "
                          "(a train is what falling as columns leaves of a body): set columns to true, or trains to false");
  if (rules.motion.trains && rules.motion.max_level() >= kCarriedLevel)
    throw RuleError(who + "RuleSet::motion.trains = true with motion.substeps = " + std::to_string(rules.motion.substeps) +
                    "; a carried train's grains are marked by motion level " + std::to_string(kCarriedLevel) +
                    ", which those sub-steps give a moving grain: set substeps to 24 or fewer, or trains to false");
}

std::uint64_t rule_fingerprint(const RuleSet& rules) {
  std::uint64_t h = 0x72756C6573657431ull;
  auto add_text = [&](const std::string& text) {
    for (char c : text) h = mix64(h ^ std::uint8_t(c));
    h = mix64(h ^ text.size());
  };
  for (char c : rules.name) h = mix64(h ^ std::uint8_t(c));
  h = mix64(h ^ rules.version);
  h = mix64(h ^ (rules.random_symmetry ? 1u : 0u));
  if (rules.random_axis_order) h = mix64(h ^ 0x617865736F726465ull);
  if (rules.motion.enabled()) h = mix64(h ^ 0x6D6F74696F6E0000ull ^ std::uint64_t(rules.motion.substeps));
  if (rules.motion.columns) h = mix64(h ^ 0x636F6C756D6E7300ull);
  if (rules.motion.trains) h = mix64(h ^ 0x747261696E730000ull);
  if (rules.motion.pressure) h = mix64(h ^ 0x7072657373757265ull);
  if (rules.motion.momentum) h = mix64(h ^ 0x6D6F6D656E74756Dull);
  if (rules.motion.shallow) h = mix64(h ^ 0x7368616C6C6F7700ull);
  for (const MaterialDef& d : rules.materials) {
    add_text(d.name);
    h = mix64(h ^ (std::uint64_t(d.behaviour) << 56) ^ std::uint64_t(d.grain.topple_gain) ^
              (std::uint64_t(d.grain.roll_cost) << 16) ^ (std::uint64_t(d.grain.roll_chance) << 32));
    h = mix64(h ^ (std::uint64_t(std::uint32_t(d.density)) << 20) ^ std::uint64_t(d.spread));
    if (d.grain.entrain != 0) h = mix64(h ^ 0x656E747261696E00ull ^ std::uint64_t(d.grain.entrain));
    if (d.grain.flow_level != 0) h = mix64(h ^ 0x666C6F776C766C00ull ^ std::uint64_t(d.grain.flow_level));
  }
  if (!rules.transition) return h;
  BlockKey key = 0;
  try {
    // Every block over the three simulated states.
    for (std::uint32_t n = 0; n < 6561; ++n) {
      BlockCells cells{};
      std::uint32_t v = n;
      for (int i = 0; i < 8; ++i, v /= 3) cells[i] = std::uint8_t(v % 3);
      key = encode_key(cells);
      h = mix64(h ^ rules.transition(cells, rules.materials)) + n;
    }
    // A pseudo-random sample over all 8 states.
    for (std::uint64_t n = 0; n < 4096; ++n) {
      key = BlockKey(mix64(n * 0x9E3779B97F4A7C15ull) & (kBlockKeyCount - 1));
      h = mix64(h ^ rules.transition(decode_key(key), rules.materials)) + key;
    }
  } catch (...) {
    throw block_rule_error(rules, key, std::current_exception());
  }
  return h;
}

}  // namespace granular
