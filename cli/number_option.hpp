#pragma once
/// @file number_option.hpp
/// Whole-number command-line options parsed strictly: decimal digits only, within a range. CLI11
/// itself reads unsigned options through strtoull, which turns "-1" into 2^64 - 1 and accepts
/// hex and octal; these options refuse anything but a decimal number in range instead, with
/// `--ticks -1: must not be negative ...` as the message (an InvalidArgument, so main prints it
/// as an `error:` line and exits 1).

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <string_view>

#include "granular/extend/threads.hpp"

namespace granular::cli {

/// The limits and wording of one whole-number option.
struct NumberRange {
  std::uint64_t min = 0;                ///< smallest accepted value
  std::uint64_t max = UINT64_MAX;       ///< largest accepted value
  std::string below_min_hint;           ///< added to the message for a value below min, e.g. "omit --size for ..."
};

/// The range of every --threads option: 0 (all hardware threads) to granular::max_threads().
inline NumberRange threads_range() { return {0, std::uint64_t(granular::max_threads()), ""}; }

/// Parses `text`, the value given to option `name`: decimal digits only, in [range.min,
/// range.max]. Throws InvalidArgument "<name> <text>: <what is wrong> (<the range>)" otherwise.
std::uint64_t parse_whole_number(std::string_view name, std::string_view text, const NumberRange& range);

/// Adds option `names` ("-t,--ticks") to `command`, parsed by parse_whole_number into `target`
/// (which keeps its value when the option is absent; that value is shown as the default).
/// `range.max` must fit in T.
template <class T>
CLI::Option* add_number_option(CLI::App& command, const std::string& names, T& target, const NumberRange& range,
                               const std::string& description) {
  std::string long_name = names.substr(names.rfind(',') + 1);
  CLI::Option* option = command.add_option_function<std::string>(
      names,
      [&target, range, long_name](const std::string& text) {
        target = static_cast<T>(parse_whole_number(long_name, text, range));
      },
      description);
  option->type_name(range.max > std::uint64_t(INT32_MAX) ? "UINT" : "INT");
  option->default_str(std::to_string(target));
  return option;
}

}  // namespace granular::cli
