#pragma once
/// @file material.hpp
/// The cell states of the automaton: 3 bits, 8 states at most.

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace granular {

/// One cell state. Values are stored in the low 3 bits of a cell byte; the high 5 bits are zero but
/// for a grain's motion state under a rule set with a motion model (motion.hpp).
/// Void, Solid and Granular are simulated; Liquid and Gas are reserved for rules to come and
/// behave as immovable obstacles until then; 5..7 are free for future materials.
enum class Material : std::uint8_t {
  Void = 0,      ///< empty space
  Solid = 1,     ///< immovable rigid structure (walls, bowls, hoppers); never moved by any rule
  Granular = 2,  ///< sand: falls under gravity and topples into heaps
  Liquid = 3,    ///< reserved
  Gas = 4,       ///< reserved
  Reserved5 = 5, ///< free state
  Reserved6 = 6, ///< free state
  Reserved7 = 7, ///< free state
};

/// Number of distinct cell states (the 3-bit alphabet).
inline constexpr int kMaterialCount = 8;

/// Per-material cell counts, indexed by the material's numeric value.
using MaterialCounts = std::array<std::uint64_t, kMaterialCount>;

/// The lower-case name of a material ("void", "solid", "granular", "liquid", "gas", "state5"...).
std::string_view material_name(Material m) noexcept;

/// Parses a material name (as printed by material_name, plus "sand" for granular); nullopt if unknown.
std::optional<Material> parse_material(std::string_view name) noexcept;

/// True for a value that fits the 3-bit state alphabet.
constexpr bool is_valid_material_value(unsigned v) noexcept { return v < kMaterialCount; }

/// The numeric cell value of a material.
constexpr std::uint8_t to_cell(Material m) noexcept { return static_cast<std::uint8_t>(m); }

}  // namespace granular
