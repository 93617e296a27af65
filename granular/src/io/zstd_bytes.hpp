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

/// The content of `packed`: exactly one zstd frame (`several_frames` false), or one or more frames
/// one after the other (true), each stating its content size (at most kMaxZstdExpansion times its
/// compressed bytes), together `size` bytes; frames and sizes are checked before the output is
/// allocated. Throws ParseError starting with `what` for
/// anything else or corrupt data, OutOfMemory when the output cannot be allocated.
std::vector<std::uint8_t> zstd_decompress(std::span<const std::uint8_t> packed, std::uint64_t size,
                                          const std::string& what, bool several_frames = false);

/// One zstd frame that states its content size, compressed from the content's pieces in order
/// (a DistributedWorld rank's slab, read a chunk at a time).
class ZstdFrameWriter {
 public:
  /// A frame of `content_size` bytes at `level`. Throws OutOfMemory naming `what` when zstd cannot
  /// start.
  ZstdFrameWriter(std::uint64_t content_size, int level, std::string what);
  ~ZstdFrameWriter();
  ZstdFrameWriter(const ZstdFrameWriter&) = delete;
  ZstdFrameWriter& operator=(const ZstdFrameWriter&) = delete;
  /// Compresses the next piece.
  void add(std::span<const std::uint8_t> piece);
  /// Ends the frame and returns it; throws OutOfMemory when the pieces did not add up to the
  /// content size.
  std::vector<std::uint8_t> finish();

 private:
  void* context_;  ///< ZSTD_CCtx
  std::string what_;
  std::vector<std::uint8_t> out_;
};

class ReadableFile;

/// Decompresses the `packed` bytes of zstd frames at byte `at` of `file` (one frame when
/// `several_frames` is false), keeping the content bytes [keep_at, keep_at + keep.size()) in
/// `keep`, with a bounded buffer whatever the content's size. Each frame's header is checked before
/// its content is made: it must state its content size, which zstd's largest expansion of the bytes
/// left bounds (kMaxZstdExpansion), and the frames together must state exactly `size` bytes; so a
/// frame that would expand past `size` is refused unread. Throws ParseError starting with `what`
/// for that, corrupt or cut-short data, or more frames than allowed; FileError when the file
/// cannot be read.
void zstd_decompress_range(const ReadableFile& file, std::uint64_t at, std::uint64_t packed, std::uint64_t size,
                           bool several_frames, std::uint64_t keep_at, std::span<std::uint8_t> keep, const std::string& what);

}  // namespace granular
