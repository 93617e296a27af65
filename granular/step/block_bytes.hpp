#pragma once
/// @file block_bytes.hpp
/// A block's 8 cell bytes as one 64-bit word (cell i in byte i, block.hpp order) and its 24-bit key.

#include <cstdint>

#include "granular/extend/block.hpp"

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

/// Byte p of a block's word.
constexpr std::uint32_t byte_at(std::uint64_t bytes, int p) { return std::uint32_t(bytes >> (8 * p)) & 0xFFu; }

/// `bytes` with byte p set to `v` (below 256).
constexpr std::uint64_t with_byte(std::uint64_t bytes, int p, std::uint32_t v) {
  return (bytes & ~(0xFFull << (8 * p))) | (std::uint64_t(v) << (8 * p));
}

/// A per-cell lookup in a table of 8 bytes: byte i of the result is byte (b & 7) of `table`, where b
/// is byte i of `bytes` (its low 3 bits: the cell's material).
constexpr std::uint64_t lookup_bytes(std::uint64_t table, std::uint64_t bytes) {
  std::uint64_t out = 0;
  for (int i = 0; i < 8; ++i) out |= ((table >> (8 * ((bytes >> (8 * i)) & 7u))) & 0xFFu) << (8 * i);
  return out;
}

/// A byte permutation in gather form: byte p of the result is byte (nibble p of `from`) of `bytes`
/// (each nibble below 8).
constexpr std::uint64_t gather_bytes(std::uint64_t bytes, std::uint32_t from) {
  std::uint64_t out = 0;
  for (int p = 0; p < 8; ++p) out |= ((bytes >> (8 * ((from >> (4 * p)) & 7u))) & 0xFFu) << (8 * p);
  return out;
}

/// The portable forms of the byte operations of the block step; a Platform (block_step.hpp) may
/// supply faster ones of the same names and meaning (a GPU's byte permute).
struct PortableByteOps {
  /// lookup_bytes.
  static constexpr std::uint64_t lookup(std::uint64_t table, std::uint64_t bytes) { return lookup_bytes(table, bytes); }
  /// gather_bytes.
  static constexpr std::uint64_t gather(std::uint64_t bytes, std::uint32_t from) { return gather_bytes(bytes, from); }
};

}  // namespace granular
