#include "bodies/body_forces.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "bodies/body_region.hpp"
#include "bodies/body_shape.hpp"
#include "granular/motion.hpp"

namespace granular {

namespace {

Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3 operator*(const Vec3& a, double k) { return {a.x * k, a.y * k, a.z * k}; }
double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double length(const Vec3& a) { return std::sqrt(dot(a, a)); }

/// The drag of a face moving along itself, as a share of the drag of one moving across: skin
/// friction against form drag.
constexpr double kSkinFriction = 0.1;

/// One layer of the body: its cells, their centroid's sums, and the materials beside it.
struct Layer {
  std::int64_t cells = 0;
  double sum_x = 0, sum_y = 0;
  MaterialCounts beside{};
  std::int64_t beside_total = 0;  ///< non-static cells beside it
};

}  // namespace

void sand_forces(const Box& box, std::span<const std::uint8_t> bytes, Int3 grid,
                 const std::vector<std::uint64_t>& owned, const MaterialTable& materials, const BodyPose& pose,
                 double mass, double moment, const BodyScale& scale, BodySand& sand, ForceScratch& s) {
  const BodyRegion region(box);
  const std::size_t volume = region.volume();
  // A cell outside the region lies outside the grid (the region holds the body and a margin where the
  // grid has one), and reads as static there, as it does to the rules.
  constexpr std::uint8_t kOutside = to_cell(Material::Solid);
  std::array<bool, kMaterialCount> static_material{};
  for (std::size_t m = 0; m < kMaterialCount; ++m) static_material[m] = materials[m].behaviour == Behaviour::Static;
  static_material[kOutside] = true;  // past the grid, and every solid cell
  auto is_static = [&](std::uint8_t m) { return static_material[m]; };

  s.owned.assign(volume, 0);
  cells_at(owned, grid, s.owned_at);
  for (const Int3 c : s.owned_at) s.owned[region.local(c)] = 1;

  const double cell_volume = scale.cell_m * scale.cell_m * scale.cell_m;
  const double face_area = scale.cell_m * scale.cell_m;
  const Vec3 velocity = pose.velocity * (scale.cell_m / scale.tick_s);  // m/s
  const Vec3 spin = pose.angular_velocity * (1.0 / scale.tick_s);       // rad/s
  // Below the speed of a gravity wave a cell deep the drag grows with the speed, not its square, so
  // that a floating body's small swings die out (as waves carry their energy away).
  const double slow = std::sqrt(scale.gravity * scale.cell_m);  // m/s
  constexpr std::array<Int3, 6> kFaces{Int3{1, 0, 0},  Int3{-1, 0, 0}, Int3{0, 1, 0},
                                       Int3{0, -1, 0}, Int3{0, 0, 1},  Int3{0, 0, -1}};
  const std::array<std::int64_t, 6> face_step{
      1, -1, region.e.x, -region.e.x, std::int64_t(region.e.x) * region.e.y, -std::int64_t(region.e.x) * region.e.y};

  std::vector<Layer> layers(std::size_t(region.e.z));
  // Each layer's surroundings: the cells of the layer within kRingWidth cells (in x and y) of a cell
  // of it on its edge, so that a grain toppling beside the body changes them by little.
  for_each_cell_beside(region, s.owned_at, kRingWidth, s.rows, [&](std::uint32_t i, int z) {
    const std::uint8_t m = std::uint8_t(bytes[i] & kMaterialMask);
    if (is_static(m)) return;
    Layer& layer = layers[std::size_t(z)];
    ++layer.beside[m];
    ++layer.beside_total;
  });
  sand.cells = std::int64_t(owned.size());
  sand.below = {};
  sand.submerged = {};
  Vec3 drag{}, drag_torque{};
  for (const Int3 c : s.owned_at) {
    Layer& layer = layers[std::size_t(c.z - box.min.z)];
    ++layer.cells;
    layer.sum_x += c.x + 0.5;
    layer.sum_y += c.y + 0.5;
    // Per face (kFaces): the cell beside it, whether the body holds it, and its material.
    const std::uint32_t at = region.local(c);
    const Int3 l{c.x - box.min.x, c.y - box.min.y, c.z - box.min.z};
    const std::array<bool, 6> in{l.x + 1 < region.e.x, l.x > 0, l.y + 1 < region.e.y, l.y > 0,
                                 l.z + 1 < region.e.z, l.z > 0};
    auto held = [&](int k) { return in[k] && s.owned[std::size_t(at + face_step[k])] != 0; };
    auto material_at = [&](int k) {
      return in[k] ? std::uint8_t(bytes[std::size_t(at + face_step[k])] & kMaterialMask) : kOutside;
    };
    if (!held(5)) ++sand.below[material_at(5)];
    for (int face = 0; face < 6; ++face) {  // the drag of the faces against a material
      if (held(face)) continue;
      const Int3 f = kFaces[std::size_t(face)];
      const std::uint8_t m = material_at(face);
      if (is_static(m)) continue;
      const BodyCoupling& k = materials[m].body;
      if (k.bulk_density <= 0 || k.drag <= 0) continue;
      const Vec3 normal{double(f.x), double(f.y), double(f.z)};
      const Vec3 r = (Vec3{c.x + 0.5, c.y + 0.5, c.z + 0.5} + normal * 0.5 - pose.position) * scale.cell_m;
      const Vec3 v = velocity + cross(spin, r);
      const double u = dot(v, normal);
      const Vec3 along = v - normal * u;
      const Vec3 push = (normal * ((std::abs(u) + slow) * u) + along * (kSkinFriction * (length(along) + slow))) *
                        (-0.5 * k.drag * k.bulk_density * face_area);
      drag = drag + push;
      drag_torque = drag_torque + cross(r, push);
    }
  }

  // Buoyancy, layer by layer, at the layers' centroids. The cells stand for the shape to the nearest
  // cell, so each layer reads its surroundings `shift` cells up, between its own and the next
  // layer's (the shape's centre above the centroid of its cells), and the lift changes smoothly with
  // the pose instead of by whole layers.
  double sum_z = 0;
  for (const Int3 c : s.owned_at) sum_z += c.z + 0.5;
  const double shift = owned.empty() ? 0.0 : std::clamp(pose.position.z - sum_z / double(owned.size()), -0.5, 0.5);
  // The share of material m beside layer z, reading the nearest layer with surroundings past the ends.
  auto share = [&](std::ptrdiff_t z, int m) {
    z = std::clamp<std::ptrdiff_t>(z, 0, std::ptrdiff_t(layers.size()) - 1);
    const Layer& layer = layers[std::size_t(z)];
    return layer.beside_total == 0 ? 0.0 : double(layer.beside[std::size_t(m)]) / double(layer.beside_total);
  };
  const std::ptrdiff_t toward = shift >= 0 ? 1 : -1;
  const double weight = std::abs(shift);
  double lift = 0, stiffness = 0;  // N, and N/m the lift falls by as the body rises
  Vec3 lift_torque{};
  for (std::size_t z = 0; z < layers.size(); ++z) {
    const Layer& layer = layers[z];
    if (layer.cells == 0) continue;
    std::ptrdiff_t beside_z = std::ptrdiff_t(z) + toward;
    if (beside_z < 0 || beside_z >= std::ptrdiff_t(layers.size()) || layers[std::size_t(beside_z)].cells == 0)
      beside_z = std::ptrdiff_t(z);  // past the body's ends: its own layer's surroundings
    double density = 0, own = 0, beside = 0;
    for (int m = 0; m < kMaterialCount; ++m) {
      const double bulk = materials[std::size_t(m)].body.bulk_density;
      own += share(std::ptrdiff_t(z), m) * bulk;
      beside += share(beside_z, m) * bulk;
      const double part = (1 - weight) * share(std::ptrdiff_t(z), m) + weight * share(beside_z, m);
      if (part == 0) continue;
      sand.submerged[std::size_t(m)] += double(layer.cells) * part;
      density += part * bulk;
    }
    stiffness -= scale.gravity * cell_volume / scale.cell_m * double(layer.cells) * double(toward) * (beside - own);
    const double f = scale.gravity * cell_volume * double(layer.cells) * density;
    lift += f;
    const Vec3 at{layer.sum_x / double(layer.cells), layer.sum_y / double(layer.cells), box.min.z + double(z) + 0.5};
    lift_torque = lift_torque + cross((at - pose.position) * scale.cell_m, Vec3{0, 0, f});
  }
  // The lift as an implicit step over the tick gives it, the body's weight m g down: a light body
  // whose lift changes steeply with its height (a cork ball in sand) would otherwise swing further
  // each tick, its force a tick late.
  if (stiffness > 0 && mass > 0) {
    const double weight_n = mass * scale.gravity, dt = scale.tick_s;
    const double implicit =
        weight_n + (lift - weight_n - stiffness * dt * velocity.z) / (1 + stiffness * dt * dt / mass);
    if (lift > 0) lift_torque = lift_torque * (implicit / lift);
    lift = implicit;
  }
  sand.buoyancy = {0, 0, lift};

  // The momentum of what it pushed, then the clamp.
  double pushed_mass = 0;
  for (int m = 0; m < kMaterialCount; ++m)
    pushed_mass += materials[std::size_t(m)].body.push * materials[std::size_t(m)].body.bulk_density * cell_volume *
                   double(sand.displaced[std::size_t(m)]);
  drag = drag - velocity * (pushed_mass / scale.tick_s);
  // The drag a tick's explicit step can take: for a drag D against momentum p, D / (1 + D dt / p),
  // what an implicit step of the tick gives (the body keeps p / (1 + D dt / p)), never more than
  // stops it, and D itself where the drag changes the motion little.
  const double momentum = mass * length(velocity), got = length(drag) * scale.tick_s;
  if (got > 0) drag = drag * (momentum / (momentum + got));
  const double spin_momentum = moment * length(spin), got_torque = length(drag_torque) * scale.tick_s;
  if (got_torque > 0) drag_torque = drag_torque * (spin_momentum / (spin_momentum + got_torque));
  sand.drag = drag;
  sand.force = sand.buoyancy + drag;
  sand.torque = lift_torque + drag_torque;
  sand.mass = mass;
}

}  // namespace granular
