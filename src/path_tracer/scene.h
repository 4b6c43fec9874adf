#pragma once
// The test scene's geometry: a pinhole camera looking at a textured sphere resting on a
// textured floor (the figures' sphere, now lit from all around). Both surfaces are Lambertian
// and carry one texture (the ColorChecker chart): the floor as a rectangle of the chart's aspect,
// the sphere with the chart wrapped twice around its equator. Nothing here is spectral.

#include <cmath>
#include <cstdint>
#include <optional>

namespace spectralize::path_tracer {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
};
inline double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline Vec3 normalize(Vec3 a) {
  return (1 / std::sqrt(dot(a, a))) * a;
}

struct Ray {
  Vec3 origin, direction;  // direction of unit length
};

/// Where a ray meets a surface: the point, the normal facing the ray, the texel.
struct Hit {
  double distance = 0;
  Vec3 point, normal;
  std::uint32_t texel = 0;
};

/// The scene's layout (world units; y up).
struct SceneLayout {
  Vec3 eye{0, 6.0, 5.2}, target{0, 0.3, 0.1};
  double vertical_fov_deg = 44;
  Vec3 sphere_centre{1.35, 0.95, -0.75};
  double sphere_radius = 0.95;
  double floor_width = 6.0;  // the chart on the floor y = 0, centred on the origin, its height
                             // set by the texture's aspect ratio
};

class Scene {
 public:
  /// The layout with a texture of width x height texels (row 0 at the far edge of the floor and
  /// at the sphere's north pole). Cost: O(1).
  Scene(const SceneLayout& layout, int texture_width, int texture_height);

  /// The camera ray through image point (px, py) in pixels of a size x size image (y down).
  /// Cost: O(1).
  Ray camera_ray(double px, double py, int size) const;
  /// The nearest surface the ray meets beyond a small offset, if any. Cost: O(1).
  std::optional<Hit> intersect(const Ray& ray) const;
  /// True when a surface lies along the ray (shadow rays to the environment). Cost: O(1).
  bool occluded(const Ray& ray) const { return intersect(ray).has_value(); }

 private:
  std::uint32_t texel_at(double u, double v) const;
  SceneLayout layout_;
  int tex_w_, tex_h_;
  double floor_depth_;
  Vec3 forward_, right_, up_;
  double tan_half_fov_;
};

}  // namespace spectralize::path_tracer
