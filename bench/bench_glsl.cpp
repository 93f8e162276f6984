// aniso_bench_glsl: GLSL evaluation throughput through the headless GL host (src/gl): a compute
// shader evaluates aniso_f (the material's parameters as uniforms, as a renderer sets them) over
// 1M direction pairs held in a storage buffer; wall clock from the dispatch to glFinish, best of
// `--repeats` runs. Prints one markdown row per model: evaluations per second. docs/glsl.md.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>

// stb_image_write (Debian's libstb-dev) trips -Wextra's missing-initializer warning.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#pragma GCC diagnostic pop

#include "aniso/gl/gl_context.h"
#include "aniso/gl/glsl_export.h"
#include "aniso/gl/glsl_library.h"
#include "aniso/gl/glsl_material.h"
#include "aniso/io/materials.h"
#include "gl/scene_raster.h"
#include "stats/rng.h"

using namespace aniso;

namespace {

// `--spheres out.png m1 m2 ...`: each material's `aniso export-glsl` source, used unchanged in a
// compute shader that lights a sphere the way BRDF Explorer's lit-sphere view does (orthographic
// view along +z, tangent = normalize(cross(y, n)), one directional light, f cos theta_i), side by
// side, exposure 1, sRGB-encoded: the picture in docs/glsl.md.
int render_spheres(const std::string& out_path, const std::vector<std::string>& materials) {
  constexpr int kSize = 256;
  const int w = kSize * int(materials.size()), h = kSize;
  std::vector<unsigned char> rgb(size_t(w) * h * 3, 0);
  gl::StorageBuffer buf(1, size_t(kSize) * kSize * sizeof(glm::vec4));
  for (size_t k = 0; k < materials.size(); ++k) {
    const MaterialDesc d = load_material(materials[k]);
    (void)build_material<double>(d);
    const std::string src =
        gl::glsl_preamble(gl::GlslDialect::Core450Compute) + "layout(local_size_x = 64) in;\n" +
        gl::export_glsl(d, materials[k]) +
        "layout(std430, binding = 1) writeonly buffer Out { vec4 outp[]; };\n"
        "const int kSize = " +
        std::to_string(kSize) +
        ";\n"
        "void main() {\n"
        "  int i = int(gl_GlobalInvocationID.x);\n  if (i >= kSize * kSize) return;\n"
        "  vec2 p = (vec2(i % kSize, i / kSize) + 0.5) / float(kSize) * 2.0 - 1.0;\n"
        "  p.y = -p.y;\n  float r2 = dot(p, p);\n"
        "  if (r2 >= 1.0) { outp[i] = vec4(0.02, 0.02, 0.025, 0.0); return; }\n"
        "  vec3 N = vec3(p, sqrt(1.0 - r2));\n"
        "  vec3 X = normalize(cross(vec3(0.0, 1.0, 0.0), N));\n  vec3 Y = cross(N, X);\n"
        "  vec3 V = vec3(0.0, 0.0, 1.0);\n  vec3 L = normalize(vec3(-0.5, 0.55, 0.65));\n"
        "  float c = max(dot(N, L), 0.0);\n"
        "  outp[i] = vec4(aniso_f_world(L, V, N, X, Y) * c * 2.5 + 0.03 * aniso_f_world(N, V, N, X, Y), 1.0);\n"
        "}\n";
    gl::ComputeProgram prog(src);
    prog.dispatch(unsigned(kSize * kSize / 64));
    std::vector<glm::vec4> px(size_t(kSize) * kSize);
    buf.read(px.data(), px.size() * sizeof(glm::vec4));
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x)
        for (int c = 0; c < 3; ++c) {
          const float v = std::clamp(px[size_t(y) * kSize + x][c], 0.f, 1.f);
          const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
          rgb[(size_t(y) * w + size_t(k) * kSize + x) * 3 + c] = (unsigned char)std::lround(255.f * s);
        }
  }
  if (!stbi_write_png(out_path.c_str(), w, h, 3, rgb.data(), w * 3)) {
    fmt::print(stderr, "cannot write {}\n", out_path);
    return 1;
  }
  fmt::print("wrote {} ({}x{})\n", out_path, w, h);
  return 0;
}

}  // namespace

// --scene FILE [--width W --height H --subsamples K]: the GL backend of the renderer
// (gl/scene_raster.h): setup (upload, program compilation) once, then the best of `repeats` frames
// of render() + glFinish (wall time: GL timer queries do not measure llvmpipe's work), the first
// frame (which also draws the mesh shadow maps) apart.
int bench_scene(const std::string& file, int width, int height, int k, int repeats) {
  render::Scene scene = render::load_scene(file);
  if (width > 0) scene.film.width = width;
  if (height > 0) scene.film.height = height;
  using clock = std::chrono::steady_clock;
  const auto seconds = [](clock::time_point a) { return std::chrono::duration<double>(clock::now() - a).count(); };
  auto t0 = clock::now();
  gl::SceneRasterizer raster(scene, gl::RasterSettings{k});
  gl::GlContext::get().finish();
  const double setup = seconds(t0);
  t0 = clock::now();
  raster.render();
  gl::GlContext::get().finish();
  const double first = seconds(t0);
  double best = 1e30;
  for (int r = 0; r < repeats; ++r) {
    t0 = clock::now();
    raster.render();
    gl::GlContext::get().finish();
    best = std::min(best, seconds(t0));
  }
  fmt::print(
      "{}: {}x{}, {} objects, {} lights, {} x {} sub-samples: setup {:.3f} s ({} programs), first frame {:.3f} s, "
      "frame {:.3f} s (best of {}), {:.3f} s per sub-sample pass, {:.1f} M pixel-samples/s\n",
      file, scene.film.width, scene.film.height, scene.objects.size(), scene.lights.size(), k, k, setup, raster.program_count(),
      first, best, repeats, best / (k * k), double(scene.film.width) * scene.film.height * k * k / best * 1e-6);
  return 0;
}

int main(int argc, char** argv) {
  int pairs = 1 << 20, repeats = 5;
  for (int i = 1; i + 1 < argc; ++i) {
    if (!std::strcmp(argv[i], "--pairs"))
      pairs = std::max(64, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--repeats"))
      repeats = std::max(1, std::atoi(argv[++i]));
  }
  std::string spheres;
  std::vector<std::string> sphere_materials;
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--spheres") && i + 1 < argc) {
      spheres = argv[i + 1];
      for (int j = i + 2; j < argc; ++j) sphere_materials.push_back(argv[j]);
      break;
    }
  try {
    gl::GlContext& ctx = gl::GlContext::get();
    fmt::print("GL: {} | {} | {}\n", ctx.renderer(), ctx.version(), ctx.platform());
  } catch (const gl::GlUnavailable& e) {
    fmt::print(stderr, "aniso_bench_glsl: no OpenGL 4.5: {}\n", e.what());
    return 2;
  }
  if (!spheres.empty()) return render_spheres(spheres, sphere_materials);
  for (int i = 1; i + 1 < argc; ++i)
    if (!std::strcmp(argv[i], "--scene")) {
      int width = 0, height = 0, k = 1;
      for (int j = 1; j + 1 < argc; ++j) {
        if (!std::strcmp(argv[j], "--width")) width = std::atoi(argv[j + 1]);
        if (!std::strcmp(argv[j], "--height")) height = std::atoi(argv[j + 1]);
        if (!std::strcmp(argv[j], "--subsamples")) k = std::clamp(std::atoi(argv[j + 1]), 1, 16);
      }
      try {
        return bench_scene(argv[i + 1], width, height, k, repeats);
      } catch (const std::exception& e) {
        fmt::print(stderr, "aniso_bench_glsl: {}\n", e.what());
        return 2;
      }
    }
  // Random pairs on the upper hemisphere (uniform), the same for every model.
  std::vector<glm::vec4> in(2 * size_t(pairs));
  Rng rng(1);
  auto upper = [&] {
    const double z = 1.0 - rng.uniform(), r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * M_PI * rng.uniform();
    return glm::vec4(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z), 0.f);
  };
  for (auto& v : in) v = upper();
  gl::StorageBuffer bin(0, in.size() * sizeof(glm::vec4), in.data());
  gl::StorageBuffer bout(1, size_t(pairs) * sizeof(glm::vec4));

  const struct {
    const char* name;
    const char* json;
  } models[] = {
      {"lambert", R"({"model": "lambert"})"},
      {"phong (normalised)", R"({"model": "phong", "kd": 0.2, "exponent": 30})"},
      {"ward vector (1992)", R"({"model": "ward", "kd": 0.1, "alpha_x": 0.08, "alpha_y": 0.3})"},
      {"ward angle (1992)", R"({"model": "ward", "kd": 0.1, "alpha_x": 0.08, "alpha_y": 0.3, "form": "angle"})"},
      {"ward approx (balanced)",
       R"({"model": "ward", "kd": 0.1, "alpha_x": 0.08, "alpha_y": 0.3, "form": "approx", "normalization": "balanced"})"},
      {"ashikhmin-shirley", R"({"model": "ashikhmin-shirley", "n_u": 10, "n_v": 500})"},
      {"lafortune (3 lobes, matte-steel)", "matte-steel"},
      {"ggx", R"({"model": "ggx", "kd": 0.2, "alpha_x": 0.05, "alpha_y": 0.4})"},
      {"metal (gold, GGX)", "gold"},
      {"metal (brushed gold: Ward + dir. diffuse)", "brushed-gold"},
  };
  fmt::print("\n| model | M evals/s | ms per {} pairs |\n|---|---:|---:|\n", pairs);
  for (const auto& m : models) {
    const MaterialDesc d = m.json[0] == '{' ? parse_material(nlohmann::json::parse(m.json), m.name) : load_material(m.json);
    const gl::GlslMaterial g = gl::glsl_material(d, gl::GlslStorage::Uniform, "u_");
    const std::string src = gl::glsl_preamble(gl::GlslDialect::Core450Compute) + "layout(local_size_x = 64) in;\n" +
                            gl::glsl_library_source() + g.declarations + g.code +
                            "layout(std430, binding = 0) readonly buffer In { vec4 inp[]; };\n"
                            "layout(std430, binding = 1) writeonly buffer Out { vec4 outp[]; };\n"
                            "uniform int count;\n"
                            "void main() {\n  int i = int(gl_GlobalInvocationID.x);\n  if (i >= count) return;\n"
                            "  outp[i] = vec4(aniso_f(inp[2 * i].xyz, inp[2 * i + 1].xyz), 0.0);\n}\n";
    gl::ComputeProgram prog(src);
    gl::set_uniforms(prog, g, "u_");
    prog.set("count", pairs);
    const unsigned groups = unsigned((pairs + 63) / 64);
    prog.dispatch(groups);  // warm-up: the driver finishes compiling on first use
    gl::GlContext::get().finish();
    double best = 1e30;
    for (int r = 0; r < repeats; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      prog.dispatch(groups);
      gl::GlContext::get().finish();
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::vector<glm::vec4> out(4);
    bout.read(out.data(), out.size() * sizeof(glm::vec4));
    fmt::print("| {} | {:.1f} | {:.2f} |\n", m.name, pairs / best * 1e-6, best * 1e3);
  }
  return 0;
}
