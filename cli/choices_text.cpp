#include "choices_text.hpp"

#include "granular/rule_presets.hpp"

namespace granular::cli {

std::string choices_text(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) text += i + 1 == names.size() ? " or " : ", ";
    text += names[i];
  }
  return text;
}

std::string rule_preset_choices() { return choices_text(rule_preset_names()); }

}  // namespace granular::cli
