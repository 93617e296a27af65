#pragma once
/// @file little_endian.hpp
/// Unsigned little-endian fields of the file formats (docs/FORMATS.md), read from and written into
/// byte buffers whatever the host's byte order.

#include <cstddef>
#include <cstdint>
#include <span>

namespace granular {

/// The `Bytes`-byte little-endian number at byte `at` of `b` (which holds it).
template <std::size_t Bytes>
std::uint64_t get_le(std::span<const std::uint8_t> b, std::size_t at) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < Bytes; ++i) v |= std::uint64_t(b[at + i]) << (8 * i);
  return v;
}

/// The uint32 at byte `at` of `b`.
inline std::uint32_t get_u32(std::span<const std::uint8_t> b, std::size_t at) { return std::uint32_t(get_le<4>(b, at)); }

/// The uint64 at byte `at` of `b`.
inline std::uint64_t get_u64(std::span<const std::uint8_t> b, std::size_t at) { return get_le<8>(b, at); }

/// Writes the low `Bytes` bytes of `v` to `dst`, least significant first.
template <std::size_t Bytes>
void put_le(std::uint8_t* dst, std::uint64_t v) {
  for (std::size_t i = 0; i < Bytes; ++i) dst[i] = std::uint8_t(v >> (8 * i));
}

/// Writes `v` as a uint32 to `dst`.
inline void put_u32(std::uint8_t* dst, std::uint32_t v) { put_le<4>(dst, v); }

/// Writes `v` as a uint64 to `dst`.
inline void put_u64(std::uint8_t* dst, std::uint64_t v) { put_le<8>(dst, v); }

}  // namespace granular
