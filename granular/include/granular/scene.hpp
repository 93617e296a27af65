#pragma once
/// @file scene.hpp
/// Scenes: JSON descriptions of a starting grid (solid structures, sand) and of emitters that pour
/// grains while the world runs. Every position and length in a scene is a fraction of a size
/// parameter N, so one file describes the same setup at any resolution. docs/SCENES.md documents
/// the format and the rounding rule that turns fractions into cells.

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "granular/geometry.hpp"
#include "granular/grid.hpp"
#include "granular/material.hpp"

namespace granular {

class World;
class DistributedWorld;

/// Largest scene file load_scene reads, in bytes (the shipped ones are about 2 KB).
inline constexpr std::uint64_t kMaxSceneFileBytes = std::uint64_t(16) << 20;

/// Deepest nesting of JSON arrays and objects a scene may have (a scene needs 4: the top-level
/// object, "shapes", a shape, its "center").
inline constexpr int kMaxSceneDepth = 32;

/// Longest scene "name", in bytes.
inline constexpr std::size_t kMaxSceneName = 256;

/// Most cells the grid of a scene at its default_n may hold (256^3): the default is for a quick
/// look; larger grids are asked for explicitly (instantiate(scene, n), `granular run --size`).
inline constexpr std::int64_t kMaxDefaultGridCells = std::int64_t(256) * 256 * 256;

/// An axis-aligned box between two corners (fractions of N). Its faces are rounded to whole cell
/// boundaries.
struct BoxShape {
  std::array<double, 3> min{};  ///< lower corner (x, y, z)
  std::array<double, 3> max{};  ///< upper corner; max >= min on every axis
};

/// A ball (fractions of N).
struct SphereShape {
  std::array<double, 3> center{};  ///< centre (x, y, z)
  double radius = 0;               ///< radius, >= 0
};

/// A vertical cylinder (fractions of N): a disc of `radius` around (center x, y) between the heights
/// z0 and z1, which are rounded to whole cell boundaries.
struct CylinderShape {
  std::array<double, 2> center{};  ///< axis position (x, y)
  double radius = 0;               ///< radius, >= 0
  double z0 = 0;                   ///< bottom height
  double z1 = 0;                   ///< top height, >= z0
};

/// A vertical cone or frustum (fractions of N): around (center x, y), between the heights z0 and z1
/// (rounded to whole cell boundaries), with radius r0 at the bottom face and r1 at the top face,
/// linear in between. r0 = 0 or r1 = 0 gives a pointed cone.
struct ConeShape {
  std::array<double, 2> center{};  ///< axis position (x, y)
  double z0 = 0;                   ///< bottom height
  double z1 = 0;                   ///< top height, >= z0
  double r0 = 0;                   ///< radius at the bottom, >= 0
  double r1 = 0;                   ///< radius at the top, >= 0
};

/// A hemispherical shell open at the top: the part of the spherical shell between radius
/// `radius - thickness` and `radius` around `center` that lies at or below the centre's height.
struct BowlShape {
  std::array<double, 3> center{};  ///< centre of the sphere; the rim lies at its height (fractions of N)
  double radius = 0;               ///< outer radius (fraction of N), > 0
  double thickness = 0;            ///< wall thickness, > 0: a fraction of N, or cells when thickness_in_cells
  bool thickness_in_cells = false; ///< true when the file gave "thickness_cells" (the wall does not scale with N)
};

/// The geometry of a scene shape.
using ShapeGeometry = std::variant<BoxShape, SphereShape, CylinderShape, ConeShape, BowlShape>;

/// One shape of a scene: a region and the material written into its cells.
struct ShapeDef {
  ShapeGeometry geometry;          ///< where
  Material material = Material::Solid;  ///< what the covered cells become
  std::optional<Material> only;    ///< when set, only cells currently holding this material change ("only": "void")
  std::string field;               ///< the shape's JSON path ("shapes[2]"), for messages
};

/// A count given in a scene either absolutely or scaled by a power of N: it resolves to
/// round(value * N^n_power), halves away from zero.
struct ScaledCount {
  double value = 0;  ///< the number written in the file
  int n_power = 0;   ///< 0: absolute ("rate", "start"); 1: per N ("start_per_n"); 2: per N^2 ("rate_per_n2")
};

/// An emitter as written in a scene: pours grains into a sphere every tick while active.
struct EmitterDef {
  std::array<double, 3> center{};           ///< centre of the pouring sphere (fractions of N)
  double radius = 0;                        ///< radius of the pouring sphere (fraction of N), > 0
  Material material = Material::Granular;   ///< what it pours (never void)
  ScaledCount rate;                         ///< cells poured per tick ("rate" or "rate_per_n2")
  ScaledCount start;                        ///< first active tick ("start" or "start_per_n"; default 0)
  std::optional<ScaledCount> stop;          ///< first inactive tick ("stop" or "stop_per_n"); none: never stops
  std::string field;                        ///< the emitter's JSON path ("emitters[0]"), for messages
};

/// A parsed scene file. Shapes are applied in order, later ones overwriting earlier ones.
struct Scene {
  std::string name;                  ///< short name ("bowl")
  std::string description;           ///< what the scene shows
  std::string source;                ///< the file (or source name) it was parsed from, for messages
  std::array<double, 3> size{};      ///< grid extent as multiples of N
  int default_n = 0;                 ///< the N used when none is given
  int min_n = 1;                     ///< the smallest N at which the scene makes sense
  std::vector<ShapeDef> shapes;      ///< shapes, applied in order
  std::vector<EmitterDef> emitters;  ///< emitters (possibly none)
};

/// An emitter resolved for one N, in cells: pours `rate` cells of `material` into the sphere
/// (center, radius) at every tick t with start <= t < stop.
struct Emitter {
  Vec3 center;                          ///< centre, in cells
  double radius = 0;                    ///< radius, in cells (> 0)
  Material material = Material::Granular;  ///< what it pours
  std::int64_t rate = 0;                ///< cells per tick (>= 1)
  std::uint64_t start = 0;              ///< first active tick
  std::uint64_t stop = 0;               ///< first inactive tick (UINT64_MAX: never stops)
};

/// A scene built at one N: the starting grid and the emitters in cells.
struct SceneInstance {
  Grid grid;                      ///< the starting cells
  std::vector<Emitter> emitters;  ///< the emitters, resolved for n
  int n = 0;                      ///< the N it was built at
};

/// Parses a scene from JSON text. `source_name` (usually the file path) is quoted in messages.
/// Throws ParseError for malformed JSON (with line and column), nesting deeper than
/// kMaxSceneDepth (checked before parsing), a missing or unknown field, a value of the wrong type,
/// an unknown shape type or material, a negative or non-finite length, a box whose min exceeds its
/// max, a zero size, or a default grid of more than kMaxDefaultGridCells cells; the message names
/// the source, the field path ("shapes[2].radius") and the offending value (an excerpt of at most
/// 60 bytes). Only granular::Error subclasses are thrown.
Scene parse_scene(std::string_view json_text, const std::string& source_name);

/// Reads and parses a scene file. Throws FileError when it cannot be read, is not a regular file
/// (after following symbolic links: a FIFO or device is never opened in a way that blocks) or is
/// larger than kMaxSceneFileBytes; ParseError as parse_scene.
Scene load_scene(const std::filesystem::path& path);

/// The folder holding the shipped scenes: "<asset dir>/scenes", where the asset dir is
/// $GRANULAR_ASSET_DIR when set and non-empty, else the source tree's assets folder when it exists
/// (a build tree), else "../share/granular/assets" beside the running program when it exists (an
/// install, wherever its prefix was moved), else the configured install prefix's.
std::filesystem::path scene_dir();

/// Resolves a scene argument: `name_or_path` itself when it names an existing file, else
/// "<scene_dir()>/<name>.json" when that exists (a trailing ".json" in the name is accepted).
/// Throws InvalidArgument listing the available scene names otherwise.
std::filesystem::path find_scene(std::string_view name_or_path);

/// Names (file stems) of the scenes in scene_dir(), sorted; empty when the folder is missing.
std::vector<std::string> list_scenes();

/// The grid extent of `scene` at size parameter `n` (>= 1): each size fraction times n, rounded
/// to the nearest whole cell (halves up). Throws InvalidArgument when an extent rounds to zero or
/// exceeds kMaxGridExtent; memory is checked where the grid is allocated (instantiate).
Int3 scene_size(const Scene& scene, int n);

/// Builds the scene at size parameter `n` (0: scene.default_n): draws every shape into a grid of
/// scene_size(scene, n) and resolves the emitters to cells. Throws InvalidArgument when n is
/// negative or below scene.min_n, the size is bad, or an emitter resolves to an invalid value
/// (rate below 1, stop before start, centre outside the grid); OutOfMemory when the grid does not fit.
SceneInstance instantiate(const Scene& scene, int n = 0);

/// Pours, for every emitter active at world.tick() (start <= tick < stop), up to `rate` cells of its
/// material into its sphere (World::pour). Call once before each World::step(1). Every active
/// emitter is checked first (a material that is not void, rate >= 0, a finite centre, a radius > 0,
/// a sphere that covers a cell of the grid): when one is invalid, InvalidArgument names it and the
/// world is unchanged. Returns the cells poured, per material.
MaterialCounts run_emitters(World& world, const std::vector<Emitter>& emitters);

/// The same for a world split over ranks (distributed_world.hpp): the same cells as run_emitters on
/// one World of the whole grid. Collective: every rank calls it with the same emitters.
MaterialCounts run_emitters(DistributedWorld& world, const std::vector<Emitter>& emitters);

/// The cells per material of a world that held `before` once emitters poured `poured` (run_emitters'
/// results, summed): every poured cell was a void cell, and no step creates or destroys one.
MaterialCounts counts_after_pouring(MaterialCounts before, const MaterialCounts& poured);

}  // namespace granular
