#pragma once
/// @file png_writer.hpp
/// Writes RGBA8 pixels to a PNG file (stb_image_write).

#include <cstdint>
#include <filesystem>
#include <vector>

namespace viewer {

/// Writes `rgba` (width * height * 4 bytes, rows top to bottom) to `path`; throws
/// std::runtime_error naming the path when it cannot be written.
void write_png(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
               const std::vector<std::uint8_t>& rgba);

}  // namespace viewer
