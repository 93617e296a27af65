#include "granular/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include <nlohmann/json.hpp>

#include "granular/errors.hpp"
#include "granular/grid_io.hpp"
#include "granular/extend/memory_budget.hpp"
#include "scenes/scene_json.hpp"
#include "scenes/scene_shapes.hpp"

#ifndef GRANULAR_SOURCE_ASSET_DIR
#define GRANULAR_SOURCE_ASSET_DIR ""
#endif
#ifndef GRANULAR_INSTALL_ASSET_DIR
#define GRANULAR_INSTALL_ASSET_DIR ""
#endif

namespace granular {

namespace {

using scene_detail::JsonFields;

/// Largest N a scene accepts (far beyond any grid that fits in memory).
constexpr std::int64_t kMaxN = 1 << 24;

/// Largest resolved count (cells per tick, tick numbers) kept exact in a double.
constexpr double kMaxCount = 9.0e15;

/// Throws ParseError when `text` nests arrays and objects deeper than kMaxSceneDepth, naming the
/// line and column where it does; checked before parsing, so no deeply nested value is ever built.
void check_nesting(std::string_view text, const std::string& source);

/// "line L, column C" of the character at 0-based offset `offset` in `text`.
std::string line_column(std::string_view text, std::size_t offset) {
  offset = std::min(offset, text.size());
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

void check_nesting(std::string_view text, const std::string& source) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxSceneDepth)
        throw ParseError(source + ": malformed JSON at " + line_column(text, i) + ": arrays and objects nest deeper than " +
                         std::to_string(kMaxSceneDepth) + " levels");
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

/// nlohmann's message without its "[json.exception...] parse error at line L, column C: " prefix.
/// Cut to 200 bytes: nlohmann quotes the token at fault, which may be as long as the file.
std::string parse_detail(const std::string& what) {
  std::string detail = what;
  if (const auto bracket = detail.find("] "); bracket != std::string::npos) detail = detail.substr(bracket + 2);
  if (const auto column = detail.find("column "); column != std::string::npos)
    if (const auto colon = detail.find(": ", column); colon != std::string::npos) detail = detail.substr(colon + 2);
  return scene_detail::cut_utf8(detail, 200);
}

/// Reads a count that may be given absolutely (`abs_key`, an integer >= abs_min) or scaled by
/// N^power (`scaled_key`, a number >= 0); nullopt when neither is present.
std::optional<ScaledCount> scaled_count(const JsonFields& f, const char* abs_key, const char* scaled_key, int power,
                                        std::int64_t abs_min) {
  const bool has_abs = f.has(abs_key), has_scaled = f.has(scaled_key);
  if (has_abs && has_scaled)
    f.fail(scaled_key, std::string("give either ") + abs_key + " or " + scaled_key + ", not both");
  if (has_abs) {
    const std::int64_t v = f.integer(abs_key, "", abs_min);
    if (double(v) > kMaxCount) f.fail(abs_key, "is too large");
    return ScaledCount{double(v), 0};
  }
  if (has_scaled) {
    const double v = f.number(scaled_key, "");
    if (v < 0) f.fail(scaled_key, "must not be negative");
    if (v > kMaxCount) f.fail(scaled_key, "is too large");
    return ScaledCount{v, power};
  }
  return std::nullopt;
}

EmitterDef parse_emitter(const nlohmann::json& value, const std::string& path, const std::string& source) {
  const JsonFields f(value, path, source);
  f.check_known({"center", "radius", "material", "rate", "rate_per_n2", "start", "start_per_n", "stop", "stop_per_n"},
                "an emitter");
  constexpr const char* needs = "an emitter needs center, radius and rate or rate_per_n2";
  EmitterDef e;
  e.field = path;
  e.center = f.point<3>("center", needs);
  e.radius = f.length("radius", needs);
  if (e.radius <= 0) f.fail("radius", "must be greater than zero");
  if (f.has("material")) {
    e.material = f.material("material", "");
    if (e.material == Material::Void) f.fail("material", "an emitter cannot pour void");
  }
  const auto rate = scaled_count(f, "rate", "rate_per_n2", 2, 1);
  if (!rate) f.fail("rate", std::string("missing required field (") + needs + ")");
  if (rate->n_power == 2 && rate->value <= 0) f.fail("rate_per_n2", "must be greater than zero");
  e.rate = *rate;
  if (auto start = scaled_count(f, "start", "start_per_n", 1, 0)) e.start = *start;
  e.stop = scaled_count(f, "stop", "stop_per_n", 1, 0);
  if (e.stop && e.stop->n_power == e.start.n_power && e.stop->value < e.start.value)
    f.fail(e.stop->n_power == 0 ? "stop" : "stop_per_n", "is before start");
  return e;
}

/// The JSON key a scaled count came from.
std::string count_key(const ScaledCount& c, const char* abs_key, const char* scaled_key) {
  return c.n_power == 0 ? abs_key : scaled_key;
}

/// round(value * n^power), halves away from zero; InvalidArgument (naming `what`) when too large.
std::int64_t resolve_count(const ScaledCount& c, int n, const std::string& what) {
  double v = c.value;
  for (int i = 0; i < c.n_power; ++i) v *= double(n);
  if (v > kMaxCount)
    throw InvalidArgument(what + ": " + number_text(c.value) + " resolves to " + number_text(v) +
                          " at N=" + std::to_string(n) + ", which is too large");
  return std::llround(v);
}

Emitter resolve_emitter(const EmitterDef& def, int n, Int3 size, const std::string& source) {
  const std::string where = source + ": " + def.field;
  auto cells = [&](double v, const char* key) {
    return double(scene_detail::to_sixteenths(v, n, where + "." + key)) / double(scene_detail::kSubcell);
  };
  Emitter e;
  e.center = {cells(def.center[0], "center"), cells(def.center[1], "center"), cells(def.center[2], "center")};
  const double extent[3] = {double(size.x), double(size.y), double(size.z)};
  const double c[3] = {e.center.x, e.center.y, e.center.z};
  for (int a = 0; a < 3; ++a)
    if (c[a] < 0 || c[a] > extent[a])
      throw InvalidArgument(where + ".center[" + std::to_string(a) + "]: " + number_text(def.center[a]) +
                            " lies outside the " + to_string(size) + " grid at N=" + std::to_string(n));
  e.radius = cells(def.radius, "radius");
  if (e.radius <= 0)
    throw InvalidArgument(where + ".radius: " + number_text(def.radius) + " rounds to zero cells at N=" +
                          std::to_string(n));
  e.material = def.material;
  const std::string rate_key = count_key(def.rate, "rate", "rate_per_n2");
  e.rate = resolve_count(def.rate, n, where + "." + rate_key);
  if (e.rate < 1)
    throw InvalidArgument(where + "." + rate_key + ": " + number_text(def.rate.value) +
                          " rounds to 0 cells per tick at N=" + std::to_string(n) + "; use a larger value or N");
  e.start = std::uint64_t(resolve_count(def.start, n, where + "." + count_key(def.start, "start", "start_per_n")));
  e.stop = std::numeric_limits<std::uint64_t>::max();
  if (def.stop) {
    const std::string stop_key = count_key(*def.stop, "stop", "stop_per_n");
    e.stop = std::uint64_t(resolve_count(*def.stop, n, where + "." + stop_key));
    if (e.stop < e.start)
      throw InvalidArgument(where + "." + stop_key + ": stop tick " + std::to_string(e.stop) +
                            " is before start tick " + std::to_string(e.start) + " at N=" + std::to_string(n));
  }
  return e;
}

/// Throws ParseError when the grid at `default_n` holds more than kMaxDefaultGridCells cells,
/// giving its size and the memory a run of it needs.
void check_default_grid(const JsonFields& f, const std::array<double, 3>& size, int default_n) {
  std::int64_t extent[3];
  try {
    for (int a = 0; a < 3; ++a)
      extent[a] = scene_detail::cell_boundary(scene_detail::to_sixteenths(size[a], default_n, "size"));
  } catch (const InvalidArgument&) {
    f.fail("default_n", "makes a grid of more than " + std::to_string(std::int64_t(scene_detail::kMaxScaledCells)) +
                            " cells along an axis with this size");
  }
  const double cells = double(extent[0]) * double(extent[1]) * double(extent[2]);
  if (cells <= double(kMaxDefaultGridCells)) return;
  const std::string count = cells < 9e18 ? std::to_string(std::uint64_t(cells)) : number_text(cells);
  f.fail("default_n", "makes a " + std::to_string(extent[0]) + "x" + std::to_string(extent[1]) + "x" +
                          std::to_string(extent[2]) + " grid (" + count + " cells, about " +
                          format_bytes(2.0 * cells) + " to run) by default, more than the " +
                          std::to_string(kMaxDefaultGridCells) +
                          " cells (256^3) a scene's default may hold; lower default_n and ask for larger N explicitly");
}

/// The asset folder: $GRANULAR_ASSET_DIR, else the source tree's when present, else the installed one.
std::filesystem::path asset_root() {
  if (const char* env = std::getenv("GRANULAR_ASSET_DIR"); env && *env) return env;
  std::error_code ec;
  const std::filesystem::path source_dir = GRANULAR_SOURCE_ASSET_DIR;
  if (!source_dir.empty() && std::filesystem::is_directory(source_dir, ec)) return source_dir;
  // An install moved to another prefix: the assets beside the program (<prefix>/bin/program,
  // <prefix>/share/granular/assets).
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path beside = (program.parent_path() / "../share/granular/assets").lexically_normal();
    if (std::filesystem::is_directory(beside, ec)) return beside;
  }
  return GRANULAR_INSTALL_ASSET_DIR;
}

}  // namespace

Scene parse_scene(std::string_view json_text, const std::string& source_name) {
  check_nesting(json_text, source_name);
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(json_text.begin(), json_text.end());
  } catch (const nlohmann::json::parse_error& e) {
    const std::size_t offset = e.byte > 0 ? e.byte - 1 : 0;
    throw ParseError(source_name + ": malformed JSON at " + line_column(json_text, offset) + ": " +
                     parse_detail(e.what()));
  } catch (const nlohmann::json::exception& e) {
    // Raised without a position (a number too large for a double: "number overflow parsing '1e999'").
    throw ParseError(source_name + ": malformed JSON: " + parse_detail(e.what()));
  }
  const JsonFields f(root, "", source_name);
  f.check_known({"name", "description", "size", "default_n", "min_n", "shapes", "emitters"}, "a scene");
  constexpr const char* needs = "a scene needs name, description, size, default_n, min_n and shapes";
  Scene scene;
  scene.source = source_name;
  scene.name = f.text("name", needs);
  if (scene.name.empty()) f.fail("name", "must not be empty");
  if (scene.name.size() > kMaxSceneName)
    f.fail("name", "must be at most " + std::to_string(kMaxSceneName) + " bytes long (it is " +
                       std::to_string(scene.name.size()) + ")");
  scene.description = f.text("description", needs);
  scene.size = f.point<3>("size", needs);
  for (int a = 0; a < 3; ++a)
    if (scene.size[a] <= 0)
      f.fail_at("size[" + std::to_string(a) + "]", "every extent must be greater than zero (the grid would be empty)",
                &root.at("size").at(a));
  const std::int64_t default_n = f.integer("default_n", needs, 1);
  if (default_n > kMaxN) f.fail("default_n", "must be at most " + std::to_string(kMaxN));
  check_default_grid(f, scene.size, int(default_n));
  const std::int64_t min_n = f.integer("min_n", needs, 1);
  if (min_n > default_n) f.fail("min_n", "must not exceed default_n (" + std::to_string(default_n) + ")");
  scene.default_n = int(default_n);
  scene.min_n = int(min_n);
  const nlohmann::json& shapes = f.array("shapes", needs);
  for (std::size_t i = 0; i < shapes.size(); ++i)
    scene.shapes.push_back(scene_detail::parse_shape(shapes[i], "shapes[" + std::to_string(i) + "]", source_name));
  if (f.has("emitters")) {
    const nlohmann::json& emitters = f.array("emitters", "");
    for (std::size_t i = 0; i < emitters.size(); ++i)
      scene.emitters.push_back(parse_emitter(emitters[i], "emitters[" + std::to_string(i) + "]", source_name));
  }
  return scene;
}

Scene load_scene(const std::filesystem::path& path) {
  const std::vector<std::uint8_t> bytes = read_file_bytes(path, kMaxSceneFileBytes);
  return parse_scene(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string());
}

std::filesystem::path scene_dir() { return asset_root() / "scenes"; }

std::vector<std::string> list_scenes() {
  std::vector<std::string> names;
  std::error_code ec;
  const std::filesystem::path dir = scene_dir();
  if (!std::filesystem::is_directory(dir, ec)) return names;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code file_ec;
    if (it->path().extension() == ".json" && it->is_regular_file(file_ec)) names.push_back(it->path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::filesystem::path find_scene(std::string_view name_or_path) {
  std::error_code ec;
  const std::filesystem::path given{std::string(name_or_path)};
  if (!name_or_path.empty() && std::filesystem::is_regular_file(given, ec)) return given;
  std::string name(name_or_path);
  if (name.size() > 5 && name.ends_with(".json")) name.resize(name.size() - 5);
  const std::filesystem::path candidate = scene_dir() / (name + ".json");
  if (!name.empty() && name.find('/') == std::string::npos && std::filesystem::is_regular_file(candidate, ec))
    return candidate;
  std::string available;
  for (const std::string& s : list_scenes()) available += (available.empty() ? "" : ", ") + s;
  if (available.empty()) available = "none (" + scene_dir().string() + " holds no .json file)";
  throw InvalidArgument("scene '" + std::string(name_or_path) + "' not found: it is not a file, and " +
                        candidate.string() + " does not exist; available scenes: " + available);
}

Int3 scene_size(const Scene& scene, int n) {
  if (n < 1) throw InvalidArgument(scene.source + ": scene '" + scene.name + "': N must be at least 1, got " + std::to_string(n));
  std::int64_t extent[3];
  for (int a = 0; a < 3; ++a) {
    const std::string field = scene.source + ": size[" + std::to_string(a) + "]";
    extent[a] = scene_detail::cell_boundary(scene_detail::to_sixteenths(scene.size[a], n, field));
    if (extent[a] < 1)
      throw InvalidArgument(field + ": " + number_text(scene.size[a]) + " times N=" + std::to_string(n) +
                            " rounds to zero cells");
  }
  const Int3 size{int(extent[0]), int(extent[1]), int(extent[2])};
  // Extents only: the memory is checked where the grid is allocated, for what the caller needs.
  check_grid_extents(size, scene.source + ": scene '" + scene.name + "' size at N=" + std::to_string(n));
  return size;
}

SceneInstance instantiate(const Scene& scene, int n) {
  if (n == 0) n = scene.default_n;
  if (n < 0)
    throw InvalidArgument(scene.source + ": scene '" + scene.name + "': N must be positive, got " + std::to_string(n));
  if (n < scene.min_n)
    throw InvalidArgument(scene.source + ": min_n: scene '" + scene.name + "' needs N >= " +
                          std::to_string(scene.min_n) + ", got N=" + std::to_string(n));
  SceneInstance out;
  out.n = n;
  out.grid = Grid(scene_size(scene, n));
  for (const ShapeDef& shape : scene.shapes) scene_detail::draw_shape(out.grid, shape, n, scene.source);
  for (const EmitterDef& e : scene.emitters) out.emitters.push_back(resolve_emitter(e, n, out.grid.size(), scene.source));
  return out;
}

}  // namespace granular
