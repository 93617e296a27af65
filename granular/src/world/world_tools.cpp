#include "granular/world.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "granular/errors.hpp"
#include "granular/motion.hpp"
#include "granular/rule_set.hpp"
#include "step/step_materials.hpp"
#include "world/pour_choice.hpp"
#include "world/region_edit.hpp"
#include "world/sphere_runs.hpp"
#include "world/tool_region.hpp"
#include "world/world_scratch.hpp"

namespace granular {

ChangeReport World::finish_tool(bool clipped) {
  if (tool_calls_ == std::numeric_limits<std::uint64_t>::max())
    throw StateError("World: a tool call after " + std::to_string(tool_calls_) +
                     " would wrap the 64-bit tool-call counter; no cell was changed");
  write_edit();
  ChangeReport report = scratch_->edit.report();
  report.region = scratch_->edit.region();
  report.clipped = clipped;
  ++tool_calls_;
  return report;
}

Box World::tool_box(const Box& region) const {
  if (!slab_tools_) return region;
  const Int3 o = slab_tools_->origin;
  const Box in = intersect(Box{{region.min.x - o.x, region.min.y - o.y, region.min.z - o.z},
                               {region.max.x - o.x, region.max.y - o.y, region.max.z - o.z}},
                           slab_tools_->owned);
  if (in.empty())
    throw StateError("World: a tool's region " + box_string(region) + " misses the cells this slab owns, " +
                     box_string(slab_tools_->owned) + " from " + to_string(o));
  return in;
}

std::vector<std::uint64_t> World::pour_keys(const Sphere& sphere, std::size_t amount) {
  bool clipped = false;
  const Box region = tool_box(sphere_region(sphere, tool_space(), "pour", clipped));
  RegionEdit& edit = begin_edit(region);
  std::vector<std::uint64_t> keys;
  for (const PourCandidate& c :
       scratch_->pour.choose(edit, sphere, pour_salt(def_.seed, tick_, tool_calls_), amount))
    keys.push_back(c.key);
  edit.trim();
  scratch_->pour.trim();
  return keys;
}

ChangeReport World::dig(const Sphere& sphere) {
  bool clipped = false;
  const Box region = tool_box(sphere_region(sphere, tool_space(), "dig", clipped));
  const MaterialTable& table = rules().materials;
  MaterialMap to{};
  for (std::size_t m = 0; m < to.size(); ++m)
    to[m] = table[m].behaviour == Behaviour::Static ? std::uint8_t(m) : to_cell(Material::Void);
  begin_edit(region).map_materials(sphere, to);
  return finish_tool(clipped);
}

ChangeReport World::shake(const Sphere& sphere, int level) {
  check_shake(rules(), level);
  bool clipped = false;
  const Box region = tool_box(sphere_region(sphere, tool_space(), "shake", clipped));
  const StepMaterials mats = step_materials(rules().materials);
  RegionEdit& edit = begin_edit(region);
  for_each_run_in_sphere(region, sphere, [&](int y, int z, int first, int last) {
    const RegionEdit::Row row = edit.row(y, z);
    for (int x = first; x < last; ++x) {
      const std::uint8_t cell = edit.byte(row.cell(x));
      if (!mats.is_faller(cell_material(cell))) continue;
      const std::uint8_t shaken = with_motion(cell, level);
      if (shaken != cell) edit.set_motion(row.cell(x), row.flag(x), shaken);
    }
  }, edit.origin());
  return finish_tool(clipped);
}

ChangeReport World::pour(Vec3 center, double radius, Material material, std::int64_t amount) {
  const Sphere sphere{center, radius};
  bool clipped = false;
  const Box region = tool_box(check_pour(sphere, material, amount, tool_space(), clipped));
  RegionEdit& edit = begin_edit(region);
  const std::uint64_t salt = pour_salt(def_.seed, tick_, tool_calls_);
  for (const PourCandidate& c : scratch_->pour.choose(edit, sphere, salt, std::size_t(amount))) {
    const Int3 g = unpack_position(c.position), o = edit.origin();
    const Int3 p{g.x - o.x, g.y - o.y, g.z - o.z};
    const RegionEdit::Row row = edit.row(p.y, p.z);
    edit.set_material(row.cell(p.x), row.flag(p.x), to_cell(material));
  }
  scratch_->pour.trim();
  return finish_tool(clipped);
}

ChangeReport World::paint(const Box& box, Material material) {
  bool clipped = false;
  const Box region = tool_box(check_paint_box(box, material, tool_space(), clipped));
  MaterialMap to{};
  to.fill(to_cell(material));
  begin_edit(region).map_materials(to);
  return finish_tool(clipped);
}

ChangeReport World::paint(const Sphere& sphere, Material material) {
  check_tool_material(material, "paint");
  bool clipped = false;
  const Box region = tool_box(sphere_region(sphere, tool_space(), "paint", clipped));
  MaterialMap to{};
  to.fill(to_cell(material));
  begin_edit(region).map_materials(sphere, to);
  return finish_tool(clipped);
}

}  // namespace granular
