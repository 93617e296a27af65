#include "step/motion_table.hpp"

#include "step/motion_block.hpp"

namespace granular {

std::vector<motion::MotionEntry> derive_motion_table(std::span<const Transition> lut) {
  std::vector<motion::MotionEntry> entries(motion::kMotionEntries);
  const auto transition = [&](std::uint32_t k) { return lut[motion::full_code_key(k)]; };
  for (std::uint32_t index = 0; index < motion::kMotionEntries; ++index)
    entries[index] = motion::motion_entry_at(index, transition);
  return entries;
}

}  // namespace granular
