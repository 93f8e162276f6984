// aniso/render/geometry.h: the scene's shapes in an Embree 3 BVH, and what a ray hit means for shading:
// the point, the geometric and shading normals, the UVs and the tangent frame the object's tangent
// source gives there (aniso/tangent/fields.h).
//
// Natural tangents (dp/du), per shape (docs/scenes.md):
//   sphere     u = phi / (2 pi), phi = atan2(n.x, n.z) about +y; v = 1 - theta / pi (v up);
//              dp/du = +y x n, along the circles of latitude (zero at the poles)
//   disc       planar: u along e_u = world x projected onto the disc (world z where the normal is
//              within 2.6 degrees of x), v along n x e_u; uv = 0.5 + offset / (2 radius)
//   rectangle  u along its "u" key, v along normal x u; uv in [0, 1]^2 over the rectangle
//   mesh       the mesh's per-vertex tangents when it has them (the torus; or UV tangents when
//              {"field": "uv"} asked for them), else the triangle's dp/du from its UVs, else none
// Sphere lights are in the same BVH (emitters only: they reflect nothing).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>

#include "aniso/core/frame.h"
#include "aniso/render/scene.h"

namespace aniso::render {

struct Ray {
  Vec3 o{0.0f}, d{0.0f, 0.0f, 1.0f};
};

struct SurfaceHit {
  float t = 0.0f;
  Vec3 p{0.0f};
  Vec3 ng{0.0f, 0.0f, 1.0f};  // geometric normal, facing the ray's origin
  Frame frame;                // shading frame (n = shading normal, facing like ng; t from the tangent source)
  // The surface's (u, v); 0 where SceneGeometry::HitUV::WhereRead skipped them.
  Vec2 uv{0.0f};
  int object = -1;  // index into Scene::objects, or -1
  int light = -1;   // index into Scene::lights (a sphere light), or -1
};

class SceneGeometry {
 public:
  explicit SceneGeometry(const Scene& scene);
  ~SceneGeometry();
  SceneGeometry(const SceneGeometry&) = delete;
  SceneGeometry& operator=(const SceneGeometry&) = delete;

  // Which (u, v) a hit carries: every hit's (Always), or only those its shading reads (an object
  // with a tangent map; a mesh's, which also give its dp/du) and 0 elsewhere (WhereRead: saves the
  // sphere's atan2 and acos per hit; the path tracer's choice, as nothing else in it reads them).
  enum class HitUV { Always, WhereRead };
  // Closest hit with t in (0, tmax); fills *hit (shading data included) and returns true.
  bool intersect(const Ray& ray, float tmax, SurfaceHit* hit, HitUV uv = HitUV::Always) const;
  // Anything in (0, tmax)?
  bool occluded(const Ray& ray, float tmax) const;
  // The closest hit's distance (INFINITY for none), without the shading: the BVH traversal alone,
  // as the benchmark measures Embree's own ray rate.
  float closest_distance(const Ray& ray, float tmax) const;
  // Radius of the sphere around the bounding box of everything in the BVH (sphere lights included).
  float bounding_radius() const;
  // Ray origin for leaving p towards d without hitting the surface it sits on: offset along the
  // geometric normal by a few float ulps of the coordinates' magnitude.
  // Inline: every shadow ray and every bounce takes one.
  static Vec3 offset_origin(const Vec3& p, const Vec3& ng, const Vec3& d) {
    // Embree intersects in float: a hit point is off the true surface by a few ulps of its largest
    // coordinate. 1e-4 relative (plus 1e-4 absolute near the origin) clears that with a wide margin
    // while staying far below the size of any feature in a scene of unit-sized objects.
    const float scale = 1e-4f * (1.0f + std::max(std::fabs(p.x), std::max(std::fabs(p.y), std::fabs(p.z))));
    return p + (glm::dot(d, ng) >= 0.0f ? scale : -scale) * ng;
  }
  // The unit normal of a triangle with edges e1, e2 (right-handed, e1 x e2); +y for a degenerate
  // one. Finite for any finite edges (no overflow of the cross product).
  static Vec3 triangle_normal(const Vec3& e1, const Vec3& e2);

  // Shading data at a point of an object (the part of intersect() after the BVH), exposed for tests.
  void shade(int object, int prim, float bu, float bv, const Ray& ray, float t, SurfaceHit* hit, HitUV uv = HitUV::Always) const;

 private:
  struct Impl;
  const Scene& scene_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aniso::render
