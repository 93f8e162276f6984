// aniso/gl/gl_context.h: a small headless OpenGL host: an EGL context without a window (Mesa's
// surfaceless platform: llvmpipe on machines without a GPU; the EGL device platform for a
// vendor's driver), compute programs, and storage buffers. The parity tests, the GLSL benchmark
// and `aniso render --backend gl` (gl/scene_raster.h, which itself needs only a current GL 3.3
// core context: a window's works too) run GLSL through it.
//
// One context per process, current on the thread that created it (GL's rule). Errors are
// exceptions: GlUnavailable when no context can be made (tests skip with its message), GlError
// for everything else (a compile error carries the driver's log).
#pragma once

#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace aniso::gl {

class GlUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
class GlError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class GlContext {
 public:
  // The process's context (created on the first call, GL 4.5 core). Throws GlUnavailable with the
  // reason (no EGL display, no GL 4.5, ...).
  static GlContext& get();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  std::string renderer() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version() const;   // GL_VERSION
  std::string platform() const;  // which EGL platform gave the display
  void finish() const;           // glFinish

 private:
  GlContext();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A compiled and linked compute program. `source` is complete (with its #version line).
class ComputeProgram {
 public:
  explicit ComputeProgram(const std::string& source);
  ~ComputeProgram();
  ComputeProgram(const ComputeProgram&) = delete;
  ComputeProgram& operator=(const ComputeProgram&) = delete;

  unsigned id() const { return id_; }
  // Uniforms by name; a name the program does not use (optimised away) is ignored, as GL does.
  void set(const std::string& name, float v) const;
  void set(const std::string& name, int v) const;
  void set(const std::string& name, const glm::vec3& v) const;
  // Binds the uniform block `block` to uniform-buffer binding point `binding`.
  void bind_block(const std::string& block, unsigned binding) const;
  // The byte offsets GL assigned to the named block members (-1 where a name is not active).
  std::vector<int> member_offsets(const std::vector<std::string>& names) const;
  // Runs groups_x work groups (glDispatchCompute(groups_x, 1, 1)) and a storage barrier.
  void dispatch(unsigned groups_x) const;

 private:
  unsigned id_ = 0;
};

// A shader storage buffer bound at `binding`.
class StorageBuffer {
 public:
  StorageBuffer(unsigned binding, size_t bytes, const void* data = nullptr);
  ~StorageBuffer();
  StorageBuffer(const StorageBuffer&) = delete;
  StorageBuffer& operator=(const StorageBuffer&) = delete;
  void read(void* out, size_t bytes) const;

 private:
  unsigned id_ = 0;
};

// A uniform buffer bound at `binding` (glBindBufferBase(GL_UNIFORM_BUFFER, binding, ...)).
class UniformBuffer {
 public:
  UniformBuffer(unsigned binding, size_t bytes, const void* data);
  ~UniformBuffer();
  UniformBuffer(const UniformBuffer&) = delete;
  UniformBuffer& operator=(const UniformBuffer&) = delete;

 private:
  unsigned id_ = 0;
};

// The measured materials' tables (gl::glsl_tables(), docs/glsl.md "Measured materials") as the
// R32F texture the library's MeasuredTables_texture reads: kGlslTablesWidth texels wide, as many
// rows as the floats need. Made in the current context (any GL 3.3 core: GlContext::get()'s, a
// window's); bind() puts it on texture unit `unit`, whose number the program's sampler uniform
// MeasuredTables_texture must hold. GlError when it exceeds GL_MAX_TEXTURE_SIZE.
class TablesTexture {
 public:
  explicit TablesTexture(const std::vector<float>& tables);
  ~TablesTexture();
  TablesTexture(const TablesTexture&) = delete;
  TablesTexture& operator=(const TablesTexture&) = delete;
  void bind(unsigned unit) const;
  unsigned id() const { return id_; }

 private:
  unsigned id_ = 0;
};

}  // namespace aniso::gl
