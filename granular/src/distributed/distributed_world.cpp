#include "granular/distributed/distributed_world.hpp"

#include <algorithm>
#include <array>
#include <exception>
#include <cstring>
#include <limits>
#include <optional>
#include <string>

#include "granular/extend/backend.hpp"
#include "granular/errors.hpp"
#include "granular/extend/hex.hpp"
#include "granular/rule_presets.hpp"
#include "granular/rule_set.hpp"
#include "granular/world_snapshot.hpp"
#include "world/region_edit.hpp"
#include "world/tool_region.hpp"
#include "util/stopwatch.hpp"

namespace granular {

namespace {

/// Bytes of one layer of a grid of `size`.
std::size_t layer_bytes(Int3 size) { return std::size_t(size.x) * std::size_t(size.y); }

/// What every rank must agree on: the whole grid's size, the seed and the rule set.
struct WorldIdentity {
  std::uint64_t made = 0;  ///< 1 when this rank could make its layout
  std::uint64_t x = 0, y = 0, z = 0, seed = 0, fingerprint = 0;
};

/// "16x16x64, seed 1, rules 'paper' (fingerprint 0x...)" for messages.
std::string describe(const WorldIdentity& w, const std::string& rules) {
  return std::to_string(w.x) + "x" + std::to_string(w.y) + "x" + std::to_string(w.z) + ", seed " + std::to_string(w.seed) +
         ", rules '" + rules + "' (fingerprint " + hex64(w.fingerprint) + ")";
}

/// The split of `size` over the ranks of `comm` with the halo `def`'s rules need, once every rank
/// has made it and all agree on the world (size, seed, rule set): a rank that cannot make it, or
/// ranks given different worlds, throw on every rank, so none goes on with a layout the others do
/// not share. Collective.
SlabLayout make_layout(const WorldDef& def, Communicator& comm, Int3 size) {
  std::exception_ptr failure;
  std::optional<SlabLayout> layout;
  WorldIdentity mine;
  std::string rules_name;
  try {
    if (!(def.domain_origin == Int3{}))
      throw InvalidArgument("DistributedWorld: WorldDef::domain_origin = " + to_string(def.domain_origin) +
                            "; a distributed world is a whole world (0, 0, 0), and places its slabs itself");
    const std::shared_ptr<const RuleSet> rules = def.rule_set ? def.rule_set : make_rule_set(def.rules);
    if (rules->motion.pressure)
      throw InvalidArgument("DistributedWorld: rule set '" + rules->name +
                            "' has RuleSet::motion.pressure = true; the head of a liquid body is the highest surface "
                            "of the whole body, which a slab cannot see: run it as one World, or turn pressure off");
    if (rules->motion.trains)
      throw InvalidArgument("DistributedWorld: rule set '" + rules->name +
                            "' has RuleSet::motion.trains = true; a falling train closes its gaps along its whole "
                            "column, which may cross a slab: run it as one World, or turn trains off");
    if (rules->motion.shallow)
      throw InvalidArgument("DistributedWorld: rule set '" + rules->name +
                            "' has RuleSet::motion.shallow = true; the shallow-water pass counts the liquid of whole "
                            "columns, which cross the slabs: run it as one World, or turn shallow off");
    layout.emplace(size, comm.size(), SlabLayout::halo_for(*rules));
    mine = {1, std::uint64_t(size.x), std::uint64_t(size.y), std::uint64_t(size.z), def.seed, rule_fingerprint(*rules)};
    rules_name = rules->name;
  } catch (...) {
    failure = std::current_exception();
  }
  const auto names = all_gather_bytes(comm, {reinterpret_cast<const std::uint8_t*>(rules_name.data()), rules_name.size()});
  std::vector<WorldIdentity> every(std::size_t(comm.size()));
  comm.all_gather({reinterpret_cast<const std::uint8_t*>(&mine), sizeof mine},
                  {reinterpret_cast<std::uint8_t*>(every.data()), every.size() * sizeof(WorldIdentity)});
  if (failure) std::rethrow_exception(failure);
  for (std::size_t r = 0; r < every.size(); ++r)
    if (!every[r].made) throw CommunicatorError("DistributedWorld: rank " + std::to_string(r) + " could not make its slab's layout");
  const auto name_of = [&](std::size_t r) { return std::string(names[r].begin(), names[r].end()); };
  for (std::size_t r = 1; r < every.size(); ++r) {
    const WorldIdentity& a = every[0];
    const WorldIdentity& b = every[r];
    const char* field = a.x != b.x || a.y != b.y || a.z != b.z ? "size"
                        : a.seed != b.seed                     ? "seed"
                        : a.fingerprint != b.fingerprint       ? "rules"
                                                               : nullptr;
    if (field)
      throw InvalidArgument(std::string("DistributedWorld: the ranks were given different worlds (their ") + field +
                            " differs): rank 0 has " + describe(a, name_of(0)) + ", rank " + std::to_string(r) + " has " +
                            describe(b, name_of(r)) + "; every rank must pass the same WorldDef and the same grid, snapshot or file");
  }
  return std::move(*layout);
}

/// A snapshot of no cells: the header fields.
WorldSnapshot snapshot_header(Int3 size, std::uint64_t tick, std::uint64_t seed, std::uint64_t tool_calls,
                              const std::string& rules, std::uint64_t rule_fingerprint) {
  WorldSnapshot h;
  h.size = size;
  h.tick = tick;
  h.seed = seed;
  h.tool_calls = tool_calls;
  h.rules = rules;
  h.rule_fingerprint = rule_fingerprint;
  return h;
}

/// The cells of the layers a slab keeps, out of the whole grid's `cells`.
std::span<const std::uint8_t> kept_cells(std::span<const std::uint8_t> cells, Int3 size, const Slab& slab) {
  return cells.subspan(std::size_t(slab.local_z0) * layer_bytes(size),
                       std::size_t(slab.local_z1 - slab.local_z0) * layer_bytes(size));
}

}  // namespace

DistributedWorld::DistributedWorld(const WorldDef& def, Communicator& comm)
    : DistributedWorld(def, comm, def.size, [](const WorldDef& local, const Slab&) { return std::make_unique<World>(local); }) {}

DistributedWorld::DistributedWorld(const WorldDef& def, Communicator& comm, const Grid& whole)
    : DistributedWorld(def, comm, whole.size(), [&](const WorldDef& local, const Slab& slab) {
        Grid initial(local.size);
        const std::span<const std::uint8_t> kept = kept_cells(whole.cells(), whole.size(), slab);
        std::copy(kept.begin(), kept.end(), initial.cells().begin());
        return std::make_unique<World>(local, initial);
      }) {}

DistributedWorld::DistributedWorld(const WorldDef& def, Communicator& comm, const WorldSnapshot& snapshot)
    : DistributedWorld(def, comm, snapshot.size, [&](const WorldDef& local, const Slab& slab) {
        const Int3 size = snapshot.size;
        if (snapshot.cells.size() != std::size_t(size.x) * std::size_t(size.y) * std::size_t(size.z))
          throw InvalidArgument("DistributedWorld: WorldSnapshot::cells holds " + std::to_string(snapshot.cells.size()) +
                                " bytes; its " + to_string(size) + " grid has another number of cells");
        if (!snapshot.bodies.bodies.empty())
          throw InvalidArgument("DistributedWorld: WorldSnapshot::bodies holds " +
                                std::to_string(snapshot.bodies.bodies.size()) + " bodies; a DistributedWorld holds none");
        if (!snapshot.side.empty() || !snapshot.faces.empty())
          throw InvalidArgument(std::string("DistributedWorld: WorldSnapshot::") +
                                (snapshot.side.empty() ? "faces" : "side") +
                                " holds a plane (MotionParams::momentum or shallow), which a DistributedWorld cannot step");
        WorldSnapshot part = snapshot_header(snapshot.size, snapshot.tick, snapshot.seed, snapshot.tool_calls,
                                             snapshot.rules, snapshot.rule_fingerprint);
        part.size = local.size;
        const std::span<const std::uint8_t> kept = kept_cells(snapshot.cells, size, slab);
        part.cells.assign(kept.begin(), kept.end());
        return std::make_unique<World>(local, part);
      }) {}

DistributedWorld::DistributedWorld(const WorldDef& def, Communicator& comm, Int3 size,
                                   const std::function<std::unique_ptr<World>(const WorldDef&, const Slab&)>& make_slab)
    : comm_(comm), layout_(make_layout(def, comm, size)), slab_range_(layout_.slab(comm.rank())) {
  WorldDef local = def;
  local.size = {size.x, size.y, slab_range_.local_z1 - slab_range_.local_z0};
  local.domain_origin = {0, 0, slab_range_.local_z0};
  // A rank that cannot make its World (memory, a backend) fails every rank, so none waits for it.
  std::exception_ptr failure;
  try {
    slab_ = make_slab(local, slab_range_);
    slab_->slab_tools_ = World::SlabTools{
        local.domain_origin, size,
        Box{{0, 0, slab_range_.z0 - slab_range_.local_z0}, {size.x, size.y, slab_range_.z1 - slab_range_.local_z0}}};
  } catch (...) {
    failure = std::current_exception();
  }
  if (!all_true(comm_, !failure)) {
    if (failure) std::rethrow_exception(failure);
    throw CommunicatorError("DistributedWorld: another rank could not make its slab's World");
  }
}

DistributedWorld::~DistributedWorld() = default;

void DistributedWorld::read_layers(int z0, int z1, std::span<std::uint8_t> out) const {
  const Int3 size = layout_.size();
  // Whole bytes, motion state included (World::read_region reports materials).
  slab_->live().read(Box{{0, 0, z0 - slab_range_.local_z0}, {size.x, size.y, z1 - slab_range_.local_z0}}, out);
}

void DistributedWorld::write_halo(int z0, std::span<const std::uint8_t> bytes) {
  const Int3 size = layout_.size();
  const int layers = int(bytes.size() / layer_bytes(size));
  RegionEdit& edit = slab_->begin_edit(Box{{0, 0, z0 - slab_range_.local_z0}, {size.x, size.y, z0 + layers - slab_range_.local_z0}});
  edit.replace_bytes(bytes);
  slab_->write_edit();
}

bool DistributedWorld::changed_since_exchange(int z0, int z1) const {
  // A brick changed when a step or a write (a tool, a halo) gave it a version after the last
  // exchange's (World::bricks_changed_since, for the bricks of these layers only).
  slab_->take_step_changes();
  const Int3 bricks = slab_->brick_counts();
  const std::size_t per_layer = std::size_t(bricks.x) * std::size_t(bricks.y);
  const int first = (z0 - slab_range_.local_z0) / kBrickSize, last = (z1 - 1 - slab_range_.local_z0) / kBrickSize;
  for (std::size_t i = std::size_t(first) * per_layer; i < std::size_t(last + 1) * per_layer; ++i)
    if (slab_->brick_version_[i] > exchange_version_) return true;
  return false;
}

void DistributedWorld::exchange_halos() {
  const int below = comm_.rank() > 0 ? comm_.rank() - 1 : Communicator::kNoRank;
  const int above = comm_.rank() + 1 < comm_.size() ? comm_.rank() + 1 : Communicator::kNoRank;
  const int halo = layout_.halo();
  const Slab& s = slab_range_;
  // A halo needs its neighbour's layers when they changed since the last exchange, or when the
  // halo did (a slab steps its halo too, wrongly near its far edge): otherwise it holds them
  // already. Each side says what changed on its side of a boundary; both then know which layers
  // travel.
  std::uint8_t to_below[2] = {}, to_above[2] = {}, from_below[2] = {}, from_above[2] = {};
  if (below != Communicator::kNoRank) {
    to_below[0] = changed_since_exchange(s.z0, s.z0 + halo);  // what I send down
    to_below[1] = changed_since_exchange(s.z0 - halo, s.z0);  // my halo below
  }
  if (above != Communicator::kNoRank) {
    to_above[0] = changed_since_exchange(s.z1 - halo, s.z1);  // what I send up
    to_above[1] = changed_since_exchange(s.z1, s.z1 + halo);  // my halo above
  }
  const auto timed = [](double& seconds, auto&& fn) {
    Stopwatch watch;
    fn();
    seconds += watch.lap() / 1e3;
  };
  timed(exchange_.message_seconds, [&] {
    comm_.send_receive(below, below != Communicator::kNoRank ? std::span<const std::uint8_t>(to_below) : std::span<const std::uint8_t>{},
                       above, above != Communicator::kNoRank ? std::span<std::uint8_t>(from_above) : std::span<std::uint8_t>{});
    comm_.send_receive(above, above != Communicator::kNoRank ? std::span<const std::uint8_t>(to_above) : std::span<const std::uint8_t>{},
                       below, below != Communicator::kNoRank ? std::span<std::uint8_t>(from_below) : std::span<std::uint8_t>{});
  });
  const bool send_down = below != Communicator::kNoRank && (to_below[0] || from_below[1]);
  const bool take_from_above = above != Communicator::kNoRank && (from_above[0] || to_above[1]);
  const bool send_up = above != Communicator::kNoRank && (to_above[0] || from_above[1]);
  const bool take_from_below = below != Communicator::kNoRank && (from_below[0] || to_below[1]);
  const std::size_t bytes = std::size_t(halo) * layer_bytes(layout_.size());
  // Both boundaries' layers are read and sent before either halo is written, so no rank's write
  // waits for another's.
  send_down_.resize(send_down ? bytes : 0);
  send_up_.resize(send_up ? bytes : 0);
  from_above_.resize(take_from_above ? bytes : 0);
  from_below_.resize(take_from_below ? bytes : 0);
  timed(exchange_.read_seconds, [&] {
    if (send_down) read_layers(s.z0, s.z0 + halo, send_down_);
    if (send_up) read_layers(s.z1 - halo, s.z1, send_up_);
  });
  timed(exchange_.message_seconds, [&] {
    comm_.send_receive(send_down ? below : Communicator::kNoRank, send_down_, take_from_above ? above : Communicator::kNoRank,
                       from_above_);
    comm_.send_receive(send_up ? above : Communicator::kNoRank, send_up_, take_from_below ? below : Communicator::kNoRank,
                       from_below_);
  });
  timed(exchange_.write_seconds, [&] {
    if (take_from_above) write_halo(s.z1, from_above_);
    if (take_from_below) write_halo(s.z0 - halo, from_below_);
  });
  exchange_.bytes_sent += (send_down ? bytes : 0) + (send_up ? bytes : 0);
  exchange_version_ = slab_->change_version();
}

void DistributedWorld::step(int ticks) {
  if (ticks < 0) throw InvalidArgument("DistributedWorld::step: ticks = " + std::to_string(ticks) + "; use 0 or more");
  exchange_ = HaloExchangeStats{};
  for (int t = 0; t < ticks; ++t) {
    Stopwatch watch;
    if (comm_.size() > 1) exchange_halos();
    exchange_.seconds += watch.lap() / 1e3;
    slab_->step(1);
  }
}

void DistributedWorld::for_each_owned_chunk(const std::function<void(int, int, std::span<const std::uint8_t>)>& fn) const {
  const std::size_t layer = layer_bytes(layout_.size());
  const int chunk_layers = int(std::max<std::size_t>(1, (std::size_t(64) << 20) / layer));
  std::vector<std::uint8_t> chunk;
  for (int z = slab_range_.z0; z < slab_range_.z1; z += chunk_layers) {
    const int z1 = std::min(slab_range_.z1, z + chunk_layers);
    chunk.resize(std::size_t(z1 - z) * layer);
    read_layers(z, z1, chunk);
    fn(z, z1, std::span<const std::uint8_t>(chunk));
  }
}

std::uint64_t DistributedWorld::hash() {
  // hash_cells sums a mix of each 8-byte word of the whole grid's bytes with the word's index: this
  // rank sums the words that start in its owned bytes, the last of which may end in the next rank's
  // first bytes (or past the grid's end, where hash_cells pads with zeros).
  const std::size_t layer = layer_bytes(layout_.size());
  const int below = comm_.rank() > 0 ? comm_.rank() - 1 : Communicator::kNoRank;
  const int above = comm_.rank() + 1 < comm_.size() ? comm_.rank() + 1 : Communicator::kNoRank;
  std::array<std::uint8_t, 8> first{}, next{};
  std::vector<std::uint8_t> start(std::size_t(std::min(slab_range_.z1, slab_range_.z0 + (layer < 8 ? 2 : 1)) - slab_range_.z0) * layer);
  read_layers(slab_range_.z0, slab_range_.z0 + int(start.size() / layer), start);
  std::copy_n(start.begin(), std::min<std::size_t>(8, start.size()), first.begin());
  comm_.send_receive(below, below != Communicator::kNoRank ? std::span<const std::uint8_t>(first) : std::span<const std::uint8_t>{},
                     above, above != Communicator::kNoRank ? std::span<std::uint8_t>(next) : std::span<std::uint8_t>{});
  std::array<std::uint8_t, 8> word{};  // a word begun in one chunk and ended in the next
  std::size_t in_word = 0;
  std::size_t at = (std::size_t(slab_range_.z0) * layer + 7) / 8 * 8;  // the next word's first byte
  std::uint64_t sum = 0;
  for_each_owned_chunk([&](int z0, int, std::span<const std::uint8_t> bytes) {
    const std::size_t chunk_at = std::size_t(z0) * layer;
    std::size_t i = at > chunk_at ? at - chunk_at : 0;  // skips the bytes of a word the rank below sums
    if (in_word > 0) {
      const std::size_t take = std::min(8 - in_word, bytes.size());
      std::copy_n(bytes.begin(), take, word.begin() + std::ptrdiff_t(in_word));
      in_word += take;
      i = take;
      if (in_word < 8) return;
      sum += hash_words_from(word, (at - 8) / 8);
      in_word = 0;
    }
    const std::size_t whole = (bytes.size() - std::min(i, bytes.size())) / 8 * 8;
    sum += hash_words_from(bytes.subspan(i, whole), (chunk_at + i) / 8);
    at = chunk_at + i + whole;
    in_word = bytes.size() - i - whole;
    std::copy_n(bytes.begin() + std::ptrdiff_t(i + whole), in_word, word.begin());
    if (in_word > 0) at += 8;
  });
  if (in_word > 0) {
    // The word that straddles the slab's top: the rest is the next rank's, or zeros past the grid.
    std::fill(word.begin() + std::ptrdiff_t(in_word), word.end(), 0);
    if (above != Communicator::kNoRank) std::copy_n(next.begin(), 8 - in_word, word.begin() + std::ptrdiff_t(in_word));
    sum += hash_words_from(word, (at - 8) / 8);
  }
  return finish_hash(layout_.size(), all_sum(comm_, sum));
}

MaterialCounts DistributedWorld::count() {
  // The slab World's own count (a device reduction on a GPU) less its halos' cells, which are read:
  // the halo layers, not the owned ones, come through host memory.
  MaterialCounts mine = slab_->count();
  std::vector<std::uint8_t> halo;
  for (const auto& [z0, z1] : {std::pair{slab_range_.local_z0, slab_range_.z0}, std::pair{slab_range_.z1, slab_range_.local_z1}}) {
    halo.resize(std::size_t(z1 - z0) * layer_bytes(layout_.size()));
    if (halo.empty()) continue;
    read_layers(z0, z1, halo);
    for (const std::uint8_t b : halo) --mine[cell_material(b)];
  }
  const std::vector<std::uint64_t> sum = all_sum(comm_, mine);
  MaterialCounts out{};
  std::copy(sum.begin(), sum.end(), out.begin());
  return out;
}

Grid DistributedWorld::gather(int root) {
  if (root < 0 || root >= comm_.size())
    throw InvalidArgument("DistributedWorld::gather: root = " + std::to_string(root) + " is outside 0.." +
                          std::to_string(comm_.size() - 1));
  const Int3 size = layout_.size();
  const std::size_t layer = layer_bytes(size);
  Grid whole = comm_.rank() == root ? Grid(size) : Grid();
  for (int r = 0; r < comm_.size(); ++r) {
    const Slab s = layout_.slab(r);
    if (r == comm_.rank() && r == root) {
      read_layers(s.z0, s.z1, whole.cells().subspan(std::size_t(s.z0) * layer, std::size_t(s.z1 - s.z0) * layer));
    } else if (r == comm_.rank()) {
      for_each_owned_chunk([&](int, int, std::span<const std::uint8_t> bytes) {
        comm_.send_receive(root, bytes, Communicator::kNoRank, {});
      });
    } else if (comm_.rank() == root) {
      const int chunk_layers = int(std::max<std::size_t>(1, (std::size_t(64) << 20) / layer));
      for (int z = s.z0; z < s.z1; z += chunk_layers) {
        const int z1 = std::min(s.z1, z + chunk_layers);
        comm_.send_receive(Communicator::kNoRank, {}, r,
                           whole.cells().subspan(std::size_t(z) * layer, std::size_t(z1 - z) * layer));
      }
    }
  }
  return whole;
}

WorldSnapshot DistributedWorld::capture(int root) {
  Grid whole = gather(root);
  WorldSnapshot s = meta();
  if (comm_.rank() == root) s.cells.assign(whole.cells().begin(), whole.cells().end());
  return s;
}

WorldSnapshot DistributedWorld::meta() const {
  return snapshot_header(layout_.size(), slab_->tick(), slab_->def().seed, slab_->tool_calls(), slab_->rules().name,
                         slab_->rule_fingerprint_);
}

template <class Local>
ChangeReport DistributedWorld::tool(const Box& region, bool clipped, bool here, Local&& local) {
  // Every rank holds the same count, so all refuse together, before any cell or message moves.
  if (slab_->tool_calls_ == std::numeric_limits<std::uint64_t>::max())
    throw StateError("DistributedWorld: a tool call after " + std::to_string(slab_->tool_calls_) +
                     " would wrap the 64-bit tool-call counter; no cell was changed");
  ChangeReport mine;
  if (here)
    mine = local();
  else
    ++slab_->tool_calls_;
  std::vector<std::uint64_t> counts{std::uint64_t(mine.cells_changed), std::uint64_t(mine.cells_shaken)};
  counts.insert(counts.end(), mine.added.begin(), mine.added.end());
  counts.insert(counts.end(), mine.removed.begin(), mine.removed.end());
  const std::vector<std::uint64_t> sum = all_sum(comm_, counts);
  ChangeReport report;
  report.cells_changed = std::int64_t(sum[0]);
  report.cells_shaken = std::int64_t(sum[1]);
  std::copy_n(sum.begin() + 2, kMaterialCount, report.added.begin());
  std::copy_n(sum.begin() + 2 + kMaterialCount, kMaterialCount, report.removed.begin());
  report.region = region;
  report.clipped = clipped;
  return report;
}

bool DistributedWorld::owns_part_of(const Box& region) const {
  return !intersect(region, slab_range_.owned(layout_.size())).empty();
}

ChangeReport DistributedWorld::dig(const Sphere& sphere) {
  bool clipped = false;
  const Box region = sphere_region(sphere, layout_.size(), "dig", clipped);
  return tool(region, clipped, owns_part_of(region), [&] { return slab_->dig(sphere); });
}

ChangeReport DistributedWorld::shake(const Sphere& sphere, int level) {
  check_shake(slab_->rules(), level);
  bool clipped = false;
  const Box region = sphere_region(sphere, layout_.size(), "shake", clipped);
  return tool(region, clipped, owns_part_of(region), [&] { return slab_->shake(sphere, level); });
}

ChangeReport DistributedWorld::pour(Vec3 center, double radius, Material material, std::int64_t amount) {
  const Sphere sphere{center, radius};
  bool clipped = false;
  const Box region = check_pour(sphere, material, amount, layout_.size(), clipped);
  // The whole world fills the `amount` void cells of the smallest keys: each rank offers its own
  // smallest, and fills those of its cells that are among the smallest of all.
  const bool here = owns_part_of(region);
  std::vector<std::uint64_t> keys;
  if (here && amount > 0) keys = slab_->pour_keys(sphere, std::size_t(amount));
  std::vector<std::uint64_t> every;
  for (const std::vector<std::uint8_t>& bytes : all_gather_bytes(
           comm_, {reinterpret_cast<const std::uint8_t*>(keys.data()), keys.size() * sizeof(std::uint64_t)})) {
    const std::size_t at = every.size();
    every.resize(at + bytes.size() / sizeof(std::uint64_t));
    if (!bytes.empty()) std::memcpy(every.data() + at, bytes.data(), bytes.size());
  }
  std::uint64_t limit = ~std::uint64_t(0);
  if (every.size() > std::size_t(amount)) {
    std::nth_element(every.begin(), every.begin() + (amount - 1), every.end());
    limit = every[std::size_t(amount - 1)];
  }
  const auto mine = std::int64_t(std::count_if(keys.begin(), keys.end(), [&](std::uint64_t k) { return k <= limit; }));
  return tool(region, clipped, mine > 0, [&] { return slab_->pour(center, radius, material, mine); });
}

ChangeReport DistributedWorld::paint(const Box& box, Material material) {
  bool clipped = false;
  const Box region = check_paint_box(box, material, layout_.size(), clipped);
  return tool(region, clipped, owns_part_of(region), [&] { return slab_->paint(box, material); });
}

ChangeReport DistributedWorld::paint(const Sphere& sphere, Material material) {
  check_tool_material(material, "paint");
  bool clipped = false;
  const Box region = sphere_region(sphere, layout_.size(), "paint", clipped);
  return tool(region, clipped, owns_part_of(region), [&] { return slab_->paint(sphere, material); });
}

}  // namespace granular
