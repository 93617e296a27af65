#pragma once
/// @file json_text.hpp
/// The text of the CLI's --json output. A path is a string of bytes that need not be UTF-8 (a
/// file named in Latin-1), and JSON text must be UTF-8: each invalid byte sequence in a string is
/// written as U+FFFD, the replacement character (what `python3 -c 'b"\xff".decode(errors="replace")'`
/// gives), never an exception after the work is done. The text output prints a path's bytes as
/// they are.

#include <nlohmann/json.hpp>
#include <string>

namespace granular::cli {

/// `j` indented by two spaces, invalid UTF-8 replaced by U+FFFD, and a final newline.
inline std::string json_text(const nlohmann::json& j) {
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace granular::cli
