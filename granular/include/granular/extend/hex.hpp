#pragma once
/// @file extend/hex.hpp
/// The one way granular prints 64-bit hashes and fingerprints.

#include <cstdint>
#include <string>

namespace granular {

/// `v` as 16 lower-case hexadecimal digits, zero-padded (e.g. "00000000000000ff").
std::string hex64(std::uint64_t v);

}  // namespace granular
