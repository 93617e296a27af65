#include "step/motion_table.hpp"

#include "step/motion_block.hpp"

namespace granular {

std::vector<Transition> derive_motion_table(std::span<const Transition> lut) {
  std::vector<Transition> table(motion::kMotionTableKeys);
  for (std::uint32_t k = 0; k < motion::kMotionTableKeys; ++k) table[k] = lut[motion::full_code_key(k)];
  return table;
}

}  // namespace granular
