#pragma once
/// @file frames_in_flight.hpp
/// How many frames the CPU may record ahead of the GPU; per-frame resources come in this many slots.

namespace viewer {

/// Frames in flight (per-frame staging buffers, command buffers, fences).
inline constexpr int kFramesInFlight = 2;

}  // namespace viewer
