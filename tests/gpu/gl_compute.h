// A headless OpenGL 4.5 core context for the GPU-driver check (issue 33): Mesa's llvmpipe
// through EGL's surfaceless platform (no display, no GPU; /work/shared/STACK.md "Engines'
// side"), libepoxy for the GL entry points, and the few calls the check needs: compile a
// compute shader, bind 3-D textures and run it over a list of points.
#pragma once

#include <epoxy/gl.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace vdblight::gpu {

/// Thrown when no context can be made or a shader does not compile or link; the message
/// says which step failed (the test fails with it: a missing driver is a failure, not a skip).
struct GlError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// An OpenGL 4.5 core context made current on this thread for the object's lifetime.
class GlContext {
public:
    GlContext();  ///< throws GlError naming the failed EGL step
    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;
    /// GL_VERSION | GL_RENDERER, e.g. "4.5 (Core Profile) Mesa 22.3.6 | llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string describe() const;

private:
    void* display_ = nullptr;
    void* context_ = nullptr;
};

/// A linked compute program (deleted with the object).
class ComputeProgram {
public:
    /// Compiles and links `source` (a whole shader, #version line included); throws GlError
    /// with the driver's log and the numbered source lines around the first error.
    explicit ComputeProgram(const std::string& source);
    ~ComputeProgram();
    ComputeProgram(const ComputeProgram&) = delete;
    ComputeProgram& operator=(const ComputeProgram&) = delete;
    GLuint id() const { return id_; }
    /// Location of a uniform, -1 if the program does not use it.
    GLint uniform(const std::string& name) const;

private:
    GLuint id_ = 0;
};

/// A 3-D RGBA texture object (deleted with the object).
struct Texture3D {
    GLuint id = 0;
    Texture3D() { glGenTextures(1, &id); }
    ~Texture3D() { glDeleteTextures(1, &id); }
    Texture3D(const Texture3D&) = delete;
    Texture3D& operator=(const Texture3D&) = delete;
};

/// Runs `program` (local size 64, binding 0: vec4 points[], 1: vec4 normals[], 2: vec4 out[],
/// uniform uint pointCount) over the points and returns out[i].xyz per point. The program's
/// samplers and other uniforms must be set before.
std::vector<float> runOverPoints(const ComputeProgram& program, const std::vector<float>& points,
                                 const std::vector<float>& normals);

/// Throws GlError naming `what` if the GL error flag is set.
void checkGl(const char* what);

}  // namespace vdblight::gpu
