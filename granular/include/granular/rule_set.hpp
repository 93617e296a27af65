#pragma once
/// @file rule_set.hpp
/// A rule set is code: a function from a block's 8 states to a transition (a permutation of the
/// block's cells). It is compiled into the transition table (Lut) once, validated, and cached.

#include <cstdint>
#include <string>

#include "granular/block.hpp"
#include "granular/motion.hpp"

namespace granular {

/// The function a rule set supplies: given a block's cells, where does each cell go.
/// Must return a permutation and must leave every solid cell in place (the table build checks).
using BlockRule = Transition (*)(const BlockCells& cells);

/// A named set of block rules.
///
/// Random variants. Every random choice is a pure function of (seed, tick, block position), so a
/// run is deterministic for a seed on every backend and thread count, and each is one of a finite
/// set of variants of the one table:
/// * random_symmetry: per block and tick, one of the 8 horizontal symmetries s (horizontal_symmetry);
///   the block's next key is inverse_s(result[s(key)]). A key whose result is itself under all 8
///   symmetries (e.g. every uniform key, and every key the table maps to itself under each view)
///   is inert whatever the draw.
/// * random_axis_order: per 8-tick cycle (not per block), one of 2 offset orders (block_offset).
///   It only moves the partition; it never changes which keys are inert.
struct RuleSet {
  std::string name;            ///< preset name, e.g. "paper"
  std::string description;     ///< one line for humans
  std::uint32_t version = 1;   ///< bump whenever the rule's behaviour changes (part of the cache key)
  bool random_symmetry = false;  ///< apply a random horizontal symmetry (D4) per block and tick, drawn
                                 ///< from block_random(seed, tick, position): one table, isotropic result
  bool random_axis_order = false;  ///< walk each 8-tick offset cycle in one of two orders (x flips every 2
                                   ///< ticks and y every 4, or the reverse), drawn per cycle from
                                   ///< block_offset(tick, seed, true); the same for every block of a tick
  BlockRule transition = nullptr;  ///< the rule itself
  MotionParams motion;  ///< inertia and rolling (motion.hpp); the default is off: one step per tick
  std::string device_rule;  ///< name of the same rule compiled for GPUs ("paper"), empty when none:
                            ///< a GPU backend builds the table on the device from it
};

/// A 64-bit identity of a rule set's behaviour: its name, version and flags plus the rule's output
/// on every key over {void, solid, granular} and on 4096 pseudo-random keys over all 8 states. It
/// keys the on-disk table cache, so a changed rule invalidates a stale table even if nobody bumped
/// the version.
std::uint64_t rule_fingerprint(const RuleSet& rules);

}  // namespace granular
