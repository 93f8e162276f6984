// render/geometry.cpp: Embree 3 scene construction and hit shading.
#include "aniso/render/geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <embree3/rtcore.h>
#include <fmt/format.h>

namespace aniso::render {

struct SceneGeometry::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  unsigned num_objects = 0;
};

namespace {

void check_device(RTCDevice device, const char* what) {
  const RTCError e = rtcGetDeviceError(device);
  if (e != RTC_ERROR_NONE) throw std::runtime_error(fmt::format("Embree error {} while {}", int(e), what));
}

// The disc's u axis (docs/scenes.md): world x projected onto the disc, or world z when the normal
// is within ~2.6 degrees of x (|n.x| > 0.999), where the projection of x is too short to trust.
Vec3 disc_u_axis(const Vec3& n) {
  const Vec3 ref = std::fabs(n.x) > 0.999f ? Vec3(0, 0, 1) : Vec3(1, 0, 0);
  return glm::normalize(ref - glm::dot(ref, n) * n);
}

}  // namespace

SceneGeometry::SceneGeometry(const Scene& scene) : scene_(scene), impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw std::runtime_error("cannot create an Embree device");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  const auto attach = [&](RTCGeometry g, unsigned id) {
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(impl_->scene, g, id);
    rtcReleaseGeometry(g);
  };
  unsigned id = 0;
  for (const Object& o : scene.objects) {
    RTCGeometry g = nullptr;
    switch (o.shape) {
      case ShapeKind::Sphere: {
        g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v =
            static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
        v[0] = o.center.x, v[1] = o.center.y, v[2] = o.center.z, v[3] = o.radius;
        break;
      }
      case ShapeKind::Disc: {
        g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT);
        auto* v =
            static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
        v[0] = o.center.x, v[1] = o.center.y, v[2] = o.center.z, v[3] = o.radius;
        auto* n =
            static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 1));
        n[0] = o.normal.x, n[1] = o.normal.y, n[2] = o.normal.z;
        break;
      }
      case ShapeKind::Rectangle: {
        g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_QUAD);
        auto* v =
            static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4));
        const Vec3 u = o.u_axis * (0.5f * o.size.x), w = glm::cross(o.normal, o.u_axis) * (0.5f * o.size.y);
        const Vec3 corners[4] = {o.center - u - w, o.center + u - w, o.center + u + w, o.center - u + w};
        for (int i = 0; i < 4; ++i) v[3 * i] = corners[i].x, v[3 * i + 1] = corners[i].y, v[3 * i + 2] = corners[i].z;
        auto* idx = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), 1));
        idx[0] = 0, idx[1] = 1, idx[2] = 2, idx[3] = 3;
        break;
      }
      case ShapeKind::Mesh: {
        const Mesh& m = *o.mesh;
        g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.positions.size()));
        for (size_t i = 0; i < m.positions.size(); ++i)
          v[3 * i] = m.positions[i].x, v[3 * i + 1] = m.positions[i].y, v[3 * i + 2] = m.positions[i].z;
        auto* idx = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m.indices.size() / 3));
        for (size_t i = 0; i < m.indices.size(); ++i) idx[i] = m.indices[i];
        break;
      }
    }
    attach(g, id++);
  }
  impl_->num_objects = id;
  for (const Light& l : scene.lights) {
    if (l.kind == LightKind::Sphere) {
      RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
      auto* v =
          static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
      v[0] = l.position.x, v[1] = l.position.y, v[2] = l.position.z, v[3] = l.radius;
      attach(g, id);
    }
    ++id;  // geomID - num_objects is the light's index, sphere or not
  }
  check_device(impl_->device, "building the geometry");
  rtcCommitScene(impl_->scene);
  check_device(impl_->device, "building the BVH");
}

SceneGeometry::~SceneGeometry() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

Vec3 SceneGeometry::triangle_normal(const Vec3& e1, const Vec3& e2) {
  // Each edge scaled by its largest component first: |e1 x e2|^2 overflows float once the edges
  // are longer than about 4e9 (a triangle of size 1e11 had a zero normal and rendered black), and
  // the direction of the cross product does not depend on the scales.
  const float m1 = std::max({std::fabs(e1.x), std::fabs(e1.y), std::fabs(e1.z)});
  const float m2 = std::max({std::fabs(e2.x), std::fabs(e2.y), std::fabs(e2.z)});
  const Vec3 c = m1 > 0.0f && m2 > 0.0f ? glm::cross(e1 / m1, e2 / m2) : Vec3(0.0f);
  const float cl = glm::length(c);
  return cl > 0.0f ? c / cl : Vec3(0, 1, 0);
}

float SceneGeometry::bounding_radius() const {
  RTCBounds b;
  rtcGetSceneBounds(impl_->scene, &b);
  const Vec3 d(b.upper_x - b.lower_x, b.upper_y - b.lower_y, b.upper_z - b.lower_z);
  // An empty scene has lower > upper (Embree reports +inf / -inf): no extent.
  if (!(d.x >= 0.0f && d.y >= 0.0f && d.z >= 0.0f) || !std::isfinite(d.x + d.y + d.z)) return 0.0f;
  return 0.5f * glm::length(d);
}

// One Embree closest-hit query of ray over [0, tmax] (rtcIntersect1); geomID is
// RTC_INVALID_GEOMETRY_ID when nothing is hit, else tfar is the hit distance.
static RTCRayHit closest_hit(RTCScene scene, const Ray& ray, float tmax) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = ray.o.x, rh.ray.org_y = ray.o.y, rh.ray.org_z = ray.o.z;
  rh.ray.dir_x = ray.d.x, rh.ray.dir_y = ray.d.y, rh.ray.dir_z = ray.d.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = tmax;
  rh.ray.mask = ~0u;
  rh.ray.flags = 0;
  rh.ray.time = 0.0f;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &ctx, &rh);
  return rh;
}

float SceneGeometry::closest_distance(const Ray& ray, float tmax) const {
  const RTCRayHit rh = closest_hit(impl_->scene, ray, tmax);
  return rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? INFINITY : rh.ray.tfar;
}

bool SceneGeometry::intersect(const Ray& ray, float tmax, SurfaceHit* hit, HitUV uv) const {
  const RTCRayHit rh = closest_hit(impl_->scene, ray, tmax);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  const unsigned g = rh.hit.geomID;
  if (g >= impl_->num_objects) {
    const int li = int(g - impl_->num_objects);
    const Light& l = scene_.lights[size_t(li)];
    hit->t = rh.ray.tfar;
    hit->p = ray.o + rh.ray.tfar * ray.d;
    Vec3 n = glm::normalize(hit->p - l.position);
    hit->ng = glm::dot(n, ray.d) > 0.0f ? -n : n;
    hit->frame = Frame::from_normal(hit->ng);
    hit->object = -1;
    hit->light = li;
    return true;
  }
  shade(int(g), int(rh.hit.primID), rh.hit.u, rh.hit.v, ray, rh.ray.tfar, hit, uv);
  return true;
}

void SceneGeometry::shade(int object, int prim, float bu, float bv, const Ray& ray, float t, SurfaceHit* hit,
                          HitUV which_uv) const {
  const Object& o = scene_.objects[size_t(object)];
  // Only a tangent map reads the (u, v) of the shading below (tangent_frame does not): the sphere's
  // and the planar shapes' are computed where there is one or the caller asks; a mesh's are always
  // interpolated (they give its dp/du).
  const bool want_uv = which_uv == HitUV::Always || o.tangent.map;
  hit->t = t;
  hit->object = object;
  hit->light = -1;
  Vec3 p = ray.o + t * ray.d;
  Vec3 ng, ns, dpdu(0.0f);
  Vec2 uv(0.0f);
  switch (o.shape) {
    case ShapeKind::Sphere: {
      ng = glm::normalize(p - o.center);
      p = o.center + o.radius * ng;  // back onto the surface: float t puts p a few ulps off it
      ns = ng;
      dpdu = Vec3(ng.z, 0.0f, -ng.x);  // +y x n
      if (want_uv) {
        const float phi = std::atan2(ng.x, ng.z);
        uv = Vec2((phi < 0.0f ? phi + 2.0f * kPi<float> : phi) * kInv2Pi<float>,
                  1.0f - std::acos(glm::clamp(ng.y, -1.0f, 1.0f)) * kInvPi<float>);
      }
      break;
    }
    case ShapeKind::Disc: {
      ng = ns = o.normal;
      const Vec3 eu = disc_u_axis(o.normal), ev = glm::cross(o.normal, eu);
      const Vec3 d = p - o.center;
      dpdu = eu;
      if (want_uv) uv = Vec2(0.5f + glm::dot(d, eu) / (2.0f * o.radius), 0.5f + glm::dot(d, ev) / (2.0f * o.radius));
      break;
    }
    case ShapeKind::Rectangle: {
      ng = ns = o.normal;
      const Vec3 ev = glm::cross(o.normal, o.u_axis);
      const Vec3 d = p - o.center;
      dpdu = o.u_axis;
      if (want_uv) uv = Vec2(0.5f + glm::dot(d, o.u_axis) / o.size.x, 0.5f + glm::dot(d, ev) / o.size.y);
      break;
    }
    case ShapeKind::Mesh: {
      const Mesh& m = *o.mesh;
      const uint32_t i0 = m.indices[3 * size_t(prim)], i1 = m.indices[3 * size_t(prim) + 1], i2 = m.indices[3 * size_t(prim) + 2];
      const float b0 = 1.0f - bu - bv;
      const Vec3 e1 = m.positions[i1] - m.positions[i0], e2 = m.positions[i2] - m.positions[i0];
      p = b0 * m.positions[i0] + bu * m.positions[i1] + bv * m.positions[i2];
      ng = triangle_normal(e1, e2);
      ns = ng;
      if (!m.normals.empty()) {
        const Vec3 nn = b0 * m.normals[i0] + bu * m.normals[i1] + bv * m.normals[i2];
        const float nl = glm::length(nn);
        if (nl > 1e-12f) ns = nn / nl;
        if (glm::dot(ns, ng) < 0.0f) ng = -ng;  // the winding decides nothing: the vertex normals do
      }
      if (!m.uvs.empty()) uv = b0 * m.uvs[i0] + bu * m.uvs[i1] + bv * m.uvs[i2];
      if (!m.tangents.empty()) {
        dpdu = b0 * m.tangents[i0] + bu * m.tangents[i1] + bv * m.tangents[i2];
      } else if (!m.uvs.empty()) {
        const Vec2 d1 = m.uvs[i1] - m.uvs[i0], d2 = m.uvs[i2] - m.uvs[i0];
        const float det = d1.x * d2.y - d2.x * d1.y;
        if (std::fabs(det) > 0.0f) dpdu = (e1 * d2.y - e2 * d1.y) / det;
      }
      break;
    }
  }
  // Two-sided surfaces: the normals face the side the ray came from.
  if (glm::dot(ng, ray.d) > 0.0f) {
    ng = -ng;
    ns = -ns;
  }
  if (glm::dot(ns, ng) < 0.0f) ns = ng;  // a shading normal on the far side of the surface carries no meaning
  hit->p = p;
  hit->ng = ng;
  hit->uv = uv;

  SurfacePointT<float> sp;
  sp.p = p;
  sp.n = ns;
  sp.dpdu = dpdu;
  sp.uv = uv;
  if (o.tangent.map) {
    // The map's direction (a, b) is in the (t, b) frame of the natural tangent.
    const Frame natural = Frame::from_normal_tangent(ns, dpdu);
    const Vec2 d = o.tangent.map->lookup(uv);
    sp.dpdu = d.x * natural.t + d.y * natural.b;
    TangentFieldT<float> f = o.tangent.field;
    f.kind = TangentFieldKind::Natural;
    hit->frame = tangent_frame(f, sp);
  } else {
    hit->frame = tangent_frame(o.tangent.field, sp);
  }
}

bool SceneGeometry::occluded(const Ray& ray, float tmax) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  r.org_x = ray.o.x, r.org_y = ray.o.y, r.org_z = ray.o.z;
  r.dir_x = ray.d.x, r.dir_y = ray.d.y, r.dir_z = ray.d.z;
  r.tnear = 0.0f;
  r.tfar = tmax;
  r.mask = ~0u;
  r.flags = 0;
  r.time = 0.0f;
  rtcOccluded1(impl_->scene, &ctx, &r);
  return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

}  // namespace aniso::render
