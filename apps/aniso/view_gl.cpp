// apps/aniso/view_gl.cpp: the explorer's offscreen targets, display pass and lobe mesh (view_gl.h).
#include "view_gl.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "aniso/gl/glsl_library.h"
#include "gl/gl_shader.h"

namespace aniso::viewgl {

namespace {

unsigned link(const char* vs, const char* fs) { return gl::vertex_fragment_program(vs, fs, "explorer shader"); }

// A full-screen triangle from gl_VertexID (no vertex buffer).
constexpr const char* kFullScreenVS = R"(#version 330 core
out vec2 uv;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  uv = p;
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

// The display pass: the one tone map, ToneMap_apply of aniso/image/tonemap.glsl (the twin of
// render::tonemap, ToneMap::Aces: exposure, Narkowicz 2015's fit with its cap, NaN and negative
// radiance black, the sRGB OETF), which comes before this in the program. The window's
// framebuffer is not sRGB: the shader encodes.
constexpr const char* kDisplayFS = R"(
in vec2 uv;
out vec4 color;
uniform sampler2D radiance_a;
uniform sampler2D radiance_b;
uniform int difference;
uniform float exposure;
uniform float gain;
uniform vec3 background;
void main() {
  vec4 a = texture(radiance_a, uv);
  vec3 c = a.rgb;
  float coverage = a.a;
  if (difference != 0) {
    vec4 b = texture(radiance_b, uv);
    c = abs(a.rgb - b.rgb) * gain;
    coverage = max(a.a, b.a);
  }
  vec3 mapped = ToneMap_apply(c, exposure, true);
  color = vec4(mix(background, mapped, clamp(coverage, 0.0, 1.0)), 1.0);
}
)";

constexpr const char* kLobeVS = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in float value;
uniform mat4 mvp;
out float v_value;
out vec3 v_position;
void main() {
  v_value = value;
  v_position = position;
  gl_Position = mvp * vec4(position, 1.0);
}
)";

// Colour by the lobe's radius (dark blue at the centre to yellow at the maximum); a negative value
// marks the axis lines, coloured by their index.
constexpr const char* kLobeFS = R"(#version 330 core
in float v_value;
in vec3 v_position;
out vec4 color;
void main() {
  if (v_value < -2.5) { color = vec4(1.0, 0.85, 0.2, 1.0); return; }      // light
  if (v_value < -1.5) { color = vec4(0.9, 0.3, 0.3, 1.0); return; }       // tangent
  if (v_value < -0.5) { color = vec4(0.4, 0.7, 1.0, 1.0); return; }       // normal
  // The surface's facet normal from screen-space derivatives, for a little shading of its shape
  // (two-sided: abs), 40 % ambient.
  vec3 n = normalize(cross(dFdx(v_position), dFdy(v_position)));
  float shade = 0.4 + 0.6 * abs(dot(n, normalize(vec3(0.3, -0.4, 0.85))));
  color = vec4(shade * mix(vec3(0.15, 0.2, 0.55), vec3(1.0, 0.9, 0.35), clamp(v_value, 0.0, 1.0)), 1.0);
}
)";

}  // namespace

RenderTarget::~RenderTarget() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (tex_) glDeleteTextures(1, &tex_);
  if (depth_) glDeleteRenderbuffers(1, &depth_);
}

void RenderTarget::resize(int width, int height) {
  width = std::max(width, 1), height = std::max(height, 1);
  if (width == w_ && height == h_ && fbo_) return;
  if (!fbo_) {
    glGenFramebuffers(1, &fbo_);
    glGenTextures(1, &tex_);
    glGenRenderbuffers(1, &depth_);
  }
  w_ = width, h_ = height;
  glBindTexture(GL_TEXTURE_2D, tex_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w_, h_, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w_, h_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex_, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error(fmt::format("explorer: a {}x{} offscreen target is incomplete", w_, h_));
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void RenderTarget::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, w_, h_);
}

DisplayPass::DisplayPass() {
  const std::string fs = gl::glsl_preamble(gl::GlslDialect::Core330) + std::string(gl::glsl_tonemap_source()) + kDisplayFS;
  program_ = link(kFullScreenVS, fs.c_str());
  glGenVertexArrays(1, &vao_);
}

DisplayPass::~DisplayPass() {
  glDeleteProgram(program_);
  glDeleteVertexArrays(1, &vao_);
}

void DisplayPass::draw(unsigned radiance_a, unsigned radiance_b, bool difference, float exposure_stops, float gain,
                       const glm::vec3& background) const {
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glUseProgram(program_);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, radiance_a);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, radiance_b ? radiance_b : radiance_a);
  glUniform1i(glGetUniformLocation(program_, "radiance_a"), 0);
  glUniform1i(glGetUniformLocation(program_, "radiance_b"), 1);
  glUniform1i(glGetUniformLocation(program_, "difference"), difference ? 1 : 0);
  glUniform1f(glGetUniformLocation(program_, "exposure"), std::exp2(exposure_stops));
  glUniform1f(glGetUniformLocation(program_, "gain"), gain);
  glUniform3f(glGetUniformLocation(program_, "background"), background.x, background.y, background.z);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glActiveTexture(GL_TEXTURE0);
}

LobeRenderer::LobeRenderer() {
  program_ = link(kLobeVS, kLobeFS);
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &vbo_);
  glGenBuffers(1, &ibo_);
  glGenVertexArrays(1, &line_vao_);
  glGenBuffers(1, &line_vbo_);
}

LobeRenderer::~LobeRenderer() {
  glDeleteProgram(program_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteVertexArrays(1, &line_vao_);
  glDeleteBuffers(1, &vbo_);
  glDeleteBuffers(1, &ibo_);
  glDeleteBuffers(1, &line_vbo_);
}

void LobeRenderer::upload(const view::LobeMesh& mesh, const glm::vec3& wi_local) {
  // Interleaved x y z value.
  std::vector<float> v;
  v.reserve(mesh.values.size() * 4);
  for (size_t i = 0; i < mesh.values.size(); ++i)
    v.insert(v.end(), {mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2], mesh.values[i]});
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(v.size() * sizeof(float)), v.data(), GL_DYNAMIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.indices.size() * sizeof(uint32_t)), mesh.indices.data(), GL_DYNAMIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, 4 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
  index_count_ = int(mesh.indices.size());
  // Axes: the normal (value -1), the tangent (-2), the light direction (-3), from the origin.
  const float lines[] = {0,
                         0,
                         0,
                         -1,
                         0,
                         0,
                         1.2f,
                         -1,
                         0,
                         0,
                         0,
                         -2,
                         1.2f,
                         0,
                         0,
                         -2,
                         0,
                         0,
                         0,
                         -3,
                         1.3f * wi_local.x,
                         1.3f * wi_local.y,
                         1.3f * wi_local.z,
                         -3};
  glBindVertexArray(line_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
  glBufferData(GL_ARRAY_BUFFER, sizeof lines, lines, GL_DYNAMIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, 4 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
  glBindVertexArray(0);
}

void LobeRenderer::draw(int width, int height, float yaw_deg, float pitch_deg) const {
  glClearColor(0.12f, 0.12f, 0.13f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  // The local frame has z along the normal; the plot shows the normal up (world y), the tangent x
  // to the right: world = (x, z, -y).
  const glm::mat4 to_world(glm::vec4(1, 0, 0, 0), glm::vec4(0, 0, -1, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 0, 1));
  const float yaw = glm::radians(yaw_deg), pitch = glm::radians(pitch_deg);
  const glm::vec3 eye = 4.6f * glm::vec3(std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch));
  const glm::mat4 view = glm::lookAt(eye + glm::vec3(0, 0.35f, 0), glm::vec3(0, 0.35f, 0), glm::vec3(0, 1, 0));
  const glm::mat4 proj = glm::perspective(glm::radians(35.0f), float(width) / float(std::max(height, 1)), 0.1f, 20.0f);
  const glm::mat4 mvp = proj * view * to_world;
  glUseProgram(program_);
  glUniformMatrix4fv(glGetUniformLocation(program_, "mvp"), 1, GL_FALSE, glm::value_ptr(mvp));
  glBindVertexArray(vao_);
  glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(line_vao_);
  glDrawArrays(GL_LINES, 0, 6);
  glBindVertexArray(0);
  glDisable(GL_DEPTH_TEST);
}

ImageTexture::~ImageTexture() {
  if (tex_) glDeleteTextures(1, &tex_);
}

void ImageTexture::upload(const render::DisplayImage& img) {
  if (!tex_) glGenTextures(1, &tex_);
  glBindTexture(GL_TEXTURE_2D, tex_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, img.width, img.height, 0, GL_RGB, GL_UNSIGNED_BYTE, img.rgb.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  w_ = img.width, h_ = img.height;
}

render::DisplayImage read_window(int width, int height) {
  render::DisplayImage img(width, height);
  std::vector<uint8_t> rows(size_t(width) * size_t(height) * 3);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
  // GL's row 0 is the bottom; images have row 0 at the top.
  const size_t stride = size_t(width) * 3;
  for (int y = 0; y < height; ++y)
    std::copy_n(rows.data() + size_t(height - 1 - y) * stride, stride, img.rgb.data() + size_t(y) * stride);
  return img;
}

}  // namespace aniso::viewgl
