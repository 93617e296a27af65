#include "session/png_writer.hpp"

#include <cstdint>
#include <stdexcept>

// The one translation unit holding stb_image_write's code; static, so it cannot clash with a
// libstb linked by someone else. Its unused writers (jpg, bmp...) are not our warnings.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace viewer {

void write_png(const std::filesystem::path& path, std::uint32_t width, std::uint32_t height,
               const std::vector<std::uint8_t>& rgba) {
  if (rgba.size() != std::size_t(width) * height * 4) throw std::runtime_error("write_png: pixel count does not match the size");
  if (!stbi_write_png(path.string().c_str(), int(width), int(height), 4, rgba.data(), int(width * 4)))
    throw std::runtime_error("cannot write PNG '" + path.string() + "' (does its folder exist and is it writable?)");
}

}  // namespace viewer
