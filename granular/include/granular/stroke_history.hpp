#pragma once
/// @file stroke_history.hpp
/// Undo and redo of a player's strokes (a tool held from press to release, or a body thrown) on a
/// World that keeps stepping: an undo puts back the exact world at the start of the last stroke
/// (every cell byte, the tick, the tool calls, the bodies), a redo the exact world at its end.
/// History is kept as the cell bytes of the 16^3 bricks that changed (World::bricks_changed_since),
/// zstd-compressed, and the bodies at each stroke's start and end (World::body_states), within a
/// memory bound that drops the oldest strokes first; the world keeps one checkpoint of its cells
/// (World::take_checkpoint) beside it. docs/design/snapshots-and-undo.md has the design. Under
/// MotionParams::momentum the history keeps the cell bytes only: a cell an undo or redo changes
/// starts with no velocity (docs/design/momentum.md).

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "granular/body.hpp"

namespace granular {

class World;

/// What an undo or a redo did.
struct HistoryMove {
  std::uint64_t tick = 0;        ///< the world's tick after it
  std::uint64_t bricks = 0;      ///< bricks it wrote
  std::size_t strokes_left = 0;  ///< strokes that can still be undone (after an undo) or redone (after a redo)
};

/// The undo/redo history of one World. Call begin_stroke() when the player presses a tool's button
/// and end_stroke() when they release it; the world may step and take tools in between and after.
/// Redo returns to a stroke's end only while the world has not changed since the undo (no tick, no
/// tool): a game pauses after an undo, as the sandbox does. Any change after an undo, and any new
/// stroke, forgets what could be redone. Borrows the world, which must outlive it; a world holds one
/// checkpoint, so it takes one history at a time: when another history or the game replaces or
/// drops the checkpoint this one took, its begin_stroke, end_stroke, undo and redo throw StateError
/// (undo never puts back other cells) until clear().
class StrokeHistory {
 public:
  /// Bytes of history kept by default: 256 MiB.
  static constexpr std::uint64_t kDefaultMaxBytes = std::uint64_t(256) << 20;

  /// An empty history of `world` that keeps at most `max_bytes` of compressed bricks (> 0). Throws
  /// InvalidArgument for max_bytes 0.
  explicit StrokeHistory(World& world, std::uint64_t max_bytes = kDefaultMaxBytes);
  /// Frees the world's checkpoint.
  ~StrokeHistory();
  StrokeHistory(const StrokeHistory&) = delete;
  StrokeHistory& operator=(const StrokeHistory&) = delete;

  /// A stroke starts now: what changed since the last mark is recorded and the world takes a
  /// checkpoint. A stroke still open is ended first. Throws what World::take_checkpoint throws.
  void begin_stroke();
  /// The open stroke ends now: the bricks it changed (with the ticks run meanwhile) are recorded,
  /// and the oldest strokes are dropped while the history holds more than max_bytes(). Nothing
  /// happens when no stroke is open.
  void end_stroke();
  /// True between begin_stroke() and end_stroke().
  bool stroke_open() const { return open_; }

  /// Puts back the world at the start of the last stroke before now (ending an open stroke first):
  /// every cell byte, the tick, the tool calls and the bodies (World::restore_bodies: a body added
  /// since is gone, and the next add_body gives the handle it gave). Nothing (nullopt) when there is no such stroke.
  std::optional<HistoryMove> undo();
  /// Puts back the world at the end of the stroke the last undo went back over. Nothing (nullopt)
  /// when there is none, or when the world changed since that undo (which forgets the redo list).
  std::optional<HistoryMove> redo();

  /// Strokes undo() can go back over now.
  std::size_t undo_count() const;
  /// Strokes redo() can go forward over now.
  std::size_t redo_count() const;
  /// Bytes the history holds (compressed bricks and their indices, the bodies' states), at most
  /// max_bytes() after every end_stroke(); the world's checkpoint is apart (checkpoint_bytes()).
  std::uint64_t bytes() const { return bytes_; }
  /// The bound given at construction.
  std::uint64_t max_bytes() const { return max_bytes_; }
  /// Bytes of the world's checkpoint (World::checkpoint_bytes).
  std::uint64_t checkpoint_bytes() const;
  /// Forgets every stroke and frees the checkpoint.
  void clear();

 private:
  /// A point in the world's history: its tick and tool calls, and which strokes start and end there.
  struct Mark {
    std::uint64_t tick = 0;
    std::uint64_t tool_calls = 0;
    bool starts_stroke = false;
    bool ends_stroke = false;
    BodyStates bodies;  ///< World::body_states() there
  };
  /// The bricks that changed between two consecutive marks, and their cells at one of the two: at
  /// the earlier mark while the world is at or after the later one, else at the later mark.
  struct Delta {
    std::vector<std::uint32_t> bricks;
    std::vector<std::uint8_t> packed;  ///< the bricks' cells (World::read_bricks layout), zstd
    std::uint64_t cells = 0;           ///< bytes `packed` holds uncompressed
  };

  Mark mark_now() const;
  // Bytes the bodies of `m` take.
  static std::uint64_t mark_bytes(const Mark& m);
  // Appends mark_now() to marks_, counting its bytes.
  void push_mark();
  // True when the world changed (a tick, a tool, any cell) since it was at marks_[at_].
  bool changed() const;
  // Appends the delta from marks_[at_] to now (bricks changed since, their cells at the checkpoint)
  // and a mark for now, unless nothing changed; the world is at that mark then, with a checkpoint.
  void record_tail();
  // The world is exactly at marks_[at_]: a checkpoint of it, and the change version to compare with.
  void settle();
  // True when the history has marks and the world's checkpoint is the one settle() last took.
  bool owns_checkpoint() const;
  // Throws StateError, naming `what`, when the history has marks but the world's checkpoint was
  // replaced or dropped by someone else since settle(): undo would put back other cells.
  void check_checkpoint(const char* what) const;
  // Forgets the marks after marks_[at_] (what could be redone).
  void forget_redo();
  // Moves the world across deltas_[i] (to marks_[i] when `back`, else to marks_[i + 1]), keeping
  // in the delta the cells of the side it left.
  std::uint64_t cross(std::size_t i, bool back);
  // Drops the oldest strokes while bytes_ > max_bytes_, never the mark the world is at.
  void enforce_bound();
  std::uint64_t delta_bytes(const Delta& d) const;

  World& world_;
  std::uint64_t max_bytes_;
  std::deque<Mark> marks_;    ///< oldest first
  std::deque<Delta> deltas_;  ///< deltas_[i] lies between marks_[i] and marks_[i + 1]
  std::size_t at_ = 0;        ///< the mark the world was at when it last settled
  std::uint64_t version_ = 0; ///< World::change_version() then
  std::uint64_t checkpoint_id_ = 0;  ///< World::checkpoint_id() of the checkpoint settle() took
  bool open_ = false;
  std::uint64_t bytes_ = 0;
};

}  // namespace granular
