#pragma once
/// @file material_choices.hpp
/// The materials the sandbox offers: every non-void state of the world's material table, state s on
/// number key s, in order. The right button applies the chosen one: a material that moves
/// (granular, liquid, gas) is poured above the hit point; a static one cannot be poured (it would
/// hang in the air where it landed), so it is painted as a sphere of structure in front of the hit
/// face, as a wall is built.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "granular/rule_set.hpp"

namespace viewer {

/// What the right button does with a chosen material.
enum class MaterialUse {
  Pour,   ///< World::pour above the hit point (granular, liquid and gas materials)
  Paint,  ///< World::paint(sphere) in front of the hit face (static materials: structure)
};

/// "pour" or "paint".
const char* to_string(MaterialUse use);

/// The use of a material of behaviour `behaviour` (not void): Paint for static, else Pour.
MaterialUse use_of(granular::Behaviour behaviour);

/// One material the sandbox offers.
struct MaterialChoice {
  int key = 0;                                                ///< the number key choosing it: its state, 1..7
  granular::Material material = granular::Material::Void;    ///< the cell state
  std::string name;                                           ///< MaterialDef::name
  std::uint32_t colour = 0;                                   ///< MaterialDef::colour, 0xRRGGBB
  granular::Behaviour behaviour = granular::Behaviour::Void;  ///< MaterialDef::behaviour
  MaterialUse use = MaterialUse::Pour;                        ///< what the right button does with it
};

/// The non-void states of `table`, in state order (a valid table has 7: states 1..7).
std::vector<MaterialChoice> material_choices(const granular::MaterialTable& table);

/// The choice of number key `digit`, if it chooses one.
std::optional<MaterialChoice> choice_of_key(const std::vector<MaterialChoice>& choices, int digit);

/// The choice of state `material` (which must be one of `choices`).
const MaterialChoice& choice_of(const std::vector<MaterialChoice>& choices, granular::Material material);

/// One line listing the choices with their colours: "1 solid #8C8C94, 2 granular #D9B873, ...".
std::string describe(const std::vector<MaterialChoice>& choices);

}  // namespace viewer
