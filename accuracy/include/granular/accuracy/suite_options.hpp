#pragma once
/// @file suite_options.hpp
/// What every accuracy test takes: the configuration (rules, backend, threads, seed), the size of
/// the run (quick for CI, full for a GPU), the target material and the calibration.

#include <cstdint>
#include <functional>
#include <string>

#include "granular/accuracy/calibration.hpp"
#include "granular/geometry.hpp"
#include "granular/world_def.hpp"

namespace granular::accuracy {

/// A material's reference angle of repose.
struct TargetMaterial {
  std::string name = "dry sand";  ///< e.g. "dry sand", "glass beads"
  double repose_deg = 33;         ///< its angle of repose in degrees
};

/// Options shared by every test of the suite.
struct SuiteOptions {
  std::string rules = "paper";                ///< rule-set preset
  BackendKind backend = BackendKind::Cpu;     ///< compute backend
  int threads = 0;                            ///< CPU threads (0 = all)
  bool sparse = WorldDef{}.sparse;            ///< step only bricks where something may move (same result as dense)
  std::uint64_t seed = 1;                     ///< world seed
  bool quick = false;                         ///< reduced sizes (CI, a couple of CPU cores); false = full size (GPU)
  TargetMaterial material;                    ///< the repose-angle reference
  Calibration calibration;                    ///< physical units
  std::string lut_cache_dir;                  ///< table cache folder (empty = the default)
  std::function<void(const std::string&)> log;  ///< progress lines (may be empty)
};

/// The WorldDef of a test world of `size` cells under `options`.
WorldDef test_world_def(const SuiteOptions& options, Int3 size);

/// Calls options.log(line) when set.
void log_line(const SuiteOptions& options, const std::string& line);

/// The known target materials: "sand" (dry sand, 33 deg) and "glass" (glass beads, 24 deg).
/// Throws InvalidArgument naming the valid ones for an unknown name.
TargetMaterial target_material(const std::string& name);

}  // namespace granular::accuracy
