#include "bodies/cell_classes.hpp"

#include <cstddef>
#include <cstring>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace granular {

namespace {

static_assert(kMaterialCount == 8 && kMaterialMask == 7, "a mark and a material make a 5-bit index");

void classify_portable(const CellClassTable& table, const std::uint8_t* marks, const std::uint8_t* bytes,
                       std::uint8_t* out, std::size_t from, std::size_t count) {
  for (std::size_t i = from; i < count; ++i) out[i] = table[marks[i]][bytes[i] & kMaterialMask];
}

#if defined(__x86_64__) || defined(__i386__)
/// The index (mark * 8 + material) picks a byte of the table's low or high sixteen by its low four
/// bits (one shuffle each), and its bit 4 which of the two.
__attribute__((target("ssse3"))) void classify_ssse3(const CellClassTable& table, const std::uint8_t* marks,
                                                     const std::uint8_t* bytes, std::uint8_t* out, std::size_t count) {
  std::uint8_t flat[32];
  std::memcpy(flat, table.data(), sizeof flat);
  const __m128i low = _mm_loadu_si128(reinterpret_cast<const __m128i*>(flat));
  const __m128i high = _mm_loadu_si128(reinterpret_cast<const __m128i*>(flat + 16));
  const __m128i material = _mm_set1_epi8(kMaterialMask), bit4 = _mm_set1_epi8(16);
  std::size_t i = 0;
  for (; i + 16 <= count; i += 16) {
    const __m128i mark = _mm_loadu_si128(reinterpret_cast<const __m128i*>(marks + i));
    const __m128i m = _mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + i)), material);
    const __m128i index = _mm_or_si128(_mm_slli_epi16(mark, 3), m);  // a mark below 4 stays in its byte
    const __m128i upper = _mm_cmpeq_epi8(_mm_and_si128(index, bit4), bit4);
    const __m128i cls = _mm_or_si128(_mm_andnot_si128(upper, _mm_shuffle_epi8(low, index)),
                                     _mm_and_si128(upper, _mm_shuffle_epi8(high, index)));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), cls);
  }
  classify_portable(table, marks, bytes, out, i, count);
}

bool has_ssse3() {
  static const bool has = __builtin_cpu_supports("ssse3");
  return has;
}
#endif

}  // namespace

void classify_cells(const CellClassTable& table, std::span<const std::uint8_t> marks,
                    std::span<const std::uint8_t> bytes, std::span<std::uint8_t> out) {
#if defined(__x86_64__) || defined(__i386__)
  if (has_ssse3()) {
    classify_ssse3(table, marks.data(), bytes.data(), out.data(), out.size());
    return;
  }
#endif
  classify_portable(table, marks.data(), bytes.data(), out.data(), 0, out.size());
}

}  // namespace granular
