// gl/gl_context.cpp: EGL without a window, through libepoxy (which resolves GL entry points with
// eglGetProcAddress, so it works with EGL contexts and no GLX).
#include "aniso/gl/gl_context.h"
#include "aniso/gl/glsl_material.h"
#include "gl/gl_shader.h"

#include <algorithm>

#include <cstdlib>
#include <cstring>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <fmt/format.h>

namespace aniso::gl {

struct GlContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  std::string platform;
};

namespace {

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

// Tries the EGL device platform first (a GPU's driver, no display server needed), then Mesa's
// surfaceless platform (llvmpipe on machines without a GPU). ANISO_GL_PLATFORM=surfaceless or
// =device forces one.
EGLDisplay open_display(std::string& platform, std::string& why) {
  const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!client_ext) {
    why = "EGL client extensions are unavailable (no EGL 1.5 / EGL_EXT_client_extensions)";
    return EGL_NO_DISPLAY;
  }
  const char* forced = std::getenv("ANISO_GL_PLATFORM");
  const std::string force = forced ? forced : "";
  if (!force.empty() && force != "device" && force != "surfaceless") {
    why = fmt::format("ANISO_GL_PLATFORM={}: no such EGL platform (expected device or surfaceless)", force);
    return EGL_NO_DISPLAY;
  }
  if ((force.empty() || force == "device") && has_extension(client_ext, "EGL_EXT_platform_device") &&
      has_extension(client_ext, "EGL_EXT_device_enumeration")) {
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (eglQueryDevicesEXT(16, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        const char* dev_ext = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
        // Mesa lists a software device too; prefer a device with a DRM render node (a real GPU).
        if (force.empty() && !has_extension(dev_ext, "EGL_EXT_device_drm_render_node") &&
            !has_extension(dev_ext, "EGL_EXT_device_drm"))
          continue;
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        EGLint major = 0, minor = 0;
        if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
          platform = fmt::format("EGL device {} ({})", i, eglQueryString(d, EGL_VENDOR));
          return d;
        }
      }
    }
  }
  if ((force.empty() || force == "surfaceless") && has_extension(client_ext, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
      platform = fmt::format("EGL surfaceless ({})", eglQueryString(d, EGL_VENDOR));
      return d;
    }
    why = fmt::format("eglInitialize on the surfaceless platform failed (EGL error 0x{:x})", eglGetError());
    return EGL_NO_DISPLAY;
  }
  why = "no EGL platform without a window system (EGL_EXT_platform_device or EGL_MESA_platform_surfaceless)";
  return EGL_NO_DISPLAY;
}

}  // namespace

GlContext::GlContext() : impl_(std::make_unique<Impl>()) {
  std::string why;
  impl_->display = open_display(impl_->platform, why);
  if (impl_->display == EGL_NO_DISPLAY) throw GlUnavailable(why);
  if (!eglBindAPI(EGL_OPENGL_API)) throw GlUnavailable("eglBindAPI(EGL_OPENGL_API) failed: no desktop OpenGL");
  const EGLint attrs[] = {
      EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 5, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  // No config and no surface: EGL_KHR_no_config_context and EGL_KHR_surfaceless_context.
  impl_->context = eglCreateContext(impl_->display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attrs);
  if (impl_->context == EGL_NO_CONTEXT)
    throw GlUnavailable(fmt::format("{}: no OpenGL 4.5 core context (EGL error 0x{:x})", impl_->platform, eglGetError()));
  if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
    throw GlUnavailable(fmt::format("{}: eglMakeCurrent failed (EGL error 0x{:x})", impl_->platform, eglGetError()));
  if (epoxy_gl_version() < 45) throw GlUnavailable(fmt::format("{}: OpenGL {} < 4.5", impl_->platform, epoxy_gl_version()));
}

GlContext::~GlContext() {
  if (impl_->display != EGL_NO_DISPLAY) {
    eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (impl_->context != EGL_NO_CONTEXT) eglDestroyContext(impl_->display, impl_->context);
    eglTerminate(impl_->display);
  }
}

GlContext& GlContext::get() {
  // A failed creation is remembered: every later call reports the same reason without retrying.
  static std::string failure;
  static std::unique_ptr<GlContext> ctx;
  if (ctx) return *ctx;
  if (!failure.empty()) throw GlUnavailable(failure);
  try {
    ctx.reset(new GlContext());
  } catch (const GlUnavailable& e) {
    failure = e.what();
    throw;
  }
  return *ctx;
}

std::string GlContext::renderer() const { return reinterpret_cast<const char*>(glGetString(GL_RENDERER)); }
std::string GlContext::version() const { return reinterpret_cast<const char*>(glGetString(GL_VERSION)); }
std::string GlContext::platform() const { return impl_->platform; }
void GlContext::finish() const { glFinish(); }

namespace {

std::string info_log(GLuint id, bool program) {
  GLint len = 0;
  if (program)
    glGetProgramiv(id, GL_INFO_LOG_LENGTH, &len);
  else
    glGetShaderiv(id, GL_INFO_LOG_LENGTH, &len);
  std::string log(size_t(len > 0 ? len : 1), '\0');
  if (program)
    glGetProgramInfoLog(id, len, nullptr, log.data());
  else
    glGetShaderInfoLog(id, len, nullptr, log.data());
  return log.c_str();
}

}  // namespace

unsigned compile_shader(unsigned stage, const std::string& source, const std::string& what) {
  const GLuint shader = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log(shader, false);
    glDeleteShader(shader);
    throw GlError(fmt::format("{} does not compile:\n{}", what, log));
  }
  return shader;
}

unsigned link_program(std::initializer_list<unsigned> shaders, const std::string& what) {
  const GLuint program = glCreateProgram();
  for (const unsigned s : shaders) glAttachShader(program, s);
  glLinkProgram(program);
  for (const unsigned s : shaders) glDeleteShader(s);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = info_log(program, true);
    glDeleteProgram(program);
    throw GlError(fmt::format("{} does not link:\n{}", what, log));
  }
  return program;
}

unsigned vertex_fragment_program(const std::string& vertex, const std::string& fragment, const std::string& what) {
  const unsigned vs = compile_shader(GL_VERTEX_SHADER, vertex, what + ": vertex shader");
  unsigned fs = 0;
  try {
    fs = compile_shader(GL_FRAGMENT_SHADER, fragment, what + ": fragment shader");
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  return link_program({vs, fs}, what + ": program");
}

ComputeProgram::ComputeProgram(const std::string& source) {
  GlContext::get();
  id_ = link_program({compile_shader(GL_COMPUTE_SHADER, source, "compute shader")}, "compute program");
}

ComputeProgram::~ComputeProgram() {
  if (id_) glDeleteProgram(id_);
}

void ComputeProgram::set(const std::string& name, float v) const {
  glProgramUniform1f(id_, glGetUniformLocation(id_, name.c_str()), v);
}
void ComputeProgram::set(const std::string& name, int v) const {
  glProgramUniform1i(id_, glGetUniformLocation(id_, name.c_str()), v);
}
void ComputeProgram::set(const std::string& name, const glm::vec3& v) const {
  glProgramUniform3f(id_, glGetUniformLocation(id_, name.c_str()), v.x, v.y, v.z);
}

void ComputeProgram::bind_block(const std::string& block, unsigned binding) const {
  const GLuint index = glGetUniformBlockIndex(id_, block.c_str());
  if (index == GL_INVALID_INDEX) throw GlError(fmt::format("no active uniform block \"{}\"", block));
  glUniformBlockBinding(id_, index, binding);
}

std::vector<int> ComputeProgram::member_offsets(const std::vector<std::string>& names) const {
  std::vector<const char*> ptrs;
  for (const auto& n : names) ptrs.push_back(n.c_str());
  std::vector<GLuint> indices(names.size(), GL_INVALID_INDEX);
  glGetUniformIndices(id_, GLsizei(names.size()), ptrs.data(), indices.data());
  std::vector<int> out(names.size(), -1);
  for (size_t i = 0; i < names.size(); ++i) {
    if (indices[i] == GL_INVALID_INDEX) continue;
    GLint offset = -1;
    glGetActiveUniformsiv(id_, 1, &indices[i], GL_UNIFORM_OFFSET, &offset);
    out[i] = offset;
  }
  return out;
}

void ComputeProgram::dispatch(unsigned groups_x) const {
  glUseProgram(id_);
  glDispatchCompute(groups_x, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  if (const GLenum err = glGetError(); err != GL_NO_ERROR) throw GlError(fmt::format("glDispatchCompute: GL error 0x{:x}", err));
}

UniformBuffer::UniformBuffer(unsigned binding, size_t bytes, const void* data) {
  GlContext::get();
  glCreateBuffers(1, &id_);
  glNamedBufferData(id_, GLsizeiptr(bytes), data, GL_STATIC_DRAW);
  glBindBufferBase(GL_UNIFORM_BUFFER, binding, id_);
}
UniformBuffer::~UniformBuffer() {
  if (id_) glDeleteBuffers(1, &id_);
}

StorageBuffer::StorageBuffer(unsigned binding, size_t bytes, const void* data) {
  GlContext::get();
  glCreateBuffers(1, &id_);
  glNamedBufferData(id_, GLsizeiptr(bytes), data, GL_DYNAMIC_COPY);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_);
}
StorageBuffer::~StorageBuffer() {
  if (id_) glDeleteBuffers(1, &id_);
}
void StorageBuffer::read(void* out, size_t bytes) const { glGetNamedBufferSubData(id_, 0, GLsizeiptr(bytes), out); }

TablesTexture::TablesTexture(const std::vector<float>& tables) {
  // GL 3.3 calls only (no direct state access): the GL backend and the native explorer make this
  // in a window's 3.3 core context.
  const int width = kGlslTablesWidth;
  const int rows = std::max(1, int((tables.size() + size_t(width) - 1) / size_t(width)));
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  if (rows > max_size || width > max_size)
    throw GlError(fmt::format("the measured tables ({} floats) need a {} x {} float texture; this GL allows {} x {}",
                              tables.size(), width, rows, max_size, max_size));
  std::vector<float> padded(size_t(width) * size_t(rows), 0.f);
  std::copy(tables.begin(), tables.end(), padded.begin());
  GLint previous = 0;
  glGetIntegerv(GL_TEXTURE_BINDING_2D, &previous);
  glGenTextures(1, &id_);
  glBindTexture(GL_TEXTURE_2D, id_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, width, rows, 0, GL_RED, GL_FLOAT, padded.data());
  // texelFetch ignores the filter, but a texture whose filter needs mipmaps it lacks is incomplete.
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glBindTexture(GL_TEXTURE_2D, GLuint(previous));
}
TablesTexture::~TablesTexture() {
  if (id_) glDeleteTextures(1, &id_);
}
void TablesTexture::bind(unsigned unit) const {
  glActiveTexture(GL_TEXTURE0 + unit);
  glBindTexture(GL_TEXTURE_2D, id_);
  glActiveTexture(GL_TEXTURE0);
}

}  // namespace aniso::gl
