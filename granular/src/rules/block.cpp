#include "granular/extend/block.hpp"

namespace granular {

// The encodings are constexpr; these checks pin the conventions the CUDA backend must share.
static_assert(encode_key({0, 1, 2, 3, 4, 5, 6, 7}) == 076543210u);
static_assert(is_permutation(kIdentityTransition));
static_assert(apply_transition({1, 2, 3, 4, 5, 6, 7, 0}, kIdentityTransition)[7] == 0);
static_assert(horizontal_symmetry(0)[5] == 5 && horizontal_symmetry(1)[0] == 1 && horizontal_symmetry(4)[1] == 2);
static_assert([] {
  for (int s = 0; s < 8; ++s)
    for (int i = 0; i < 8; ++i)
      if (symmetry_image(i, s) != horizontal_symmetry(s)[i] || symmetry_preimage(symmetry_image(i, s), s) != i) return false;
  return true;
}());
static_assert(block_count(4, 0) == 2 && block_count(4, 1) == 3 && block_count(5, 0) == 3 && block_count(5, 1) == 3);

}  // namespace granular
