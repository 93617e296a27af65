#pragma once
/// @file step_materials.hpp
/// What the block step reads of a rule set's material table, as plain integers that host and device
/// code share: no step code names a material value, it asks this table.

#include <cstdint>

#include "granular/material.hpp"
#include "granular/motion.hpp"
#include "granular/rule_set.hpp"
#include "step/block_bytes.hpp"

namespace granular {

/// Table codes of the motion model (motion_block.hpp): what its transition table is indexed by.
inline constexpr std::uint32_t kCodeVoid = 0, kCodeObstacle = 1, kCodeGrain = 2, kCodeRoller = 3;

/// Bits of a material's byte in StepMaterials::cell_props: its table code (2 bits), whether it falls
/// as a grain, whether it is a gas.
inline constexpr std::uint32_t kPropCode = 3, kPropFaller = 4, kPropGas = 8;

/// The material table as the step reads it.
struct StepMaterials {
  std::uint32_t codes = 0;     ///< 4 bits per state: the table code of material m (kCodeVoid, kCodeObstacle,
                               ///< kCodeGrain); liquids are grains and gases void to the gravity-and-flow table
  std::uint32_t fallers = 0;   ///< bit m set: material m falls as a grain (granular or liquid) and carries a
                               ///< motion state under a motion model
  std::uint32_t granular = 0;  ///< bit m set: material m is granular
  std::uint32_t liquids = 0;   ///< bit m set: material m is a liquid
  std::uint32_t gases = 0;     ///< bit m set: material m is a gas
  std::uint32_t outside = 1;   ///< the state a cell outside the grid reads as (a static material)
  std::uint16_t roll_chance[kMaterialCount] = {};  ///< GrainMotion::roll_chance per material
  std::uint16_t topple_gain[kMaterialCount] = {};  ///< GrainMotion::topple_gain per material
  std::uint16_t roll_cost[kMaterialCount] = {};    ///< GrainMotion::roll_cost per material
  std::uint16_t entrain[kMaterialCount] = {};      ///< GrainMotion::entrain per material
  std::uint32_t entrained = 0;  ///< bit m set: material m's GrainMotion::entrain is above 0
  std::uint8_t flow_level[kMaterialCount] = {};  ///< GrainMotion::flow_level per material, 0 read as
                                                 ///< kMotionLevelMask (no limit)
  std::uint16_t spread[kMaterialCount] = {};       ///< MaterialDef::spread per material
  std::int8_t density[kMaterialCount] = {};        ///< MaterialDef::density per material (static: unused)
  std::uint8_t pair_codes[64] = {};  ///< the codes of two cells (6 bits of a key) from their materials
  std::uint64_t cell_props = 0;      ///< byte m: what the block step asks of material m at once (kPropCode,
                                     ///< kPropFaller, kPropGas), for per-cell lookups (lookup_bytes)

  /// The key of table codes of a key of materials (3 bits per cell, block order).
  constexpr BlockKey code_key(BlockKey materials) const {
    return BlockKey(pair_codes[materials & 63u]) | (BlockKey(pair_codes[(materials >> 6) & 63u]) << 6) |
           (BlockKey(pair_codes[(materials >> 12) & 63u]) << 12) | (BlockKey(pair_codes[materials >> 18]) << 18);
  }

  /// The table code of material `m` (< 8).
  constexpr std::uint32_t code(std::uint32_t m) const { return (codes >> (4 * m)) & 15u; }
  /// True when material `m` (< 8) falls as a grain (granular or liquid).
  constexpr bool is_faller(std::uint32_t m) const { return ((fallers >> m) & 1u) != 0; }
  /// True when material `m` (< 8) is granular.
  constexpr bool is_granular(std::uint32_t m) const { return ((granular >> m) & 1u) != 0; }
  /// True when material `m` (< 8) is a liquid.
  constexpr bool is_liquid(std::uint32_t m) const { return ((liquids >> m) & 1u) != 0; }
  /// True when material `m` (< 8) is a gas.
  constexpr bool is_gas(std::uint32_t m) const { return ((gases >> m) & 1u) != 0; }
  /// True when material `m` (< 8) is void.
  constexpr bool is_void(std::uint32_t m) const { return code(m) == kCodeVoid && !is_gas(m); }
  /// True when material `m` (< 8) is a fluid: void, a liquid or a gas.
  constexpr bool is_fluid(std::uint32_t m) const { return code(m) == kCodeVoid || is_liquid(m); }
  /// True when the fluid pass (fluid_block.hpp) may move something in a block holding the materials
  /// of `present` (bit m set for each material m in it): a liquid or a gas, or two granular materials.
  constexpr bool fluid_pass_applies(std::uint32_t present) const {
    const std::uint32_t grains = present & granular;
    return (present & (liquids | gases)) != 0 || (grains & (grains - 1)) != 0;
  }
};

/// The gravity-and-flow table code of a behaviour: a liquid falls and topples as a grain does, and
/// grains and liquids fall through a gas as through void (fluid_block.hpp moves what is left).
constexpr std::uint32_t behaviour_code(Behaviour b) {
  switch (b) {
    case Behaviour::Void:
    case Behaviour::Gas: return kCodeVoid;
    case Behaviour::Granular:
    case Behaviour::Liquid: return kCodeGrain;
    default: return kCodeObstacle;
  }
}

/// The step's view of a material table (validated: validate_rule_set).
inline StepMaterials step_materials(const MaterialTable& table) {
  StepMaterials m;
  bool outside_found = false;
  for (std::uint32_t s = 0; s < kMaterialCount; ++s) {
    const MaterialDef& d = table[s];
    m.codes |= behaviour_code(d.behaviour) << (4 * s);
    if (d.behaviour == Behaviour::Granular || d.behaviour == Behaviour::Liquid) m.fallers |= 1u << s;
    if (d.behaviour == Behaviour::Granular) m.granular |= 1u << s;
    if (d.behaviour == Behaviour::Liquid) m.liquids |= 1u << s;
    if (d.behaviour == Behaviour::Gas) m.gases |= 1u << s;
    if (d.behaviour == Behaviour::Static && !outside_found) {
      m.outside = s;
      outside_found = true;
    }
    m.roll_chance[s] = std::uint16_t(d.grain.roll_chance);
    m.topple_gain[s] = std::uint16_t(d.grain.topple_gain);
    m.roll_cost[s] = std::uint16_t(d.grain.roll_cost);
    m.entrain[s] = std::uint16_t(d.grain.entrain);
    if (d.grain.entrain > 0 && m.is_faller(s)) m.entrained |= 1u << s;
    m.flow_level[s] = std::uint8_t(d.grain.flow_level > 0 ? d.grain.flow_level : kMotionLevelMask);
    m.spread[s] = std::uint16_t(d.spread);
    m.density[s] = std::int8_t(d.density);
  }
  for (std::uint32_t pair = 0; pair < 64; ++pair)
    m.pair_codes[pair] = std::uint8_t(m.code(pair & 7u) | (m.code(pair >> 3) << 3));
  for (std::uint32_t s = 0; s < kMaterialCount; ++s) {
    const std::uint32_t props = m.code(s) | (m.is_faller(s) ? kPropFaller : 0u) | (m.is_gas(s) ? kPropGas : 0u);
    m.cell_props |= std::uint64_t(props) << (8 * s);
  }
  return m;
}

/// Bit m set for each material m among a block's 8 cell bytes (the material in each byte's low 3
/// bits), through ByteOps's per-cell lookup (block_bytes.hpp).
template <class ByteOps = PortableByteOps>
constexpr std::uint32_t present_materials(std::uint64_t bytes) {
  std::uint64_t one_hot = ByteOps::lookup(0x8040201008040201ull, bytes);  // byte i: 1 << material i
  one_hot |= one_hot >> 32;
  one_hot |= one_hot >> 16;
  one_hot |= one_hot >> 8;
  return std::uint32_t(one_hot) & 0xFFu;
}

/// The key of a block's materials as table codes (3 bits per cell, block order).
constexpr BlockKey code_key(const StepMaterials& m, const BlockCells& cells) { return m.code_key(encode_key(cells)); }

}  // namespace granular
