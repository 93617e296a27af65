#include "granular/rule_presets.hpp"

#include <utility>

#include "granular/errors.hpp"
#include "granular/material.hpp"
#include "paper_rule.hpp"

namespace granular {

namespace {

RuleSet make_preset(std::string name, std::string description, bool random_symmetry) {
  RuleSet r;
  r.name = std::move(name);
  r.description = std::move(description);
  r.version = 1;
  r.random_symmetry = random_symmetry;
  r.transition = &paper_transition;
  r.device_rule = "paper";
  return r;
}

}  // namespace

Transition paper_transition(const BlockCells& cells) { return rules::paper_rule(encode_key(cells)); }

std::shared_ptr<const RuleSet> make_rule_set(std::string_view name) {
  if (name == "paper")
    return std::make_shared<const RuleSet>(
        make_preset("paper", "gravity then flow, fixed preference order (the paper's rules)", false));
  if (name == "isotropic")
    return std::make_shared<const RuleSet>(
        make_preset("isotropic", "the paper's rules under a random horizontal symmetry per block and tick", true));
  std::string valid;
  for (const auto& n : rule_preset_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw InvalidArgument("unknown rule set '" + std::string(name) + "'; valid rule sets: " + valid);
}

std::vector<std::string> rule_preset_names() { return {"paper", "isotropic"}; }

}  // namespace granular
