#include "bodies/body_watch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace viewer {

namespace {

constexpr double kGravity = 9.81;  // m/s^2

double distance(granular::Vec3 a, granular::Vec3 b) {
  return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
}

}  // namespace

BodyWatch::BodyWatch(const granular::MaterialTable& materials, double tick_seconds, double cell_metres)
    : materials_(materials) {
  if (!std::isfinite(tick_seconds) || tick_seconds <= 0 || !std::isfinite(cell_metres) || cell_metres <= 0)
    throw std::invalid_argument("BodyWatch: tick_seconds = " + std::to_string(tick_seconds) +
                                " and cell_metres = " + std::to_string(cell_metres) + " must be finite and > 0");
  g_cells_ = kGravity * tick_seconds * tick_seconds / cell_metres;
}

void BodyWatch::follow(granular::BodyId id, std::uint64_t tick, granular::Vec3 position, granular::Vec3 velocity,
                       bool thrown) {
  Followed body;
  body.announce = thrown;
  body.start_tick = tick;
  body.start = position;
  body.velocity = velocity;
  followed_[id] = body;
}

void BodyWatch::keep_only(const std::vector<granular::BodyId>& ids) {
  std::erase_if(followed_,
                [&](const auto& entry) { return std::find(ids.begin(), ids.end(), entry.first) == ids.end(); });
}

double BodyWatch::fall_ticks(double z0, double vz, double z, double g_cells) {
  const double discriminant = vz * vz + 2 * g_cells * (z0 - z);
  if (discriminant < 0) return 0;
  return (vz + std::sqrt(discriminant)) / g_cells;
}

int BodyWatch::touched(const granular::BodySand& sand) const {
  int best = -1;
  double most = 0;
  for (int m = 0; m < granular::kMaterialCount; ++m) {
    const granular::Behaviour b = materials_[std::size_t(m)].behaviour;
    if (b == granular::Behaviour::Void || b == granular::Behaviour::Gas) continue;
    const double cells =
        sand.submerged[std::size_t(m)] + double(sand.below[std::size_t(m)]) + double(sand.displaced[std::size_t(m)]);
    if (cells > most) {
      most = cells;
      best = m;
    }
  }
  return best;
}

double BodyWatch::submerged(const granular::BodySand& sand) {
  double cells = 0;
  for (int m = 1; m < granular::kMaterialCount; ++m) cells += sand.submerged[std::size_t(m)];
  return sand.cells > 0 ? cells / double(sand.cells) : 0;
}

std::vector<std::string> BodyWatch::observe(std::uint64_t tick, const std::vector<BodyReading>& bodies) {
  std::vector<std::string> lines;
  char line[320];
  for (const BodyReading& reading : bodies) {
    const auto it = followed_.find(reading.id);
    if (it == followed_.end() || reading.sand == nullptr) continue;
    Followed& body = it->second;
    const double elapsed = double(tick) - double(body.start_tick);
    const int material = touched(*reading.sand);
    if (!body.announce && body.recent.empty() && material >= 0) body.landed = true;  // brought back lying there
    if (!body.landed && material >= 0) {
      body.landed = true;
      const double fall = fall_ticks(body.start.z, body.velocity.z, reading.position.z, g_cells_);
      std::snprintf(line, sizeof(line),
                    "body %u: landed in %s at tick %llu, %.0f ticks after the throw, centre at z %.1f "
                    "(a free fall from z %.1f takes %.1f ticks)",
                    unsigned(reading.id), materials_[std::size_t(material)].name.c_str(),
                    static_cast<unsigned long long>(tick), elapsed, reading.position.z, body.start.z, fall);
      lines.emplace_back(line);
    }
    body.recent.push_back(reading.position);
    if (int(body.recent.size()) > kRestTicks) body.recent.pop_front();
    const bool still = int(body.recent.size()) == kRestTicks &&
                       std::all_of(body.recent.begin(), body.recent.end(),
                                   [&](granular::Vec3 p) { return distance(p, reading.position) <= kRestCells; });
    if (body.landed && still && !body.resting) {
      body.resting = true;
      body.rest_at = reading.position;
      const granular::Vec3 p = reading.position;
      const std::string in = material >= 0 ? materials_[std::size_t(material)].name : std::string("nothing");
      std::snprintf(line, sizeof(line),
                    "body %u: at rest at tick %llu, %.0f ticks after the throw: centre (%.1f, %.1f, %.1f), bottom "
                    "%.1f cells up, %.0f%% submerged, on or in %s",
                    unsigned(reading.id), static_cast<unsigned long long>(tick), elapsed, p.x, p.y, p.z, reading.bottom,
                    100 * submerged(*reading.sand), in.c_str());
      lines.emplace_back(line);
    } else if (body.resting && distance(reading.position, body.rest_at) > kMovedCells) {
      body.resting = false;  // moved on (a tool, another body): it may come to rest once more
    }
  }
  return lines;
}

}  // namespace viewer
