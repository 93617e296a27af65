#pragma once
/// @file scene_json.hpp
/// Private: reads the fields of one JSON object of a scene file, throwing ParseError messages that
/// name the source, the field path ("shapes[2].radius") and the offending value.

#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <string>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

#include "granular/errors.hpp"
#include "granular/material.hpp"
#include "util/number_text.hpp"

namespace granular::scene_detail {

/// Largest magnitude of a position or length, as a fraction of N (a bound that keeps the scaled
/// integer arithmetic exact; no sensible scene comes near it).
inline constexpr double kMaxFraction = 1000.0;

/// The valid material names, for messages.
inline constexpr const char* kMaterialNames =
    "void, solid, granular (or sand), liquid (or water), gas, gravel, state6, state7";

/// Longest excerpt of a file's content that a message quotes, in bytes.
inline constexpr std::size_t kMaxExcerpt = 60;

/// `text` cut to at most `max` bytes at a UTF-8 character boundary, "..." appended when cut.
inline std::string cut_utf8(std::string_view text, std::size_t max) {
  if (text.size() <= max) return std::string(text);
  std::size_t end = max > 3 ? max - 3 : 0;
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;
  return std::string(text.substr(0, end)) + "...";
}

/// Appends the JSON text of `value` to `out` (compact, as nlohmann's dump()), stopping once `out` holds `budget` bytes: never
/// serialises more of a large string, array or object than a message can show.
inline void append_excerpt(const nlohmann::json& value, std::string& out, std::size_t budget) {
  if (out.size() >= budget) return;
  using Type = nlohmann::json::value_t;
  switch (value.type()) {
    case Type::string: {
      const std::string& s = value.get_ref<const std::string&>();
      const nlohmann::json head = std::string(s.substr(0, budget - out.size() + 1));
      out += head.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
      return;
    }
    case Type::array: {
      out += '[';
      bool first = true;
      for (const auto& element : value) {
        if (out.size() >= budget) return;
        if (!first) out += ',';
        first = false;
        append_excerpt(element, out, budget);
      }
      out += ']';
      return;
    }
    case Type::object: {
      out += '{';
      bool first = true;
      for (const auto& item : value.items()) {
        if (out.size() >= budget) return;
        if (!first) out += ',';
        first = false;
        out += nlohmann::json(std::string(item.key().substr(0, budget))).dump(-1, ' ', false,
                                                                             nlohmann::json::error_handler_t::replace);
        out += ':';
        append_excerpt(item.value(), out, budget);
      }
      out += '}';
      return;
    }
    default:
      out += value.dump();
      return;
  }
}

/// A JSON value as short text for messages (at most kMaxExcerpt bytes, "..." when cut).
inline std::string describe(const nlohmann::json& value) {
  std::string text;
  append_excerpt(value, text, kMaxExcerpt + 1);
  return cut_utf8(text, kMaxExcerpt);
}

/// Joins a parent path and a key: "" + "size" = "size", "shapes[2]" + "radius" = "shapes[2].radius".
/// A key longer than 40 bytes is cut ("...").
inline std::string join_path(const std::string& parent, std::string_view key) {
  const std::string k = cut_utf8(key, 40);
  return parent.empty() ? k : parent + "." + k;
}

/// Reads the fields of one JSON object at `path` in the scene `source`.
class JsonFields {
 public:
  /// Wraps `value`, which must be a JSON object (ParseError otherwise).
  JsonFields(const nlohmann::json& value, std::string path, const std::string& source)
      : value_(value), path_(std::move(path)), source_(source) {
    if (!value_.is_object())
      throw ParseError(source_ + ": " + (path_.empty() ? std::string("top level") : path_) +
                       ": expected a JSON object, got " + describe(value_));
  }

  /// The wrapped object.
  const nlohmann::json& json() const { return value_; }
  /// This object's path ("" for the top level).
  const std::string& path() const { return path_; }
  /// The scene's source name.
  const std::string& source() const { return source_; }
  /// The path of one of this object's fields.
  std::string field_path(std::string_view key) const { return join_path(path_, key); }

  /// Throws ParseError "<source>: <path>: <problem>, got <value>" (no value when the field is absent).
  [[noreturn]] void fail(std::string_view key, const std::string& problem) const {
    const nlohmann::json* v = find(key);
    fail_at(field_path(key), problem, v);
  }

  /// Throws ParseError for an element or sub-path of this object.
  [[noreturn]] void fail_at(const std::string& full_path, const std::string& problem,
                            const nlohmann::json* value) const {
    std::string message = source_ + ": " + full_path + ": " + problem;
    if (value) message += ", got " + describe(*value);
    throw ParseError(message);
  }

  /// The field, or nullptr when absent.
  const nlohmann::json* find(std::string_view key) const {
    const auto it = value_.find(key);
    return it == value_.end() ? nullptr : &*it;
  }
  /// True when the field is present.
  bool has(std::string_view key) const { return find(key) != nullptr; }

  /// The field; ParseError naming `needed_by` when absent.
  const nlohmann::json& require(std::string_view key, std::string_view needed_by) const {
    const nlohmann::json* v = find(key);
    if (!v) fail(key, "missing required field (" + std::string(needed_by) + ")");
    return *v;
  }

  /// Rejects any field not in `allowed` ("comment" is always allowed); `what` names the object kind.
  void check_known(std::initializer_list<std::string_view> allowed, std::string_view what) const {
    for (const auto& item : value_.items()) {
      if (item.key() == "comment") continue;
      bool known = false;
      for (std::string_view a : allowed) known = known || a == item.key();
      if (known) continue;
      std::string list;
      for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      fail(item.key(), "unknown field (" + std::string(what) + " has: " + list + ", comment)");
    }
  }

  /// A required string.
  std::string text(std::string_view key, std::string_view needed_by) const {
    const nlohmann::json& v = require(key, needed_by);
    if (!v.is_string()) fail(key, "expected a string");
    return v.get<std::string>();
  }

  /// A required finite number.
  double number(std::string_view key, std::string_view needed_by) const {
    return number_value(require(key, needed_by), field_path(key));
  }

  /// A required position (fraction of N): finite, magnitude at most kMaxFraction.
  double position(std::string_view key, std::string_view needed_by) const {
    return position_value(require(key, needed_by), field_path(key));
  }

  /// A required length (fraction of N): finite, >= 0, at most kMaxFraction.
  double length(std::string_view key, std::string_view needed_by) const {
    const double v = number(key, needed_by);
    if (v < 0) fail(key, "must not be negative");
    if (v > kMaxFraction) fail(key, "must be at most " + std::to_string(int(kMaxFraction)) + " (a fraction of N)");
    return v;
  }

  /// A required array of D positions (fractions of N).
  template <std::size_t D>
  std::array<double, D> point(std::string_view key, std::string_view needed_by) const {
    const nlohmann::json& v = require(key, needed_by);
    if (!v.is_array() || v.size() != D)
      fail(key, "expected an array of " + std::to_string(D) + " numbers");
    std::array<double, D> out{};
    for (std::size_t i = 0; i < D; ++i)
      out[i] = position_value(v[i], field_path(key) + "[" + std::to_string(i) + "]");
    return out;
  }

  /// A required integer >= `min`.
  std::int64_t integer(std::string_view key, std::string_view needed_by, std::int64_t min) const {
    const nlohmann::json& v = require(key, needed_by);
    if (!v.is_number_integer()) fail(key, "expected an integer");
    if (v.is_number_unsigned() && v.get<std::uint64_t>() > std::uint64_t(std::numeric_limits<std::int64_t>::max()))
      fail(key, "is too large");
    const std::int64_t i = v.get<std::int64_t>();
    if (i < min) fail(key, "must be at least " + std::to_string(min));
    return i;
  }

  /// A required material name.
  Material material(std::string_view key, std::string_view needed_by) const {
    const nlohmann::json& v = require(key, needed_by);
    if (!v.is_string()) fail(key, std::string("expected a material name (") + kMaterialNames + ")");
    const auto m = parse_material(v.get<std::string>());
    if (!m) fail(key, std::string("unknown material (valid: ") + kMaterialNames + ")");
    return *m;
  }

  /// A required array.
  const nlohmann::json& array(std::string_view key, std::string_view needed_by) const {
    const nlohmann::json& v = require(key, needed_by);
    if (!v.is_array()) fail(key, "expected an array");
    return v;
  }

 private:
  double number_value(const nlohmann::json& v, const std::string& full_path) const {
    if (!v.is_number()) fail_at(full_path, "expected a number", &v);
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail_at(full_path, "must be a finite number", &v);
    return d;
  }

  double position_value(const nlohmann::json& v, const std::string& full_path) const {
    const double d = number_value(v, full_path);
    if (std::fabs(d) > kMaxFraction)
      fail_at(full_path, "must lie within +-" + std::to_string(int(kMaxFraction)) + " (a fraction of N)", &v);
    return d;
  }

  const nlohmann::json& value_;
  std::string path_;
  std::string source_;
};

}  // namespace granular::scene_detail
