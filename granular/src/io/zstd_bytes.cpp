#include "io/zstd_bytes.hpp"

#include <zstd.h>

#include <algorithm>
#include <new>

#include "granular/errors.hpp"
#include "io/expansion_bound.hpp"
#include "io/regular_file.hpp"

namespace granular {

namespace {

/// The content size that the zstd frame at the start of `rest` states (`left` bytes lie from its
/// start to the end of the data): a ParseError naming the frame (`which`, after `what`) when `rest`
/// does not start a frame or the frame does not state its size.
std::uint64_t stated_content_size(std::span<const std::uint8_t> rest, std::uint64_t left, std::uint64_t size,
                                  bool several_frames, const std::string& what, const std::string& which) {
  const unsigned long long stated = ZSTD_getFrameContentSize(rest.data(), rest.size());
  if (stated == ZSTD_CONTENTSIZE_ERROR)
    throw ParseError(what + " are not a zstd frame" + which + " (" + std::to_string(left) + " bytes)");
  if (stated == ZSTD_CONTENTSIZE_UNKNOWN)
    throw ParseError(what + ": the zstd frame" + which + " does not state its content size; it must state " +
                     (several_frames ? "one" : std::to_string(size) + " bytes"));
  return stated;
}

/// Checks a frame's stated content before any of it is made: within kMaxZstdExpansion of the
/// `backing` bytes that hold the frame at most, and, added to the frames' `total` so far, within the
/// `size` bytes expected.
void add_stated_content(std::uint64_t stated, std::uint64_t backing, std::uint64_t size, bool several_frames,
                        std::uint64_t& total, const std::string& what, const std::string& which) {
  if (exceeds_expansion(stated, backing, kMaxZstdExpansion))
    throw ParseError(what + ": the zstd frame" + which + " states " + std::to_string(stated) +
                     " bytes of content in at most " + std::to_string(backing) + " bytes (zstd expands at most " +
                     std::to_string(kMaxZstdExpansion) + "-fold)");
  total += stated;
  if (total > size || total < stated)
    throw ParseError(what + ": the zstd frame" + which + " holds " + std::to_string(stated) + " bytes; " +
                     (several_frames ? "the frames hold more than " : "expected ") + std::to_string(size));
}

}  // namespace

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
                                          const std::string& what, bool several_frames) {
  // The frames: where each lies and what it states, all checked before anything is allocated.
  struct Frame {
    std::size_t at, bytes;
    std::uint64_t content;
  };
  std::vector<Frame> frames;
  std::uint64_t total = 0;
  for (std::size_t at = 0; at < packed.size() || frames.empty();) {
    const std::span<const std::uint8_t> rest = packed.subspan(at);
    const std::string which = several_frames ? " (frame " + std::to_string(frames.size()) + " at byte " + std::to_string(at) + ")" : "";
    const std::uint64_t stated = stated_content_size(rest, rest.size(), size, several_frames, what, which);
    const std::size_t frame = ZSTD_findFrameCompressedSize(rest.data(), rest.size());
    if (ZSTD_isError(frame))
      throw ParseError(what + ": the zstd frame" + which + " is damaged or cut short: " + ZSTD_getErrorName(frame));
    if (!several_frames && frame != rest.size())
      throw ParseError(what + ": " + std::to_string(rest.size() - frame) + " bytes follow the zstd frame of " +
                       std::to_string(frame) + " bytes");
    add_stated_content(stated, frame, size, several_frames, total, what, which);
    frames.push_back({at, frame, stated});
    at += frame;
  }
  if (total != size)
    throw ParseError(what + ": the zstd frame" + (several_frames ? "s hold " : " holds ") + std::to_string(total) +
                     " bytes; expected " + std::to_string(size));
  std::vector<std::uint8_t> out;
  try {
    out.resize(std::size_t(size));
  } catch (const std::bad_alloc&) {
    throw OutOfMemory(what + ": could not allocate the " + std::to_string(size) + " bytes they hold");
  }
  std::size_t filled = 0;
  for (const Frame& f : frames) {
    const std::size_t got = ZSTD_decompress(out.data() + filled, std::size_t(f.content), packed.data() + f.at, f.bytes);
    if (ZSTD_isError(got))
      throw ParseError(what + ": the zstd frame at byte " + std::to_string(f.at) + " is damaged: " + ZSTD_getErrorName(got));
    if (got != f.content)
      throw ParseError(what + ": the zstd frame at byte " + std::to_string(f.at) + " gave " + std::to_string(got) +
                       " bytes; it states " + std::to_string(f.content));
    filled += got;
  }
  return out;
}

ZstdFrameWriter::ZstdFrameWriter(std::uint64_t content_size, int level, std::string what)
    : context_(ZSTD_createCCtx()), what_(std::move(what)) {
  ZSTD_CCtx* c = static_cast<ZSTD_CCtx*>(context_);
  if (!c || ZSTD_isError(ZSTD_CCtx_setParameter(c, ZSTD_c_compressionLevel, level)) ||
      ZSTD_isError(ZSTD_CCtx_setPledgedSrcSize(c, content_size))) {
    ZSTD_freeCCtx(c);
    throw OutOfMemory(what_ + ": zstd could not start a frame of " + std::to_string(content_size) + " bytes");
  }
}

ZstdFrameWriter::~ZstdFrameWriter() { ZSTD_freeCCtx(static_cast<ZSTD_CCtx*>(context_)); }

void ZstdFrameWriter::add(std::span<const std::uint8_t> piece) {
  ZSTD_inBuffer in{piece.data(), piece.size(), 0};
  std::uint8_t block[1 << 16];
  while (in.pos < in.size) {
    ZSTD_outBuffer out{block, sizeof block, 0};
    const std::size_t r = ZSTD_compressStream2(static_cast<ZSTD_CCtx*>(context_), &out, &in, ZSTD_e_continue);
    if (ZSTD_isError(r)) throw OutOfMemory(what_ + ": zstd could not compress: " + ZSTD_getErrorName(r));
    out_.insert(out_.end(), block, block + out.pos);
  }
}

std::vector<std::uint8_t> ZstdFrameWriter::finish() {
  ZSTD_inBuffer in{nullptr, 0, 0};
  std::uint8_t block[1 << 16];
  for (;;) {
    ZSTD_outBuffer out{block, sizeof block, 0};
    const std::size_t left = ZSTD_compressStream2(static_cast<ZSTD_CCtx*>(context_), &out, &in, ZSTD_e_end);
    if (ZSTD_isError(left)) throw OutOfMemory(what_ + ": zstd could not end the frame: " + ZSTD_getErrorName(left));
    out_.insert(out_.end(), block, block + out.pos);
    if (left == 0) break;
  }
  return std::move(out_);
}

void zstd_decompress_range(const ReadableFile& file, std::uint64_t at, std::uint64_t packed, std::uint64_t size,
                           bool several_frames, std::uint64_t keep_at, std::span<std::uint8_t> keep, const std::string& what) {
  if (keep_at > size || keep.size() > size - keep_at)
    throw ParseError(what + ": the kept bytes " + std::to_string(keep_at) + ".." + std::to_string(keep_at + keep.size()) +
                     " lie outside the " + std::to_string(size) + " bytes of content");
  ZSTD_DCtx* d = ZSTD_createDCtx();
  if (!d) throw OutOfMemory(what + ": zstd could not start decompressing");
  struct FreeContext {
    ZSTD_DCtx* d;
    ~FreeContext() { ZSTD_freeDCtx(d); }
  } const free_context{d};
  std::vector<std::uint8_t> input(1 << 20), output(ZSTD_DStreamOutSize());
  std::size_t begin = 0, end = 0;  // the bytes of `input` not yet decompressed
  std::uint64_t read = 0;          // compressed bytes read into `input` so far
  // Moves the unread bytes to the front of `input` and reads more after them.
  const auto refill = [&] {
    std::copy(input.begin() + std::ptrdiff_t(begin), input.begin() + std::ptrdiff_t(end), input.begin());
    end -= begin;
    begin = 0;
    const std::size_t n = std::size_t(std::min<std::uint64_t>(input.size() - end, packed - read));
    file.read_at(at + read, std::span(input).subspan(end, n));
    read += n;
    end += n;
  };
  std::uint64_t produced = 0, stated_total = 0, frame_content = 0, frame_produced = 0;
  std::size_t frames = 0;
  bool in_frame = false;
  for (;;) {
    if (!in_frame) {
      if (begin == end && read == packed) break;
      const std::uint64_t frame_at = read - (end - begin);
      const std::string which = " (frame " + std::to_string(frames) + " at byte " + std::to_string(frame_at) + ")";
      if (frames > 0 && !several_frames)
        throw ParseError(what + ": " + std::to_string(packed - frame_at) + " bytes follow the zstd frame");
      // The frame's header is checked before any of its content is made.
      constexpr std::size_t kLongestFrameHeader = 18;  // magic 4, descriptor 1, window 1, dictionary 4, size 8
      if (end - begin < kLongestFrameHeader && read < packed) refill();
      frame_content = stated_content_size(std::span(input).subspan(begin, end - begin), packed - frame_at, size,
                                          several_frames, what, which);
      add_stated_content(frame_content, packed - frame_at, size, several_frames, stated_total, what, which);
      in_frame = true;
      frame_produced = 0;
    }
    if (begin == end && read < packed) refill();
    ZSTD_inBuffer src{input.data() + begin, end - begin, 0};
    ZSTD_outBuffer dst{output.data(), output.size(), 0};
    const std::size_t left = ZSTD_decompressStream(d, &dst, &src);
    if (ZSTD_isError(left)) throw ParseError(what + ": the zstd data is damaged: " + ZSTD_getErrorName(left));
    begin += src.pos;
    if (frame_produced + dst.pos > frame_content)
      throw ParseError(what + ": a zstd frame holds more than the " + std::to_string(frame_content) + " bytes it states");
    // Keeps the part of the output that lies in the kept range.
    const std::uint64_t from = std::max(produced, keep_at), to = std::min(produced + dst.pos, keep_at + keep.size());
    if (from < to) std::copy_n(output.data() + (from - produced), to - from, keep.data() + (from - keep_at));
    produced += dst.pos;
    frame_produced += dst.pos;
    if (left == 0) {
      if (frame_produced != frame_content)
        throw ParseError(what + ": a zstd frame holds " + std::to_string(frame_produced) + " bytes; it states " +
                         std::to_string(frame_content));
      in_frame = false;
      ++frames;
    } else if (src.pos == 0 && dst.pos == 0 && begin == end && read == packed) {
      throw ParseError(what + ": the zstd data is cut short inside a frame");
    }
  }
  if (frames == 0) throw ParseError(what + ": no whole zstd frame");
  if (produced != size)
    throw ParseError(what + ": the zstd frame" + (several_frames ? "s hold " : " holds ") + std::to_string(produced) +
                     " bytes; expected " + std::to_string(size));
}

}  // namespace granular
