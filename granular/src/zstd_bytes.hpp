#pragma once
/// @file zstd_bytes.hpp
/// Byte buffers compressed as one zstd frame (zstd is a private dependency of the core): the
/// snapshot file's cells and the stroke history's bricks.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace granular {

/// `bytes` as one zstd frame at `level` that states its content size. Throws OutOfMemory naming
/// `what` when the buffer cannot be allocated or zstd fails.
std::vector<std::uint8_t> zstd_compress(std::span<const std::uint8_t> bytes, int level, const std::string& what);

/// The content of `packed`, which must be exactly one zstd frame stating a content size of `size`
/// bytes: both are checked before the output is allocated. Throws ParseError starting with `what`
/// for anything else or corrupt data, OutOfMemory when the output cannot be allocated.
std::vector<std::uint8_t> zstd_decompress(std::span<const std::uint8_t> packed, std::uint64_t size,
                                          const std::string& what);

}  // namespace granular
