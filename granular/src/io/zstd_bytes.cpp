#include "io/zstd_bytes.hpp"

#include <zstd.h>

#include <algorithm>
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
    const unsigned long long stated = ZSTD_getFrameContentSize(rest.data(), rest.size());
    if (stated == ZSTD_CONTENTSIZE_ERROR)
      throw ParseError(what + " are not a zstd frame" + which + " (" + std::to_string(rest.size()) + " bytes)");
    if (stated == ZSTD_CONTENTSIZE_UNKNOWN)
      throw ParseError(what + ": the zstd frame" + which + " does not state its content size; it must state " +
                       (several_frames ? "one" : std::to_string(size) + " bytes"));
    const std::size_t frame = ZSTD_findFrameCompressedSize(rest.data(), rest.size());
    if (ZSTD_isError(frame))
      throw ParseError(what + ": the zstd frame" + which + " is damaged or cut short: " + ZSTD_getErrorName(frame));
    if (!several_frames && frame != rest.size())
      throw ParseError(what + ": " + std::to_string(rest.size() - frame) + " bytes follow the zstd frame of " +
                       std::to_string(frame) + " bytes");
    total += stated;
    if (total > size || total < stated)
      throw ParseError(what + ": the zstd frame" + which + " holds " + std::to_string(stated) + " bytes; " +
                       (several_frames ? "the frames hold more than " : "expected ") + std::to_string(size));
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

std::uint64_t zstd_decompress_range(std::istream& in, std::uint64_t packed, bool several_frames, std::uint64_t keep_at,
                                    std::span<std::uint8_t> keep, const std::string& what) {
  ZSTD_DCtx* d = ZSTD_createDCtx();
  if (!d) throw OutOfMemory(what + ": zstd could not start decompressing");
  const auto free_context = [&] { ZSTD_freeDCtx(d); };
  std::vector<std::uint8_t> input(1 << 20), output(ZSTD_DStreamOutSize());
  std::uint64_t read = 0, produced = 0;
  std::size_t frames_ended = 0, last = 1;  // last: what the last call returned (0: a frame ended)
  // Keeps the part of the `bytes` just decompressed into `output` that lies in the kept range.
  const auto keep_output = [&](std::size_t bytes) {
    const std::uint64_t from = std::max(produced, keep_at), to = std::min(produced + bytes, keep_at + keep.size());
    if (from < to) std::copy_n(output.data() + (from - produced), to - from, keep.data() + (from - keep_at));
    produced += bytes;
  };
  try {
    while (read < packed) {
      const std::size_t n = std::size_t(std::min<std::uint64_t>(input.size(), packed - read));
      if (!in.read(reinterpret_cast<char*>(input.data()), std::streamsize(n)))
        throw FileError(what + ": the file ends " + std::to_string(packed - read) + " bytes before its compressed cells do");
      read += n;
      ZSTD_inBuffer src{input.data(), n, 0};
      while (src.pos < src.size) {
        if (last == 0 && !several_frames)
          throw ParseError(what + ": " + std::to_string(packed - (read - n + src.pos)) + " bytes follow the zstd frame");
        ZSTD_outBuffer dst{output.data(), output.size(), 0};
        last = ZSTD_decompressStream(d, &dst, &src);
        if (ZSTD_isError(last)) throw ParseError(what + ": the zstd data is damaged: " + ZSTD_getErrorName(last));
        if (last == 0) ++frames_ended;
        keep_output(dst.pos);
      }
    }
    // Flush what the last input left in the decoder.
    for (ZSTD_outBuffer dst{output.data(), output.size(), 0}; last != 0; dst.pos = 0) {
      ZSTD_inBuffer none{nullptr, 0, 0};
      last = ZSTD_decompressStream(d, &dst, &none);
      if (ZSTD_isError(last)) throw ParseError(what + ": the zstd data is damaged: " + ZSTD_getErrorName(last));
      if (dst.pos == 0 && last != 0) throw ParseError(what + ": the zstd data is cut short inside a frame");
      keep_output(dst.pos);
      if (last == 0) ++frames_ended;
    }
  } catch (...) {
    free_context();
    throw;
  }
  free_context();
  if (frames_ended == 0) throw ParseError(what + ": no whole zstd frame");
  if (produced < keep_at + keep.size())
    throw ParseError(what + ": the zstd data holds " + std::to_string(produced) + " bytes, fewer than " +
                     std::to_string(keep_at + keep.size()));
  return produced;
}

}  // namespace granular
