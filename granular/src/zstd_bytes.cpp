#include "zstd_bytes.hpp"

#include <zstd.h>

#include <new>

#include "granular/errors.hpp"

namespace granular {

std::vector<std::uint8_t> zstd_compress(std::span<const std::uint8_t> bytes, int level, const std::string& what) {
  std::vector<std::uint8_t> packed;
  try {
    packed.resize(ZSTD_compressBound(bytes.size()));
  } catch (const std::bad_alloc&) {
    throw OutOfMemory(what + ": could not allocate " + std::to_string(ZSTD_compressBound(bytes.size())) +
                      " bytes to compress " + std::to_string(bytes.size()) + " bytes");
  }
  const std::size_t n = ZSTD_compress(packed.data(), packed.size(), bytes.data(), bytes.size(), level);
  if (ZSTD_isError(n))
    throw OutOfMemory(what + ": zstd could not compress " + std::to_string(bytes.size()) + " bytes: " +
                      ZSTD_getErrorName(n));
  packed.resize(n);
  packed.shrink_to_fit();
  return packed;
}

std::vector<std::uint8_t> zstd_decompress(std::span<const std::uint8_t> packed, std::uint64_t size,
                                          const std::string& what) {
  const unsigned long long stated = ZSTD_getFrameContentSize(packed.data(), packed.size());
  if (stated == ZSTD_CONTENTSIZE_ERROR)
    throw ParseError(what + " are not a zstd frame (" + std::to_string(packed.size()) + " bytes)");
  if (stated == ZSTD_CONTENTSIZE_UNKNOWN)
    throw ParseError(what + ": the zstd frame does not state its content size; it must state " +
                     std::to_string(size) + " bytes");
  if (stated != size)
    throw ParseError(what + ": the zstd frame holds " + std::to_string(stated) + " bytes; expected " +
                     std::to_string(size));
  const std::size_t frame = ZSTD_findFrameCompressedSize(packed.data(), packed.size());
  if (ZSTD_isError(frame))
    throw ParseError(what + ": the zstd frame is damaged or cut short: " + ZSTD_getErrorName(frame));
  if (frame != packed.size())
    throw ParseError(what + ": " + std::to_string(packed.size() - frame) + " bytes follow the zstd frame of " +
                     std::to_string(frame) + " bytes");
  std::vector<std::uint8_t> out;
  try {
    out.resize(std::size_t(size));
  } catch (const std::bad_alloc&) {
    throw OutOfMemory(what + ": could not allocate the " + std::to_string(size) + " bytes they hold");
  }
  const std::size_t got = ZSTD_decompress(out.data(), out.size(), packed.data(), packed.size());
  if (ZSTD_isError(got))
    throw ParseError(what + ": the zstd frame is damaged: " + ZSTD_getErrorName(got));
  if (got != size)
    throw ParseError(what + ": the zstd frame gave " + std::to_string(got) + " bytes; it states " +
                     std::to_string(size));
  return out;
}

}  // namespace granular
