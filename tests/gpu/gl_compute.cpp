#include "gl_compute.h"

#include <dlfcn.h>
#include <epoxy/egl.h>
#include <link.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace vdblight::gpu {
namespace {

std::string eglStep(const char* what) {
    std::ostringstream s;
    s << "no OpenGL context (EGL surfaceless, Mesa llvmpipe): " << what << " failed, EGL error 0x" << std::hex
      << eglGetError() << " (scripts/setup.sh installs libegl-mesa0 libgl1-mesa-dri libegl-dev libepoxy-dev)";
    return s.str();
}

// The numbered lines of `source` around `line` (1-based), for a compile error's message.
std::string linesAround(const std::string& source, int line) {
    std::istringstream in(source);
    std::ostringstream out;
    std::string text;
    for (int n = 1; std::getline(in, text); ++n)
        if (n >= line - 3 && n <= line + 3) out << n << ": " << text << '\n';
    return out.str();
}

// The first "0:LINE(" of a Mesa compile log, or 0.
int firstErrorLine(const std::string& log) {
    const std::size_t at = log.find("0:");
    return at == std::string::npos ? 0 : std::atoi(log.c_str() + at + 2);
}

// Keeps the DRI driver that eglInitialize loaded (Mesa: dri/swrast_dri.so) in memory until the
// process ends. eglTerminate unloads it, and with it the globals that hold the last pointers
// to some of its allocations; LeakSanitizer then reports those blocks as leaks from an
// "<unknown module>" (128 bytes from realloc on a freshly installed Debian 12, session 21:
// every GPU test of the ASan suite failed). With dlclose made a no-op, nothing was reported.
// RTLD_NOLOAD | RTLD_NODELETE only marks the library already loaded; eglTerminate still runs.
void keepDriversLoaded() {
    std::vector<std::string> drivers;
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void* out) {
            const std::string path = info->dlpi_name ? info->dlpi_name : "";
            if (path.find("/dri/") != std::string::npos) static_cast<std::vector<std::string>*>(out)->push_back(path);
            return 0;
        },
        &drivers);
    for (const std::string& path : drivers) dlopen(path.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
}

}  // namespace

GlContext::GlContext() {
    // The surfaceless platform needs no window system: EGL_MESA_platform_surfaceless.
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!clientExtensions || !std::strstr(clientExtensions, "EGL_MESA_platform_surfaceless"))
        throw GlError(eglStep("EGL_MESA_platform_surfaceless (client extension)"));
    EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) throw GlError(eglStep("eglGetPlatformDisplayEXT"));
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) throw GlError(eglStep("eglInitialize"));
    display_ = display;
    keepDriversLoaded();
    if (!eglBindAPI(EGL_OPENGL_API)) throw GlError(eglStep("eglBindAPI(EGL_OPENGL_API)"));
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    // EGL_KHR_no_config_context: no framebuffer configuration, nothing is drawn.
    EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context == EGL_NO_CONTEXT) throw GlError(eglStep("eglCreateContext (OpenGL 4.5 core, EGL_NO_CONFIG_KHR)"));
    context_ = context;
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
        throw GlError(eglStep("eglMakeCurrent (EGL_NO_SURFACE)"));
    if (epoxy_gl_version() < 45) throw GlError("the OpenGL context is " + describe() + ", not 4.5");
}

GlContext::~GlContext() {
    if (!display_) return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_) eglDestroyContext(display_, context_);
    eglTerminate(display_);
    eglReleaseThread();
}

std::string GlContext::describe() const {
    const auto text = [](GLenum what) {
        const GLubyte* s = glGetString(what);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    return text(GL_VERSION) + " | " + text(GL_RENDERER);
}

ComputeProgram::ComputeProgram(const std::string& source) {
    const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::string log(std::max(length, 1), '\0');
        glGetShaderInfoLog(shader, length, nullptr, log.data());
        glDeleteShader(shader);
        throw GlError("compute shader does not compile:\n" + log + linesAround(source, firstErrorLine(log)));
    }
    id_ = glCreateProgram();
    glAttachShader(id_, shader);
    glLinkProgram(id_);
    glDeleteShader(shader);
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &length);
        std::string log(std::max(length, 1), '\0');
        glGetProgramInfoLog(id_, length, nullptr, log.data());
        throw GlError("compute program does not link:\n" + log);
    }
}

ComputeProgram::~ComputeProgram() { glDeleteProgram(id_); }

GLint ComputeProgram::uniform(const std::string& name) const { return glGetUniformLocation(id_, name.c_str()); }

void checkGl(const char* what) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        std::ostringstream s;
        s << what << ": GL error 0x" << std::hex << e;
        throw GlError(s.str());
    }
}

std::vector<float> runOverPoints(const ComputeProgram& program, const std::vector<float>& points,
                                 const std::vector<float>& normals) {
    const std::size_t count = points.size() / 3;
    // std430 vec4 arrays: xyz and a padding float per point.
    const auto padded = [count](const std::vector<float>& v) {
        std::vector<float> out(4 * count, 0.0f);
        for (std::size_t i = 0; i < count; ++i) std::copy_n(&v[3 * i], 3, &out[4 * i]);
        return out;
    };
    const std::vector<float> p4 = padded(points), n4 = padded(normals);
    GLuint buffers[3];
    glGenBuffers(3, buffers);
    const std::size_t bytes = 4 * count * sizeof(float);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[0]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes), p4.data(), GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffers[1]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes), n4.data(), GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, buffers[2]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes), nullptr, GL_DYNAMIC_READ);
    glUseProgram(program.id());
    glUniform1ui(program.uniform("pointCount"), GLuint(count));
    glDispatchCompute(GLuint((count + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> result(4 * count);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(bytes), result.data());
    glDeleteBuffers(3, buffers);
    checkGl("running the compute shader");
    std::vector<float> xyz(3 * count);
    for (std::size_t i = 0; i < count; ++i) std::copy_n(&result[4 * i], 3, &xyz[3 * i]);
    return xyz;
}

}  // namespace vdblight::gpu
