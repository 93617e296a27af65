#include "io/snapshot_bodies.hpp"

#include <array>
#include <bit>

#include "granular/errors.hpp"
#include "io/little_endian.hpp"

namespace granular {

namespace {

/// A body record's doubles, in file order: half extents, radius, half length, density, position,
/// orientation (w, x, y, z), velocity, angular velocity.
constexpr std::size_t kRecordDoubles = 19;
static_assert(16 + 8 * kRecordDoubles == kBodyRecordBytes);

/// Pointers to the doubles of `def` in file order.
template <class Def>
auto record_doubles(Def& def) {
  auto& p = def.pose;
  return std::array{&def.half_extents.x, &def.half_extents.y, &def.half_extents.z, &def.radius, &def.half_length,
                    &def.density,        &p.position.x,       &p.position.y,       &p.position.z, &p.orientation.w,
                    &p.orientation.x,    &p.orientation.y,    &p.orientation.z,    &p.velocity.x, &p.velocity.y,
                    &p.velocity.z,       &p.angular_velocity.x, &p.angular_velocity.y, &p.angular_velocity.z};
}

}  // namespace

std::vector<std::uint8_t> encode_body_section(const BodyStates& states, const std::string& who) {
  if (states.bodies.size() > kMaxBodies)
    throw InvalidArgument(who + ": " + std::to_string(states.bodies.size()) + " bodies; a world holds at most " +
                          std::to_string(kMaxBodies) + " (kMaxBodies)");
  std::uint64_t cells = 0;
  for (const BodyState& b : states.bodies) cells += b.cells.size();
  std::vector<std::uint8_t> out(std::size_t(body_section_bytes(states.bodies.size(), cells)));
  std::uint8_t* at = out.data();
  put_u64(at, states.next_id);
  at += 8;
  for (std::size_t i = 0; i < states.bodies.size(); ++i) {
    const BodyState& b = states.bodies[i];
    if (unsigned(b.def.shape) > unsigned(BodyShape::Capsule))
      throw InvalidArgument(who + ": bodies[" + std::to_string(i) + "].def.shape = " +
                            std::to_string(unsigned(b.def.shape)) + " is not a BodyShape");
    put_u64(at, b.id);
    put_u32(at + 8, std::uint32_t(b.def.shape));
    put_u32(at + 12, 0);
    at += 16;
    for (const double* v : record_doubles(b.def)) {
      put_u64(at, std::bit_cast<std::uint64_t>(*v));
      at += 8;
    }
    put_u64(at, b.cells.size());
    at += 8;
    for (std::size_t k = 0; k < b.cells.size(); ++k) {
      if (k > 0 && b.cells[k] <= b.cells[k - 1])
        throw InvalidArgument(who + ": bodies[" + std::to_string(i) + "].cells[" + std::to_string(k) + "] = " +
                              std::to_string(b.cells[k]) + " does not follow " + std::to_string(b.cells[k - 1]) +
                              "; a body's cells are ascending grid indices");
      put_u64(at, k == 0 ? b.cells[0] : b.cells[k] - b.cells[k - 1]);
      at += 8;
    }
  }
  return out;
}

BodyStates decode_body_section(std::span<const std::uint8_t> bytes, std::uint32_t count, std::uint64_t cells,
                               const std::string& src) {
  const std::string where = src + ": the body section";
  if (bytes.size() < body_section_bytes(count, 0))
    throw ParseError(where + " holds " + std::to_string(bytes.size()) + " bytes; its " + std::to_string(count) +
                     " bodies need at least " + std::to_string(body_section_bytes(count, 0)));
  BodyStates states;
  states.next_id = get_u64(bytes, 0);
  std::size_t at = 8;
  states.bodies.resize(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string body = where + ", bodies[" + std::to_string(i) + "] at byte " + std::to_string(at);
    if (bytes.size() - at < kBodyRecordBytes + 8)
      throw ParseError(body + ": the section ends inside its record");
    BodyState& b = states.bodies[i];
    b.id = get_u64(bytes, at);
    const std::uint32_t shape = get_u32(bytes, at + 8);
    if (shape > std::uint32_t(BodyShape::Capsule))
      throw ParseError(body + ": shape (bytes 8..11 of the record) = " + std::to_string(shape) +
                       " is not a BodyShape (0 box, 1 sphere, 2 capsule)");
    b.def.shape = BodyShape(shape);
    if (const std::uint32_t reserved = get_u32(bytes, at + 12); reserved != 0)
      throw ParseError(body + ": reserved field (bytes 12..15 of the record) = " + std::to_string(reserved) +
                       "; it is 0");
    at += 16;
    for (double* v : record_doubles(b.def)) {
      *v = std::bit_cast<double>(get_u64(bytes, at));
      at += 8;
    }
    const std::uint64_t n = get_u64(bytes, at);
    at += 8;
    if (n > (bytes.size() - at) / 8 || n > cells)
      throw ParseError(body + ": cell count " + std::to_string(n) + " is more than the " +
                       std::to_string((bytes.size() - at) / 8) + " the section's bytes hold (the grid has " +
                       std::to_string(cells) + " cells)");
    b.cells.resize(std::size_t(n));
    std::uint64_t cell = 0;
    for (std::uint64_t k = 0; k < n; ++k, at += 8) {
      const std::uint64_t step = get_u64(bytes, at);
      if (k > 0 && step == 0)
        throw ParseError(body + ": cells[" + std::to_string(k) + "] repeats the cell before it (a gap of 0)");
      if (k == 0 ? step >= cells : step > cells - 1 - cell)
        throw ParseError(body + ": cells[" + std::to_string(k) + "] lies past the grid's " + std::to_string(cells) +
                         " cells");
      cell = k == 0 ? step : cell + step;
      b.cells[std::size_t(k)] = cell;
    }
  }
  if (at != bytes.size())
    throw ParseError(where + " holds " + std::to_string(bytes.size() - at) + " bytes after its last body");
  return states;
}

}  // namespace granular
