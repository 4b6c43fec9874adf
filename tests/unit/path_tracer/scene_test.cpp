// The scene's geometry: camera rays, the sphere and the floor met where the geometry says,
// normals facing the ray, texels where the chart's layout puts them, shadows.

#include "path_tracer/scene.h"

#include <gtest/gtest.h>

#include <cmath>

namespace spectralize::path_tracer {
namespace {

SceneLayout layout() {
  SceneLayout l;
  l.eye = {0, 1, 10};
  l.target = {0, 1, 0};
  l.vertical_fov_deg = 40;
  l.sphere_centre = {0, 1, 0};
  l.sphere_radius = 1;
  l.floor_width = 6;
  return l;
}

TEST(Scene, CentreRayLooksAtTheTarget) {
  const Scene scene(layout(), 60, 40);
  const Ray r = scene.camera_ray(50, 50, 100);
  EXPECT_NEAR(r.direction.x, 0, 1e-12);
  EXPECT_NEAR(r.direction.y, 0, 1e-12);
  EXPECT_NEAR(r.direction.z, -1, 1e-12);
  // The top edge of the image is half the field of view up.
  const Ray top = scene.camera_ray(50, 0, 100);
  EXPECT_NEAR(std::atan2(top.direction.y, -top.direction.z), 20 * M_PI / 180, 1e-12);
}

TEST(Scene, SphereIsMetAtItsSurfaceFacingTheRay) {
  const Scene scene(layout(), 60, 40);
  const auto hit = scene.intersect({{0, 1, 10}, {0, 0, -1}});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 9, 1e-12);
  EXPECT_NEAR(hit->normal.z, 1, 1e-12);
  // The front of the equator is the middle of the chart: u = 0.5, v = 0.5.
  EXPECT_EQ(hit->texel, 20u * 60 + 30);
  // From inside, the normal faces the ray too.
  const auto inside = scene.intersect({{0, 1, 0}, {1, 0, 0}});
  ASSERT_TRUE(inside);
  EXPECT_NEAR(inside->distance, 1, 1e-12);
  EXPECT_NEAR(inside->normal.x, -1, 1e-12);
}

TEST(Scene, FloorCarriesTheChartInItsAspect) {
  const Scene scene(layout(), 60, 40);  // floor 6 x 4 units: 10 texels per unit
  // Straight down onto (2.05, 0, -1.55): u = 2.05 / 6 + 0.5, v = -1.55 / 4 + 0.5.
  const auto hit = scene.intersect({{2.05, 5, -1.55}, {0, -1, 0}});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 5, 1e-12);
  EXPECT_NEAR(hit->normal.y, 1, 1e-12);
  EXPECT_EQ(hit->texel, 4u * 60 + 50);
  // Beyond the chart's rectangle there is no floor.
  EXPECT_FALSE(scene.intersect({{3.01, 5, 5}, {0, -1, 0}}));
  EXPECT_FALSE(scene.intersect({{0, 5, 2.01}, {0, -1, 0}}));
  // From below, the normal faces down.
  const auto below = scene.intersect({{2.5, -1, 1}, {0, 1, 0}});
  ASSERT_TRUE(below);
  EXPECT_NEAR(below->normal.y, -1, 1e-12);
}

TEST(Scene, TheSphereShadowsTheFloorBeneathIt) {
  const Scene scene(layout(), 60, 40);
  EXPECT_TRUE(scene.occluded({{0, 0, 0}, {0, 1, 0}}));
  EXPECT_FALSE(scene.occluded({{2.5, 0, 0}, {0, 1, 0}}));
  // A ray that starts on a surface does not meet that surface again.
  EXPECT_FALSE(scene.occluded({{0, 2, 0}, {0, 1, 0}}));
}

}  // namespace
}  // namespace spectralize::path_tracer
