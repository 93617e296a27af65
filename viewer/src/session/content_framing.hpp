#pragma once
/// @file content_framing.hpp
/// What the sandbox's camera looks at by default: the scene's content, the bounding box of the
/// cells that are not void (solids included), rather than the whole grid.

#include <optional>
#include <string>

#include "session/camera.hpp"
#include "granular/geometry.hpp"
#include "granular/world.hpp"

namespace viewer {

/// The smallest box holding every non-void cell of `world`; nullopt when every cell is void.
std::optional<granular::Box> content_bounds(const granular::World& world);

/// The default camera: OrbitCamera::framing of the content for an image of `aspect` (width /
/// height), or of the whole grid when it is empty.
OrbitCamera frame_content(const granular::World& world, float aspect);

/// The camera a session starts with: `camera_text` parsed (the --camera option, see
/// OrbitCamera::parse) or, when it is empty, frame_content. Throws std::invalid_argument on a bad text.
OrbitCamera initial_camera(const std::string& camera_text, const granular::World& world, float aspect);

}  // namespace viewer
