// What every viewer shader shares: the push constants (viewer/src/view_constants.hpp mirrors
// them) and the brick size.
layout(push_constant) uniform ViewConstants {
  mat4 matrix;     // raster: view-projection; ray march: inverse view-projection
  vec4 eye;        // camera position (cells); w: brush radius (0: no brush)
  ivec4 grid;      // grid extent xyz; w: the section and x-ray (see_inside.glsl)
  ivec4 bricks;    // bricks per axis xyz; w: image width (ray march)
  vec4 brush;      // brush centre xyz (cells); w: image height (ray march)
} pc;

// A brick: the cube of cells that is the unit of upload, rebuild and drawing (granular::kBrickSize).
const int kBrickSize = 16;
const uint kBrickCells = 4096u;
