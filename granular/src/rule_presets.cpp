#include "granular/rule_presets.hpp"

#include <numeric>
#include <utility>

#include "granular/errors.hpp"
#include "granular/material.hpp"

namespace granular {

namespace {

constexpr std::uint8_t kVoid = to_cell(Material::Void);
constexpr std::uint8_t kGrain = to_cell(Material::Granular);

/// Tracks which original cell sits at each block position while rules move cells around.
class BlockState {
 public:
  explicit BlockState(const BlockCells& cells) : cells_(cells) { std::iota(at_.begin(), at_.end(), std::uint8_t(0)); }
  std::uint8_t state(int position) const { return cells_[at_[position]]; }
  void swap(int p, int q) { std::swap(at_[p], at_[q]); }
  Transition transition() const {
    std::array<std::uint8_t, 8> dest{};
    for (int p = 0; p < 8; ++p) dest[at_[p]] = std::uint8_t(p);
    return encode_transition(dest);
  }

 private:
  BlockCells cells_;
  std::array<std::uint8_t, 8> at_{};
};

RuleSet make_preset(std::string name, std::string description, bool random_symmetry) {
  RuleSet r;
  r.name = std::move(name);
  r.description = std::move(description);
  r.version = 1;
  r.random_symmetry = random_symmetry;
  r.transition = &paper_transition;
  return r;
}

}  // namespace

Transition paper_transition(const BlockCells& cells) {
  BlockState b(cells);
  // Gravity: a grain in the top layer falls into the void below it.
  for (int column = 0; column < 4; ++column)
    if (b.state(column + 4) == kGrain && b.state(column) == kVoid) b.swap(column + 4, column);
  // Flow: a grain resting on something topples into a neighbouring bottom cell when both that
  // cell and the cell above it are void (the path over the edge is clear).
  for (int column = 0; column < 4; ++column) {
    const int top = column + 4;
    if (b.state(top) != kGrain) continue;
    for (int flip : {1, 2, 3}) {
      const int target = column ^ flip;
      if (b.state(target) == kVoid && b.state(target + 4) == kVoid) {
        b.swap(top, target);
        break;
      }
    }
  }
  return b.transition();
}

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
