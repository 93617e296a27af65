#include "granular/rule_presets.hpp"

#include <array>
#include <utility>

#include "granular/errors.hpp"
#include "granular/material.hpp"
#include "step/fluid_block.hpp"
#include "step/motion_block.hpp"
#include "step/paper_rule.hpp"
#include "step/step_materials.hpp"

namespace granular {

namespace {

/// The inertial presets' grain: a topple always gains a level and a roll costs one with chance
/// 160/256, which puts the full-size poured cone's angle at 34.6 degrees, near dry sand's 33 (tuned on
/// the accuracy suite's cone on the GPU: 128 gives 29.4, 192 gives 36.4); every moving grain may roll.
constexpr GrainMotion kInertialGrain{.topple_gain = 256, .roll_cost = 160, .roll_chance = 256};

/// The entrain preset's grain: a moving grain that rolls or topples sets a grain at rest on a step
/// edge of its block moving with chance 128/256, a topple gains a level with chance 192/256 and a roll
/// costs one with chance 224/256. Tuned on the accuracy suite's tilted bed, dug crater and cones
/// (entrain 64 to 256, topple gain 128 to 256, roll cost 160 to 256; docs/ACCURACY.md): more entrain
/// lowers the angle an avalanche stops at, a smaller topple gain raises the cones' angles.
constexpr GrainMotion kEntrainGrain{.topple_gain = 192, .roll_cost = 224, .roll_chance = 256, .entrain = 128};

/// `grain` with its flow level set to `level`.
constexpr GrainMotion with_flow_level(GrainMotion grain, int level) {
  grain.flow_level = level;
  return grain;
}

/// The flow preset's grain: the entrain preset's, and a grain that rolls or topples keeps at most
/// level 1, so a grain landing on a slope flows down it one cell a tick whatever height it fell from
/// (docs/accuracy/flow.md lists the settings and flow levels tried).
constexpr GrainMotion kFlowGrain = with_flow_level(kEntrainGrain, 1);

/// Density ranks of the shipped materials: gas < void (0) < liquid < sand < gravel.
constexpr int kGasDensity = -1, kLiquidDensity = 2, kSandDensity = 3, kGravelDensity = 4;

/// Liquid under a motion model: it falls and topples as sand does, and rolls on almost for free, so a
/// falling mass of it runs out over a floor; the one-step rules give it no motion (all zero).
constexpr GrainMotion liquid_motion(GrainMotion sand) {
  if (sand.roll_chance == 0) return {};
  return GrainMotion{.topple_gain = 256, .roll_cost = 16, .roll_chance = 256};
}

/// Gravel under a motion model: every roll costs a level (sand: 160/256) and a topple gains none (sand:
/// always), so a moving gravel grain stops sooner and its cone is steeper: 38.6 degrees on the quick
/// suite against sand's 29-33 (docs/accuracy/gravel_cone.md lists every value tried).
constexpr GrainMotion gravel_motion(GrainMotion sand) {
  if (sand.roll_chance == 0) return {};
  return GrainMotion{
      .topple_gain = 0, .roll_cost = 256, .roll_chance = 256, .entrain = sand.entrain, .flow_level = sand.flow_level};
}

/// One preset of the registry.
struct PresetEntry {
  const char* name;
  const char* description;
  std::uint32_t version;
  bool random_symmetry;
  bool random_axis_order;
  int substeps;  ///< MotionParams::substeps (1: no motion model)
  bool columns = false;  ///< MotionParams::columns
  GrainMotion grain = kInertialGrain;  ///< sand's motion under a motion model (gravel's follows from it)
  bool pressure = false;  ///< MotionParams::pressure
  bool momentum = false;  ///< MotionParams::momentum
  bool trains = false;    ///< MotionParams::trains
  bool shallow = false;   ///< MotionParams::shallow (the liquid's spread is then 0: the pass levels it)
};

constexpr std::array<PresetEntry, 11> kPresets = {{
    {"paper", "gravity then flow, fixed preference order (the paper's rules)", 1, false, false, 1},
    {"isotropic",
     "the paper's rules under a random horizontal symmetry per block and tick and a random offset order per cycle", 2,
     true, true, 1},
    {"d4", "the paper's rules under a random horizontal symmetry per block and tick, the paper's offset cycle", 1, true,
     false, 1},
    {"inertial",
     "isotropic plus inertia and rolling: 16 sub-steps per tick, grains accelerate in free fall and roll on", 1, true,
     true, 16},
    {"inertial-24",
     "inertial with 24 sub-steps per tick: a top speed of 23 cells per tick instead of 15, for 1.5 times the cost", 1,
     true, true, 24},
    {"inertial-24-entrain",
     "inertial-24 with avalanches: a rolling or toppling grain sets the grains at rest on step edges of its block "
     "moving, so a tilted slope fails near 38 degrees and its avalanche stops near 34",
     1, true, true, 24, false, kEntrainGrain},
    {"inertial-24-flow",
     "inertial-24-entrain with grains that flow over a surface one cell a tick: a grain that rolls or topples keeps "
     "at most level 1, so a poured pile's angle no longer depends on the height its grains fell from",
     1, true, true, 24, false, kFlowGrain},
    {"inertial-24-columns",
     "inertial-24-flow with grains in free fall falling as columns, in trains that close their gaps every tick: a "
     "released block falls as a block, in free-fall time, and a pile still flows one cell a tick",
     4, true, true, 24, true, kFlowGrain, false, false, true},
    {"inertial-24-pressure",
     "inertial-24-flow with liquids under the head of their body: connected vessels level, a water column pours out "
     "from every row, and a liquid under a higher surface of its body rises",
     1, true, true, 24, false, kFlowGrain, true},
    {"inertial-24-momentum",
     "inertial-24-pressure with liquids that keep a sideways velocity: a liquid pushed out by its head, or running "
     "off a surface, goes on until a wall stops it (up to 18 cells a tick), so a burst dam's front runs instead of "
     "diffusing",
     2, true, true, 24, false, kFlowGrain, true, true},
    {"inertial-24-shallow",
     "inertial-24-flow with liquid under open sky moving as shallow water: a released body of water runs out as a "
     "body, a pool levels within a few L / sqrt(g h) and then rests",
     1, true, true, 24, false, kFlowGrain, false, false, false, true},
}};

RuleSet make_preset(const PresetEntry& e) {
  RuleSet r;
  r.name = e.name;
  r.description = e.description;
  r.version = e.version;
  r.random_symmetry = e.random_symmetry;
  r.random_axis_order = e.random_axis_order;
  r.motion.substeps = e.substeps;
  r.motion.columns = e.columns;
  r.motion.pressure = e.pressure;
  r.motion.momentum = e.momentum;
  r.motion.trains = e.trains;
  r.motion.shallow = e.shallow;
  r.materials = default_materials(r.motion.enabled() ? e.grain : GrainMotion{});
  // Under the shallow-water pass the liquid's surface is the pass's to level: the block step's
  // random spread of a surface cell would keep a pool at rest churning (docs/design/shallow-water.md).
  if (e.shallow) {
    MaterialDef& liquid = r.materials[to_cell(Material::Liquid)];
    liquid.spread = 0;
    liquid.grain.topple_gain = 0;
    liquid.grain.roll_cost = 256;
  }
  r.transition = r.motion.enabled() ? &motion_transition : &paper_transition;
  r.device_rule = r.motion.enabled() ? "motion" : "paper";
  return r;
}

}  // namespace

Transition paper_transition(const BlockCells& cells, const MaterialTable& materials) {
  return fluid::one_step_transition(encode_key(cells), step_materials(materials));
}

Transition motion_transition(const BlockCells& codes, const MaterialTable&) { return motion::motion_rule(encode_key(codes)); }

MaterialTable default_materials(GrainMotion grain) {
  MaterialTable t;
  for (int s = 0; s < kMaterialCount; ++s) {
    t[std::size_t(s)].name = std::string(material_name(Material(s)));
    t[std::size_t(s)].behaviour = Behaviour::Static;
  }
  auto row = [&](Material m, Behaviour b, int density, std::uint32_t colour) -> MaterialDef& {
    MaterialDef& d = t[to_cell(m)];
    d.behaviour = b;
    d.density = density;
    d.colour = colour;
    return d;
  };
  row(Material::Void, Behaviour::Void, 0, 0x000000);
  row(Material::Solid, Behaviour::Static, 0, 0x8C8C94);
  row(Material::Granular, Behaviour::Granular, kSandDensity, 0xD9B873).grain = grain;
  MaterialDef& liquid = row(Material::Liquid, Behaviour::Liquid, kLiquidDensity, 0x2E6FD9);
  liquid.grain = liquid_motion(grain);
  liquid.spread = 256;
  row(Material::Gas, Behaviour::Gas, kGasDensity, 0xD8E6C8).spread = 256;
  row(Material::Gravel, Behaviour::Granular, kGravelDensity, 0x6E6A64).grain = gravel_motion(grain);
  row(Material::State6, Behaviour::Static, 0, 0xA0522D);
  row(Material::State7, Behaviour::Static, 0, 0x7A4FA0);
  // What bodies feel (docs/design/bodies.md, "Forces"): dry sand's and gravel's bulk densities with
  // twice a bluff body's drag (a granular medium resists being sheared), water's with a bluff body's;
  // a body loses all the momentum of the grains and water it pushes.
  t[to_cell(Material::Granular)].body = {1600, 4.0, 1.0};
  t[to_cell(Material::Gravel)].body = {1750, 4.0, 1.0};
  t[to_cell(Material::Liquid)].body = {1000, 2.0, 1.0};
  t[to_cell(Material::Gas)].body = {1.2, 1.0, 0.0};
  return t;
}

RuleSet preset(std::string_view name) {
  for (const PresetEntry& e : kPresets)
    if (name == e.name) return make_preset(e);
  std::string valid;
  for (const auto& n : rule_preset_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw InvalidArgument("unknown rule set '" + std::string(name) + "'; valid rule sets: " + valid);
}

std::shared_ptr<const RuleSet> make_rule_set(std::string_view name) { return std::make_shared<const RuleSet>(preset(name)); }

std::vector<std::string> rule_preset_names() {
  std::vector<std::string> names;
  for (const PresetEntry& e : kPresets) names.emplace_back(e.name);
  return names;
}

}  // namespace granular
