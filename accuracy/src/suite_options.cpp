#include "granular/accuracy/suite_options.hpp"

#include "granular/errors.hpp"

namespace granular::accuracy {

WorldDef test_world_def(const SuiteOptions& options, Int3 size) {
  WorldDef def;
  def.size = size;
  def.rules = options.rules;
  def.seed = options.seed;
  def.backend = options.backend;
  def.threads = options.threads;
  def.sparse = options.sparse;
  def.lut_cache_dir = options.lut_cache_dir;
  return def;
}

void log_line(const SuiteOptions& options, const std::string& line) {
  if (options.log) options.log(line);
}

TargetMaterial target_material(const std::string& name) {
  if (name == "sand") return {"dry sand", 33};
  if (name == "glass") return {"glass beads", 24};
  throw InvalidArgument("unknown target material '" + name + "'; valid materials: sand (dry sand, 33 deg), glass (glass beads, 24 deg)");
}

}  // namespace granular::accuracy
