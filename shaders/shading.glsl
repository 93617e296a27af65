// Sun and sky lighting shared by the raster and ray-march renderers; liquids add a sun glint.
// Include after materials.glsl.

const vec3 kSun = normalize(vec3(0.45, 0.30, 0.84));
const vec3 kBrushColor = vec3(1.0, 0.35, 0.2);

// Lit colour of a surface of `albedo` and look `look`, facing `normal`, with ambient occlusion
// `occlusion` (1: open), seen along `to_eye` (unit vector from the surface to the eye).
vec3 shade(vec3 albedo, uint look, vec3 normal, float occlusion, vec3 to_eye) {
  float diffuse = max(dot(normal, kSun), 0.0);
  float sky = 0.5 + 0.5 * normal.z;
  vec3 color = albedo * (0.72 * diffuse + 0.38 * sky) * occlusion;
  if (look == kLookLiquid) {
    vec3 half_vector = normalize(kSun + to_eye);
    color += vec3(0.55) * pow(max(dot(normal, half_vector), 0.0), 48.0);
  }
  return color;
}

// `color` tinted where `position` lies inside the brush (pc.eye.w: its radius, 0 when hidden).
vec3 brush_highlight(vec3 color, vec3 position) {
  return (pc.eye.w > 0.0 && distance(position, pc.brush.xyz) < pc.eye.w) ? mix(color, kBrushColor, 0.35) : color;
}
