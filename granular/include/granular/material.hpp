#pragma once
/// @file material.hpp
/// The cell states of the automaton: 3 bits, 8 states at most.

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace granular {

/// One cell state of the presets' material table (default_materials, rule_presets.hpp). Values are
/// stored in the low 3 bits of a cell byte; the high 5 bits are zero but for a falling material's
/// motion state under a rule set with a motion model (motion.hpp). What a state does is the rule
/// set's material table (RuleSet::materials): a game may give states 6 and 7 (static in the presets)
/// behaviours of its own.
enum class Material : std::uint8_t {
  Void = 0,      ///< empty space
  Solid = 1,     ///< immovable rigid structure (walls, bowls, hoppers); never moved by any rule
  Granular = 2,  ///< sand: falls under gravity and topples into heaps
  Liquid = 3,    ///< water: falls, spreads sideways and finds its level; sand sinks in it
  Gas = 4,       ///< rises through void and liquid and spreads under ceilings
  Gravel = 5,    ///< a coarser, heavier grain with a steeper angle of repose than sand
  State6 = 6,    ///< static in the presets; free for a game's own material
  State7 = 7,    ///< static in the presets; free for a game's own material
};

/// Number of distinct cell states (the 3-bit alphabet).
inline constexpr int kMaterialCount = 8;

/// Per-material cell counts, indexed by the material's numeric value.
using MaterialCounts = std::array<std::uint64_t, kMaterialCount>;

/// The lower-case name of a material ("void", "solid", "granular", "liquid", "gas", "gravel", "state6", "state7").
std::string_view material_name(Material m) noexcept;

/// Parses a material name (as printed by material_name, plus "sand" for granular and "water" for
/// liquid); nullopt if unknown.
std::optional<Material> parse_material(std::string_view name) noexcept;

/// True for a value that fits the 3-bit state alphabet.
constexpr bool is_valid_material_value(unsigned v) noexcept { return v < kMaterialCount; }

/// The numeric cell value of a material.
constexpr std::uint8_t to_cell(Material m) noexcept { return static_cast<std::uint8_t>(m); }

}  // namespace granular
