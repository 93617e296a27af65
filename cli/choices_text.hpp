#pragma once
/// @file choices_text.hpp
/// The values an option accepts, as its help text lists them.

#include <string>
#include <vector>

namespace granular::cli {

/// `names` as a help text lists them: "a, b or c" ("a" for one name, "" for none).
std::string choices_text(const std::vector<std::string>& names);

/// Every rule-set preset of the registry (granular::rule_preset_names()), as choices_text lists them.
std::string rule_preset_choices();

}  // namespace granular::cli
