#pragma once
/// @file rule_set.hpp
/// A rule set is data: a material table (what each of the 8 cell states is and the parameters the
/// step reads for it), the motion model's parameters, the random variants, and the block rule that
/// is compiled into the transition table (Lut) once, validated, and cached. A game copies a preset
/// (granular::preset, rule_presets.hpp), changes it, and passes it as WorldDef::rule_set.

#include <array>
#include <cstdint>
#include <string>

#include "granular/extend/block.hpp"
#include "granular/material.hpp"
#include "granular/motion.hpp"

namespace granular {

/// How the step treats cells of a material.
enum class Behaviour : std::uint8_t {
  Void = 0,      ///< empty space: mobile cells move into it
  Static = 1,    ///< never moved by any rule (walls, bowls, obstacles)
  Granular = 2,  ///< falls under gravity and topples into heaps (with the motion model: inertia, rolling)
  Liquid = 3,    ///< falls and topples as a grain does, and also spreads sideways over liquid (fluid_block.hpp)
  Gas = 4,       ///< rises through every denser fluid (void, liquids) and spreads sideways under gas
};

/// The lower-case name of a behaviour ("void", "static", "granular", "liquid", "gas").
const char* behaviour_name(Behaviour b) noexcept;

/// How a material acts on the bodies in it (body.hpp; docs/design/bodies.md, "Forces"). No effect on
/// the step, and not part of the rule set's fingerprint.
struct BodyCoupling {
  double bulk_density = 0;  ///< kg/m^3 of a cell of it (grains and the voids between them): the buoyancy
                            ///< it gives a body submerged in it (0: none, as void and walls)
  double drag = 0;          ///< drag coefficient of a body face moving against it (0 .. 100)
  double push = 0;          ///< fraction of the momentum of the cells a body pushes out of its way that the
                            ///< body loses (0 .. 1)
};

/// One row of the material table: one cell state.
struct MaterialDef {
  std::string name;                         ///< lower-case name, unique in the table ("sand")
  Behaviour behaviour = Behaviour::Static;  ///< how the step treats it
  GrainMotion grain;                        ///< granular and liquid materials under a motion model: rolling and
                                            ///< level changes
  int density = 0;  ///< density rank, -64..64: a mobile cell above a lighter one sinks through it (void is 0,
                    ///< so a gas is below 0 and a granular or liquid material above it). Two granular
                    ///< materials pass each other only while one of them moves (level above 0).
  int spread = 0;   ///< liquids: chance out of 256 that a liquid standing on liquid moves sideways into a
                    ///< lighter fluid beside it when it takes part in a step; gases the same under gas
                    ///< (0: never spreads; unused by the other behaviours)
  std::uint32_t colour = 0x808080;  ///< display colour 0xRRGGBB for viewers and tools (no effect on the step)
  BodyCoupling body;                ///< what it does to bodies (no effect on the step)
};

/// The material table: row m describes cell state m.
using MaterialTable = std::array<MaterialDef, kMaterialCount>;

/// The function a rule set supplies: given a block's 8 table keys' states, where does each cell go.
/// Without a motion model the states are materials and `materials` says what they are; with one
/// they are the motion model's table codes (motion_block.hpp) and `materials` is not consulted.
/// Must return a permutation that leaves every fixed state (fixed_states) in place (the table
/// build checks).
using BlockRule = Transition (*)(const BlockCells& cells, const MaterialTable& materials);

/// A named rule set.
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
  std::string name;            ///< preset name, e.g. "paper": 1..kMaxRuleSetNameBytes bytes of printable ASCII
  std::string description;     ///< one line for humans
  std::uint32_t version = 1;   ///< bump whenever the rule's behaviour changes (part of the cache key)
  MaterialTable materials;     ///< what each cell state is (default_materials() in the presets)
  bool random_symmetry = false;  ///< apply a random horizontal symmetry (D4) per block and tick, drawn
                                 ///< from block_random(seed, tick, position): one table, isotropic result
  bool random_axis_order = false;  ///< walk each 8-tick offset cycle in one of two orders (x flips every 2
                                   ///< ticks and y every 4, or the reverse), drawn per cycle from
                                   ///< block_offset(tick, seed, true); the same for every block of a tick
  BlockRule transition = nullptr;  ///< the rule itself
  MotionParams motion;  ///< the motion model (motion.hpp); the default is off: one step per tick
  std::string device_rule;  ///< name of the same rule compiled for GPUs ("paper", "motion"), empty when
                            ///< none: a GPU backend builds the table on the device from it
};

/// The table states that must never move: with a motion model the obstacle codes (motion_block.hpp),
/// otherwise the static materials. Bit s set for state s.
std::uint8_t fixed_states(const RuleSet& rules);

/// Longest RuleSet::name validate_rule_set accepts, in bytes.
inline constexpr std::size_t kMaxRuleSetNameBytes = 64;

/// Throws RuleError naming the field and value when `rules` cannot be stepped: a name that is
/// empty, longer than kMaxRuleSetNameBytes or not printable ASCII (0x20..0x7E), no transition, a
/// material table without exactly one void material and at least one static one, an empty or
/// duplicate material name, a behaviour out of range, a grain motion or spread chance outside 0..256,
/// a density out of -64..64 or of the wrong sign for its behaviour (void 0, gas below 0, granular and
/// liquid above 0), a colour above 0xFFFFFF, or motion parameters out of range (MotionParams::substeps
/// 1, or a multiple of 8 up to 32).
void validate_rule_set(const RuleSet& rules);

/// A 64-bit identity of a rule set's behaviour: its name, version, flags, material table and motion
/// parameters, plus the rule's output on every key over {void, solid, granular} and on 4096
/// pseudo-random keys over all 8 states. It keys the on-disk table cache, so a changed rule invalidates
/// a stale table even if nobody bumped the version.
std::uint64_t rule_fingerprint(const RuleSet& rules);

}  // namespace granular
