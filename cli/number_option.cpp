#include "number_option.hpp"

#include <charconv>

#include "granular/errors.hpp"

namespace granular::cli {

namespace {

/// The quoted value for a message, cut to 40 characters.
std::string shown(std::string_view text) {
  return text.size() <= 40 ? std::string(text) : std::string(text.substr(0, 37)) + "...";
}

std::string range_text(const NumberRange& r) {
  return "a whole number from " + std::to_string(r.min) + " to " + std::to_string(r.max);
}

}  // namespace

std::uint64_t parse_whole_number(std::string_view name, std::string_view text, const NumberRange& range) {
  const std::string head = std::string(name) + " " + shown(text) + ": ";
  const std::string expected = " (expected " + range_text(range) + ")";
  if (text.empty()) throw InvalidArgument(std::string(name) + " needs a value" + expected);
  if (text.front() == '-') {
    const bool digits = text.size() > 1 && text.find_first_not_of("0123456789", 1) == std::string_view::npos;
    throw InvalidArgument(head + (digits ? "must not be negative" : "is not a whole number") + expected);
  }
  if (text.find_first_not_of("0123456789") != std::string_view::npos)
    throw InvalidArgument(head + "is not a whole number" + expected);
  std::uint64_t v = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec == std::errc::result_out_of_range || v > range.max)
    throw InvalidArgument(head + "is too large" + expected);
  if (v < range.min)
    throw InvalidArgument(head + "must be at least " + std::to_string(range.min) +
                          (range.below_min_hint.empty() ? expected : " (" + range.below_min_hint + ")"));
  return v;
}

}  // namespace granular::cli
