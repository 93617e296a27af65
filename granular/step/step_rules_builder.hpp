#pragma once
/// @file step_rules_builder.hpp
/// How a backend makes its StepRules (block_step.hpp) from what it was created with: one host
/// function for the CPU and the CUDA backend, each passing the tables it keeps (host or device
/// memory).

#include <cstdint>

#include "granular/extend/backend_factory.hpp"
#include "granular/extend/block.hpp"
#include "granular/motion.hpp"
#include "granular/rule_set.hpp"
#include "step/block_step.hpp"
#include "step/step_materials.hpp"

namespace granular {

/// The tables the Rules read, where the backend keeps them; null for one the rule set does not use
/// or the backend has not made yet.
struct StepTables {
  const BlockKey* result = nullptr;                  ///< StepRules::result
  const motion::MotionEntry* transitions = nullptr;  ///< StepRules::transitions
  const std::uint64_t* inert = nullptr;              ///< StepRules::inert
  const std::int32_t* heads = nullptr;               ///< StepRules::heads (MotionParams::pressure)
};

/// The StepRules of the backend `info` creates: info.rules' flags, motion model and materials,
/// info.seed and info.domain_origin, reading `tables`.
inline StepRules make_step_rules(const BackendCreateInfo& info, const StepTables& tables) {
  const RuleSet& rules = *info.rules;
  const Int3 o = info.domain_origin;
  return StepRules{.result = tables.result, .transitions = tables.transitions, .inert = tables.inert,
                   .seed = info.seed, .random_symmetry = rules.random_symmetry,
                   .random_axis_order = rules.random_axis_order, .motion = rules.motion,
                   .materials = step_materials(rules.materials), .origin = block_position_offset(o.x, o.y, o.z),
                   .heads = tables.heads, .grid = info.initial.size()};
}

}  // namespace granular
