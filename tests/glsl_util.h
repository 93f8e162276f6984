// tests/glsl_util.h: what the GLSL tests share: glslangValidator, the GL context (or a skip with
// its reason), and a compute kernel that evaluates a material on a list of direction pairs.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "aniso/core/sampling.h"
#include "aniso/gl/gl_context.h"
#include "aniso/gl/glsl_library.h"
#include "aniso/gl/glsl_material.h"
#include "stats/rng.h"

namespace aniso::test {

// Runs glslangValidator on `source` as a shader of the given stage ("frag", "comp"); returns ""
// when it compiles, else the log.
inline std::string glslang_errors(const std::string& source, const std::string& stage, const std::string& tag) {
  const std::string path = fmt::format("{}/aniso_glsl_{}_{}.{}", ::testing::TempDir(), tag, getpid(), stage);
  {
    std::ofstream out(path);
    out << source;
  }
  const std::string cmd = fmt::format("{} {} 2>&1", ANISO_GLSLANG, path);
  std::string log;
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  while (p && fgets(buf, sizeof buf, p)) log += buf;
  const int rc = p ? pclose(p) : -1;
  std::remove(path.c_str());
  return rc == 0 ? "" : (log.empty() ? "glslangValidator failed" : log);
}

#define ANISO_REQUIRE_GLSLANG()                 \
  if (std::string(ANISO_GLSLANG).empty())       \
  GTEST_SKIP() << "glslangValidator not found " \
                  "(Debian package glslang-tools)"

// The GL context, or a skip naming why there is none.
#define ANISO_REQUIRE_GL()                                     \
  try {                                                        \
    aniso::gl::GlContext::get();                               \
  } catch (const aniso::gl::GlUnavailable& e) {                \
    GTEST_SKIP() << "no OpenGL 4.5 through EGL: " << e.what(); \
  }

struct GpuResult {
  glm::vec3 f;
  float pdf;
  glm::vec3 sample_wi;
  bool sample_valid;
  glm::vec3 sample_weight;
  float sample_pdf;
};

// Evaluates `body` (GLSL statements over wi, wo, u that set f, pdf and s, a BSDFSample) for every
// (wi, wo, u) in a compute shader: the library, `material_glsl` and the body.
inline std::vector<GpuResult> run_pairs(const std::string& material_glsl, const std::string& body,
                                        const std::vector<glm::vec3>& wi, const std::vector<glm::vec3>& wo,
                                        const std::vector<glm::vec3>& u,
                                        const std::function<void(const gl::ComputeProgram&)>& set = {}) {
  const std::string src = gl::glsl_preamble(gl::GlslDialect::Core450Compute) + "layout(local_size_x = 64) in;\n" +
                          gl::glsl_library_source() + material_glsl +
                          "layout(std430, binding = 0) readonly buffer In { vec4 inp[]; };\n"
                          "layout(std430, binding = 1) writeonly buffer Out { vec4 outp[]; };\n"
                          "uniform int count;\n"
                          "void main() {\n"
                          "  int i = int(gl_GlobalInvocationID.x);\n"
                          "  if (i >= count) return;\n"
                          "  vec3 wi = inp[3 * i].xyz, wo = inp[3 * i + 1].xyz, u = inp[3 * i + 2].xyz;\n"
                          "  vec3 f = vec3(0.0); float pdf = 0.0; BSDFSample s = BSDFSample_none();\n" +
                          body +
                          "  outp[3 * i] = vec4(f, pdf);\n"
                          "  outp[3 * i + 1] = vec4(s.wi, s.valid ? 1.0 : 0.0);\n"
                          "  outp[3 * i + 2] = vec4(s.weight, s.pdf);\n"
                          "}\n";
  gl::ComputeProgram prog(src);
  if (set) set(prog);
  const size_t n = wi.size();
  std::vector<glm::vec4> in(3 * n);
  for (size_t i = 0; i < n; ++i) {
    in[3 * i] = glm::vec4(wi[i], 0.f);
    in[3 * i + 1] = glm::vec4(wo[i], 0.f);
    in[3 * i + 2] = glm::vec4(u[i], 0.f);
  }
  gl::StorageBuffer bin(0, in.size() * sizeof(glm::vec4), in.data());
  gl::StorageBuffer bout(1, in.size() * sizeof(glm::vec4));
  prog.set("count", int(n));
  prog.dispatch(unsigned((n + 63) / 64));
  std::vector<glm::vec4> out(3 * n);
  bout.read(out.data(), out.size() * sizeof(glm::vec4));
  std::vector<GpuResult> r(n);
  for (size_t i = 0; i < n; ++i) {
    r[i].f = glm::vec3(out[3 * i]);
    r[i].pdf = out[3 * i].w;
    r[i].sample_wi = glm::vec3(out[3 * i + 1]);
    r[i].sample_valid = out[3 * i + 1].w != 0.f;
    r[i].sample_weight = glm::vec3(out[3 * i + 2]);
    r[i].sample_pdf = out[3 * i + 2].w;
  }
  return r;
}

// Direction pairs for the parity tests, each with a u triple and what kind of pair it is.
struct Grid {
  std::vector<glm::vec3> wi, wo, u;
  std::vector<std::string> kind;

  // (a, b) normalised, and u's three floats drawn from rng.
  void add(glm::vec3 a, glm::vec3 b, const char* k, Rng& rng) {
    wi.push_back(glm::normalize(a));
    wo.push_back(glm::normalize(b));
    u.push_back(glm::vec3(float(rng.uniform()), float(rng.uniform()), float(rng.uniform())));
    kind.push_back(k);
  }
};

// Pair i, for a failure message.
inline std::string describe(const Grid& g, size_t i) {
  return fmt::format("{} pair #{}: wi = ({:.7g}, {:.7g}, {:.7g}), wo = ({:.7g}, {:.7g}, {:.7g}), u = ({:.7g}, {:.7g}, {:.7g})",
                     g.kind[i], i, g.wi[i].x, g.wi[i].y, g.wi[i].z, g.wo[i].x, g.wo[i].y, g.wo[i].z, g.u[i].x, g.u[i].y,
                     g.u[i].z);
}

inline glm::vec3 unit(double theta, double phi) {
  return glm::vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

// The GLSL sampler's draws at one view, for the chi-square tests: Material_sample(aniso_material(),
// wo, u.x, u.yz) of `material_glsl` (whose aniso_material() `set` makes ready) for n triples
// u = (uc, u0, u1) from Rng(seed), drawn in the order chi2_test draws its own from the same seed.
struct GlslDraws {
  std::vector<glm::vec3> u;
  std::vector<GpuResult> r;
  size_t next = 0;  // how many of r sample() has handed out

  // chi2_test's sampler: the GPU's draws in order (the (uc, u) it passes are the same numbers).
  BSDFSampleT<float> sample() {
    const GpuResult& g = r.at(next++);
    BSDFSampleT<float> s;
    s.valid = g.sample_valid;
    s.wi = g.sample_wi;
    s.pdf = g.sample_pdf;
    return s;
  }
};

inline GlslDraws glsl_draws(const std::string& material_glsl, const glm::vec3& wo, int64_t n, uint64_t seed,
                            const std::function<void(const gl::ComputeProgram&)>& set) {
  GlslDraws d;
  d.u.resize(size_t(n));
  Rng rng(seed);
  for (auto& u : d.u) {
    u.x = rng.uniform_as<float>();
    u.y = rng.uniform_as<float>();
    u.z = rng.uniform_as<float>();
  }
  const std::vector<glm::vec3> wi(size_t(n), glm::vec3(0, 0, 1)), wos(size_t(n), wo);
  d.r = run_pairs(material_glsl, "  s = Material_sample(aniso_material(), wo, u.x, u.yz);\n", wi, wos, d.u, set);
  return d;
}

// The GLSL parity bound: within 1e-4 relative, or 1e-6 absolute where the value is tiny.
inline bool close(double gpu, double cpu, double rel = 1e-4, double abs_tol = 1e-6) {
  if (!std::isfinite(gpu) || !std::isfinite(cpu)) return false;
  const double d = std::abs(gpu - cpu);
  return d <= abs_tol || d <= rel * std::abs(cpu);
}

}  // namespace aniso::test
