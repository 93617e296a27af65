#pragma once
/// @file block_bytes.hpp
/// A block's 8 cell bytes as one 64-bit word (cell i in byte i, block.hpp order) and its 24-bit key.

#include <cstdint>

#include "granular/block.hpp"

namespace granular {

/// One in every byte of a word.
inline constexpr std::uint64_t kEveryByte = 0x0101010101010101ull;

/// The block's 8 bytes (cell i in byte i, each < 8) packed to its 24-bit key.
constexpr BlockKey pack_key(std::uint64_t v) {
  std::uint64_t t = (v | (v >> 5)) & 0x003F003F003F003Full;
  t = (t | (t >> 10)) & 0x00000FFF00000FFFull;
  return BlockKey((t | (t >> 20)) & 0xFFFFFFu);
}

/// The inverse of pack_key: cell i's 3 bits in byte i.
constexpr std::uint64_t unpack_key(BlockKey k) {
  std::uint64_t t = (std::uint64_t(k) & 0xFFFu) | ((std::uint64_t(k) & 0xFFF000u) << 20);
  t = (t & 0x0000003F0000003Full) | ((t & 0x00000FC000000FC0ull) << 10);
  return (t & 0x0007000700070007ull) | ((t & 0x0038003800380038ull) << 5);
}

}  // namespace granular
