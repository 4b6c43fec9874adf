#include "path_tracer/scene.h"

#include <algorithm>
#include <numbers>

namespace spectralize::path_tracer {

namespace {

// Rays start this far along their direction: no surface is met again at its own point.
constexpr double kEpsilon = 1e-6;

}  // namespace

Scene::Scene(const SceneLayout& layout, int texture_width, int texture_height)
    : layout_(layout),
      tex_w_(texture_width),
      tex_h_(texture_height),
      floor_depth_(layout.floor_width * texture_height / texture_width) {
  forward_ = normalize(layout.target - layout.eye);
  right_ = normalize(cross(forward_, Vec3{0, 1, 0}));
  up_ = cross(right_, forward_);
  tan_half_fov_ = std::tan(layout.vertical_fov_deg * std::numbers::pi / 360);
}

Ray Scene::camera_ray(double px, double py, int size) const {
  const double sx = (2 * px / size - 1) * tan_half_fov_;
  const double sy = (1 - 2 * py / size) * tan_half_fov_;
  return {layout_.eye, normalize(forward_ + sx * right_ + sy * up_)};
}

std::uint32_t Scene::texel_at(double u, double v) const {
  const int x = std::clamp(static_cast<int>(u * tex_w_), 0, tex_w_ - 1);
  const int y = std::clamp(static_cast<int>(v * tex_h_), 0, tex_h_ - 1);
  return static_cast<std::uint32_t>(y * tex_w_ + x);
}

std::optional<Hit> Scene::intersect(const Ray& ray) const {
  std::optional<Hit> best;
  // The sphere: |o + t d - c|^2 = r^2.
  const Vec3 oc = ray.origin - layout_.sphere_centre;
  const double b = dot(oc, ray.direction);
  const double c = dot(oc, oc) - layout_.sphere_radius * layout_.sphere_radius;
  const double disc = b * b - c;
  if (disc >= 0) {
    const double root = std::sqrt(disc);
    double t = -b - root;
    if (t <= kEpsilon) t = -b + root;
    if (t > kEpsilon) {
      Hit h;
      h.distance = t;
      h.point = ray.origin + t * ray.direction;
      const Vec3 n = (1 / layout_.sphere_radius) * (h.point - layout_.sphere_centre);
      h.normal = dot(n, ray.direction) < 0 ? n : -1.0 * n;
      // The chart twice around the equator (u), pole to pole (v).
      const double phi = std::atan2(n.x, n.z);  // 0 facing +z, the camera's side
      double u = 0.5 + phi / std::numbers::pi;
      u -= std::floor(u);
      const double v = std::acos(std::clamp(n.y, -1.0, 1.0)) / std::numbers::pi;
      h.texel = texel_at(u, v);
      best = h;
    }
  }
  // The floor: the chart's rectangle in the plane y = 0.
  if (ray.direction.y != 0) {
    const double t = -ray.origin.y / ray.direction.y;
    if (t > kEpsilon && (!best || t < best->distance)) {
      const Vec3 p = ray.origin + t * ray.direction;
      const double u = p.x / layout_.floor_width + 0.5, v = p.z / floor_depth_ + 0.5;
      if (u >= 0 && u < 1 && v >= 0 && v < 1) {
        Hit h;
        h.distance = t;
        h.point = p;
        h.normal = ray.direction.y < 0 ? Vec3{0, 1, 0} : Vec3{0, -1, 0};
        h.texel = texel_at(u, v);
        best = h;
      }
    }
  }
  return best;
}

}  // namespace spectralize::path_tracer
