#pragma once
/// @file region_edit.hpp
/// One edit of a box of cells by World (a tool or load): the cell bytes read from the backend, what
/// the edit changed in them (the ChangeReport) and the bricks holding a changed cell, kept as the
/// cells change, so that the write needs no further pass over them. World keeps one and reuses its
/// buffers from call to call.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "granular/bricks.hpp"
#include "granular/geometry.hpp"
#include "granular/material.hpp"
#include "granular/motion.hpp"
#include "granular/change_report.hpp"

namespace granular {

/// What an edit makes of each material: material m becomes to[m].
using MaterialMap = std::array<std::uint8_t, kMaterialCount>;

/// The cells of one region being edited, the report of their changes and the flags of the bricks
/// they lie in.
class RegionEdit {
 public:
  /// Where row (y, z) of the region lies in the edit's buffers, addressed by grid x (in the
  /// region's x range).
  struct Row {
    std::size_t cell0 = 0;  ///< index in cells() of the row's cell at x = 0 (may lie before the buffer)
    std::size_t flag0 = 0;  ///< index of the brick flag at brick x = 0 (may lie before the flags)
    /// Index in cells() of the row's cell at `x`.
    std::size_t cell(int x) const { return cell0 + std::size_t(x); }
    /// Index of the flag of the brick holding the row's cell at `x`.
    std::size_t flag(int x) const { return flag0 + std::size_t(unsigned(x) / unsigned(kBrickSize)); }
  };

  /// Starts an edit of `region`, a non-empty box inside a grid of `grid_size`: makes room for its
  /// cells (cells(), for the caller to fill from the backend), an empty report and no brick flagged.
  /// Spheres (map_materials) and positions (origin()) are in the coordinates of a world in which
  /// the grid's cell (0, 0, 0) is cell `origin` (World's slab tools; (0, 0, 0) for a world of its own).
  void begin(const Box& region, Int3 grid_size, Int3 origin = {});
  /// The region being edited.
  const Box& region() const { return region_; }
  /// Where the grid's cell (0, 0, 0) lies in the coordinates of the edit's spheres.
  Int3 origin() const { return origin_; }
  /// The region's cell bytes (x fastest), as the backend holds them, with the edit's changes.
  std::span<std::uint8_t> cells() { return {cells_.data(), count_}; }
  /// The region's cell bytes (x fastest), as the backend holds them, with the edit's changes.
  std::span<const std::uint8_t> cells() const { return {cells_.data(), count_}; }
  /// The places of row (y, z) of the region in the buffers.
  Row row(int y, int z) const {
    const std::size_t rows_before =
        std::size_t(z - region_.min.z) * std::size_t(extent_.y) + std::size_t(y - region_.min.y);
    const std::size_t brick_rows_before = std::size_t(z / kBrickSize - first_brick_.z) * std::size_t(bricks_.y) +
                                          std::size_t(y / kBrickSize - first_brick_.y);
    return {rows_before * std::size_t(extent_.x) - std::size_t(region_.min.x),
            brick_rows_before * std::size_t(bricks_.x) - std::size_t(first_brick_.x)};
  }
  /// The byte of the cell at index `cell`.
  std::uint8_t byte(std::size_t cell) const { return cells_[cell]; }

  /// Gives the cell at index `cell` (in the brick of flag `flag`) material `m`, which differs from
  /// its material, at rest; counts the change in the report and flags the brick.
  void set_material(std::size_t cell, std::size_t flag, std::uint8_t m) {
    const std::uint8_t was = cell_material(cells_[cell]);
    cells_[cell] = m;
    ++report_.cells_changed;
    ++report_.removed[was];
    ++report_.added[m];
    flags_[flag] = 1;
  }
  /// Sets the byte of the cell at index `cell` (in the brick of flag `flag`) to `byte`, which holds
  /// the same material and another motion state; counts the cell as shaken and flags the brick.
  void set_motion(std::size_t cell, std::size_t flag, std::uint8_t byte) {
    cells_[cell] = byte;
    ++report_.cells_shaken;
    flags_[flag] = 1;
  }
  /// Sets the byte of the cell at index `cell` (in the brick of flag `flag`) to `byte` and flags the
  /// brick, counting nothing: the cells a body leaves (world_bodies.cpp), which it reports itself.
  void put(std::size_t cell, std::size_t flag, std::uint8_t byte) {
    cells_[cell] = byte;
    flags_[flag] = 1;
  }
  /// Flags the bricks of the cells at indices `cells` (into cells()), which the caller wrote itself,
  /// counting nothing: a body's stamp (bodies/body_stamp.hpp), which reports its own.
  void flag_written(std::span<const std::uint32_t> cells);
  /// Each cell of the region whose material m is not to[m] gets material to[m], at rest, counted
  /// in the report, its brick flagged.
  void map_materials(const MaterialMap& to);
  /// Each cell of the region whose centre lies in `sphere` and whose material m is not to[m] gets
  /// material to[m], at rest, counted in the report, its brick flagged.
  void map_materials(const Sphere& sphere, const MaterialMap& to);
  /// Each cell of the region whose byte differs from `bytes`' (a byte per cell, x fastest) gets that
  /// byte, motion state and all, its brick flagged; not counted in the report (a slab's halo taking
  /// its neighbour's cells).
  void replace_bytes(std::span<const std::uint8_t> bytes);
  /// Each cell of the region whose material is not `after`'s (a material per cell, x fastest) gets
  /// that material, at rest, counted in the report, its brick flagged.
  void put_materials(std::span<const std::uint8_t> after);

  /// The report so far: cells changed per material and cells shaken (region and clipped left for
  /// the caller).
  const ChangeReport& report() const { return report_; }
  /// The grid indices (ascending) of the bricks holding a cell the edit set; empty when it set none.
  std::span<const std::uint32_t> bricks();
  /// Frees buffers a large edit (a load) made large (trim_scratch).
  void trim();

 private:
  // Each cell x in [first, last) of the runs (y, z, first, last) that for_each_run(fn) gives,
  // whose index in cells() is i and material `was`, gets material new_material(i, was) when that
  // differs, at rest, counted in the report, its brick flagged: the one loop of map_materials and
  // put_materials.
  template <class ForEachRun, class NewMaterial>
  void set_runs(ForEachRun&& for_each_run, NewMaterial&& new_material);
  // Calls fn(y, z, first, last) for every row of the region, whole.
  template <class Fn>
  void for_each_row(Fn&& fn) const;

  Box region_{};
  Int3 origin_{};       ///< begin's origin
  Int3 extent_{};       ///< cells of the region per axis
  Int3 grid_bricks_{};  ///< bricks of the grid per axis
  Int3 first_brick_{};  ///< brick coordinates of the region's first cell
  Int3 bricks_{};       ///< bricks the region touches per axis
  std::size_t count_ = 0;               ///< cells of the region
  std::vector<std::uint8_t> cells_;     ///< at least count_ bytes
  std::vector<std::uint8_t> flags_;     ///< per brick the region touches (x fastest): 1 when a cell in it was set
  std::vector<std::uint32_t> list_;     ///< the flagged bricks' grid indices (bricks())
  ChangeReport report_{};
};

}  // namespace granular
