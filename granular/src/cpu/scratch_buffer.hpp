#pragma once
/// @file scratch_buffer.hpp
/// Buffers World reuses from one tool call to the next, freed when one call made them large.

#include <cstddef>
#include <vector>

namespace granular {

/// Bytes a reused buffer keeps between calls: far more than a tool's sphere needs, far less than a
/// grid.
inline constexpr std::size_t kKeptScratchBytes = std::size_t(1) << 20;

/// Frees `buffer`'s memory when it holds more than kKeptScratchBytes (after a load of a large grid
/// or a tool of a large sphere), so that one large call leaves no large buffer behind.
template <class T>
void trim_scratch(std::vector<T>& buffer) {
  if (buffer.capacity() * sizeof(T) <= kKeptScratchBytes) return;
  buffer.clear();
  buffer.shrink_to_fit();
}

}  // namespace granular
