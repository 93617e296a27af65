#pragma once
/// @file number_text.hpp
/// Numbers as the shortest text that reads back as them, for messages.

#include <charconv>
#include <string>

#include "granular/geometry.hpp"

namespace granular {

/// The shortest text that reads back as `v` ("0.1", "863", "1e+30"), for messages.
inline std::string number_text(double v) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}

/// `v` as "(x, y, z)" with number_text's numbers, for messages.
inline std::string vec_text(const Vec3& v) {
  // Appended in turn: a literal prefixed to a temporary string draws a false -Wrestrict from GCC 12.
  std::string text = "(";
  text += number_text(v.x);
  text += ", ";
  text += number_text(v.y);
  text += ", ";
  text += number_text(v.z);
  return text += ")";
}

}  // namespace granular
