#include "session/camera.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

namespace viewer {

OrbitCamera OrbitCamera::framing(granular::Int3 size) {
  OrbitCamera camera;
  camera.target = glm::vec3(size.x, size.y, size.z) * 0.5f - glm::vec3(0, 0, size.z * 0.12f);
  const float extent = float(std::max({size.x, size.y, size.z}));
  camera.distance = extent * 1.9f;
  return camera;
}

OrbitCamera OrbitCamera::framing(const granular::Box& box, float aspect, float fill) {
  OrbitCamera camera;
  const glm::vec3 lo(box.min.x, box.min.y, box.min.z), hi(box.max.x, box.max.y, box.max.z);
  auto corner_point = [&](int corner) {
    return glm::vec3((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
  };
  camera.target = (lo + hi) * 0.5f;
  const glm::vec3 forward = glm::normalize(camera.target - camera.eye());
  const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0, 0, 1)));
  const glm::vec3 up = glm::cross(right, forward);
  const float tan_v = std::tan(glm::radians(camera.fov_degrees) * 0.5f);
  const float tan_h = tan_v * aspect;
  // In the view's basis (right, up, forward), a corner at v from the target lies inside `fill` of
  // the frame when |v.right| <= fill * tan_h * depth (and likewise up), depth being distance +
  // v.forward: each corner and axis bounds the distance from below. Perspective makes the near
  // corners look larger, so the fitted box is off centre; the target then moves by the offset of
  // the box's image from the frame's centre and the distance is fitted again.
  for (int pass = 0; pass < 4; ++pass) {
    float distance = 1.0f;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 v = corner_point(corner) - camera.target;
      const float depth_offset = glm::dot(v, forward);
      distance = std::max({distance, std::abs(glm::dot(v, right)) / (fill * tan_h) - depth_offset,
                           std::abs(glm::dot(v, up)) / (fill * tan_v) - depth_offset, 1.0f - depth_offset});
    }
    camera.distance = distance;
    glm::vec2 image_min(1e30f), image_max(-1e30f);  // the corners' image, in units of the frame's half size
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 v = corner_point(corner) - camera.target;
      const float depth = distance + glm::dot(v, forward);
      const glm::vec2 image(glm::dot(v, right) / (tan_h * depth), glm::dot(v, up) / (tan_v * depth));
      image_min = glm::min(image_min, image);
      image_max = glm::max(image_max, image);
    }
    const glm::vec2 offset = (image_min + image_max) * 0.5f;
    camera.target += distance * (offset.x * tan_h * right + offset.y * tan_v * up);
  }
  return camera;
}

OrbitCamera OrbitCamera::parse(const std::string& text, granular::Int3 size) {
  std::vector<float> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    try {
      std::size_t used = 0;
      values.push_back(std::stof(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw std::invalid_argument("--camera '" + text + "': '" + item + "' is not a number");
    }
  }
  if (values.size() != 3 && values.size() != 6)
    throw std::invalid_argument("--camera '" + text + "': expected yaw,pitch,distance or yaw,pitch,distance,tx,ty,tz");
  if (values[2] <= 0) throw std::invalid_argument("--camera '" + text + "': distance must be > 0");
  OrbitCamera camera = framing(size);
  camera.yaw_degrees = values[0];
  camera.pitch_degrees = std::clamp(values[1], -89.0f, 89.0f);
  camera.distance = values[2] * float(std::max({size.x, size.y, size.z}));
  if (values.size() == 6) camera.target = glm::vec3(values[3] * size.x, values[4] * size.y, values[5] * size.z);
  return camera;
}

glm::vec3 OrbitCamera::eye() const {
  const float yaw = glm::radians(yaw_degrees), pitch = glm::radians(pitch_degrees);
  return target + distance * glm::vec3(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
}

glm::mat4 OrbitCamera::view() const { return glm::lookAt(eye(), target, glm::vec3(0, 0, 1)); }

glm::mat4 OrbitCamera::projection(float aspect) const {
  const float near_plane = std::max(0.05f, distance * 0.01f);
  glm::mat4 projection = glm::perspective(glm::radians(fov_degrees), aspect, near_plane, distance * 4.0f + 4096.0f);
  projection[1][1] *= -1.0f;
  return projection;
}

void OrbitCamera::orbit(float dx, float dy) {
  yaw_degrees -= dx * 0.3f;
  pitch_degrees = std::clamp(pitch_degrees + dy * 0.3f, -89.0f, 89.0f);
}

void OrbitCamera::pan(float dx, float dy) {
  const glm::vec3 forward = glm::normalize(target - eye());
  const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0, 0, 1)));
  const glm::vec3 up = glm::cross(right, forward);
  const float scale = distance * 0.0015f;
  target += (-dx * right + dy * up) * scale;
}

void OrbitCamera::zoom(float factor) { distance = std::clamp(distance * factor, 1.0f, 100000.0f); }

void OrbitCamera::fly(float forward, float right, float up) {
  const glm::vec3 f = glm::normalize(target - eye());
  const glm::vec3 r = glm::normalize(glm::cross(f, glm::vec3(0, 0, 1)));
  target += forward * f + right * r + up * glm::vec3(0, 0, 1);
}

Ray ray_through_pixel(const OrbitCamera& camera, float x, float y, float width, float height) {
  const glm::mat4 inverse = glm::inverse(camera.projection(width / height) * camera.view());
  const float ndc_x = 2.0f * (x + 0.5f) / width - 1.0f;
  const float ndc_y = 2.0f * (y + 0.5f) / height - 1.0f;
  glm::vec4 far_point = inverse * glm::vec4(ndc_x, ndc_y, 1.0f, 1.0f);
  far_point /= far_point.w;
  Ray ray;
  ray.origin = camera.eye();
  ray.direction = glm::normalize(glm::vec3(far_point) - ray.origin);
  return ray;
}

}  // namespace viewer
