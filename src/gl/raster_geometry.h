// gl/raster_geometry.h: the triangles the GL backend rasterises for an object (private to src/gl):
// for the analytic shapes a slightly larger convex proxy whose fragments intersect the exact shape
// (shaders/raster.frag.glsl), for a mesh its triangles with their shading attributes.
#pragma once

#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "aniso/core/math.h"
#include "aniso/render/scene.h"

namespace aniso::gl {

// The proxies of analytic shapes are this much larger than the shape, so that coverage is decided
// by the fragment's exact ray test alone and never by the rasteriser's edge rule at the rim.
constexpr float kProxyGrowth = 1.02f;

// One vertex of the vertex buffer (the attributes of shaders/raster.vert.glsl, in order).
struct Vertex {
  glm::vec3 p{0.0f}, n{0.0f};
  glm::vec2 uv{0.0f};
  glm::vec3 dpdu{0.0f}, ng{0.0f};
};

// Triangles that cover the object's projection: a proxy for the analytic shapes (a cube about the
// sphere, its faces counter-clockwise seen from outside; a square about the disc; the rectangle
// grown), the triangles themselves for a mesh, with their normals, UVs, dp/du and face normal.
std::vector<Vertex> object_vertices(const render::Object& o);

// Centre and radius of a sphere around the triangles (for the far plane and the shadow maps).
std::pair<Vec3, float> bounding_sphere(const std::vector<Vertex>& vs);

}  // namespace aniso::gl
