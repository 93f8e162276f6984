// gl/raster_geometry.cpp: see raster_geometry.h.
#include "gl/raster_geometry.h"

#include <cmath>

#include "aniso/core/sampling.h"
#include "aniso/render/geometry.h"

namespace aniso::gl {
namespace {

using render::ShapeKind;

void push_quad(std::vector<Vertex>& out, const Vec3& c, const Vec3& a, const Vec3& b) {
  const Vec3 q[4] = {c - a - b, c + a - b, c + a + b, c - a + b};
  for (int i : {0, 1, 2, 0, 2, 3}) {
    Vertex v;
    v.p = q[i];
    out.push_back(v);
  }
}

}  // namespace

// Triangles that cover the object's projection: a proxy for the analytic shapes (the fragment
// intersects the exact shape), the triangles themselves for a mesh, with their shading attributes.
std::vector<Vertex> object_vertices(const render::Object& o) {
  std::vector<Vertex> out;
  switch (o.shape) {
    case ShapeKind::Sphere: {
      const float h = o.radius * kProxyGrowth;
      const Vec3 x(h, 0, 0), y(0, h, 0), z(0, 0, h);
      // Each face counter-clockwise seen from outside (a x b points out), so that back faces can be
      // culled when the camera is outside the cube (draw_pass).
      push_quad(out, o.center + x, y, z);
      push_quad(out, o.center - x, z, y);
      push_quad(out, o.center + y, z, x);
      push_quad(out, o.center - y, x, z);
      push_quad(out, o.center + z, x, y);
      push_quad(out, o.center - z, y, x);
      break;
    }
    case ShapeKind::Disc: {
      Vec3 a, b;
      orthonormal_basis(o.normal, a, b);
      push_quad(out, o.center, a * (o.radius * kProxyGrowth), b * (o.radius * kProxyGrowth));
      break;
    }
    case ShapeKind::Rectangle: {
      const Vec3 b = glm::cross(o.normal, o.u_axis);
      push_quad(out, o.center, o.u_axis * (0.5f * o.size.x * kProxyGrowth), b * (0.5f * o.size.y * kProxyGrowth));
      break;
    }
    case ShapeKind::Mesh: {
      const render::Mesh& m = *o.mesh;
      out.reserve(m.indices.size());
      for (size_t f = 0; f + 2 < m.indices.size(); f += 3) {
        const uint32_t i[3] = {m.indices[f], m.indices[f + 1], m.indices[f + 2]};
        // The triangle's normal and, without per-vertex tangents, its dp/du from the UVs: the
        // arithmetic of SceneGeometry::shade (render/geometry.cpp).
        const Vec3 e1 = m.positions[i[1]] - m.positions[i[0]], e2 = m.positions[i[2]] - m.positions[i[0]];
        const Vec3 ng = render::SceneGeometry::triangle_normal(e1, e2);
        Vec3 face_dpdu(0.0f);
        if (m.tangents.empty() && !m.uvs.empty()) {
          const Vec2 d1 = m.uvs[i[1]] - m.uvs[i[0]], d2 = m.uvs[i[2]] - m.uvs[i[0]];
          const float det = d1.x * d2.y - d2.x * d1.y;
          if (std::fabs(det) > 0.0f) face_dpdu = (e1 * d2.y - e2 * d1.y) / det;
        }
        for (uint32_t k : i) {
          Vertex v;
          v.p = m.positions[k];
          if (!m.normals.empty()) v.n = m.normals[k];
          if (!m.uvs.empty()) v.uv = m.uvs[k];
          v.dpdu = m.tangents.empty() ? face_dpdu : m.tangents[k];
          v.ng = ng;
          out.push_back(v);
        }
      }
      break;
    }
  }
  return out;
}

// Centre and radius of a sphere around the object's triangles (for the far plane).
std::pair<Vec3, float> bounding_sphere(const std::vector<Vertex>& vs) {
  Vec3 lo(INFINITY), hi(-INFINITY);
  for (const Vertex& v : vs) lo = glm::min(lo, v.p), hi = glm::max(hi, v.p);
  if (vs.empty()) return {Vec3(0.0f), 0.0f};
  return {0.5f * (lo + hi), 0.5f * glm::length(hi - lo)};
}

}  // namespace aniso::gl
