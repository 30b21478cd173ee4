// The OpenGL 3.3 core entry points the renderer uses, loaded at run time through whatever
// context provider made the context current (EGL, OSMesa, GLFW). render/ links no GL library:
// libOSMesa and libGL both export gl*, so an executable that linked both would call the wrong one
// (toolchain.md); a table of function pointers filled from the provider's get-proc avoids that.
#pragma once
#include <GL/glcorearb.h>

namespace ps::gl {

#define PS_GL_FUNCTIONS(X)                                                                     \
  X(PFNGLGETSTRINGPROC, GetString) X(PFNGLGETINTEGERVPROC, GetIntegerv)                         \
  X(PFNGLGETERRORPROC, GetError) X(PFNGLVIEWPORTPROC, Viewport)                                 \
  X(PFNGLCLEARCOLORPROC, ClearColor) X(PFNGLCLEARPROC, Clear) X(PFNGLENABLEPROC, Enable)        \
  X(PFNGLDISABLEPROC, Disable) X(PFNGLBLENDFUNCPROC, BlendFunc) X(PFNGLDEPTHMASKPROC, DepthMask) \
  X(PFNGLDEPTHFUNCPROC, DepthFunc) X(PFNGLCULLFACEPROC, CullFace)                               \
  X(PFNGLREADPIXELSPROC, ReadPixels) X(PFNGLPIXELSTOREIPROC, PixelStorei)                       \
  X(PFNGLFINISHPROC, Finish) X(PFNGLGENBUFFERSPROC, GenBuffers)                                 \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers) X(PFNGLBINDBUFFERPROC, BindBuffer)                   \
  X(PFNGLBUFFERDATAPROC, BufferData) X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                   \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays) X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays) \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                                  \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                                  \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                          \
  X(PFNGLVERTEXATTRIBDIVISORPROC, VertexAttribDivisor) X(PFNGLCREATESHADERPROC, CreateShader)   \
  X(PFNGLSHADERSOURCEPROC, ShaderSource) X(PFNGLCOMPILESHADERPROC, CompileShader)               \
  X(PFNGLGETSHADERIVPROC, GetShaderiv) X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)           \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram) X(PFNGLATTACHSHADERPROC, AttachShader)               \
  X(PFNGLLINKPROGRAMPROC, LinkProgram) X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                   \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog) X(PFNGLDELETESHADERPROC, DeleteShader)       \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram) X(PFNGLUSEPROGRAMPROC, UseProgram)                   \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                            \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv) X(PFNGLUNIFORM3FVPROC, Uniform3fv)             \
  X(PFNGLUNIFORM4FVPROC, Uniform4fv) X(PFNGLUNIFORM1FPROC, Uniform1f)                           \
  X(PFNGLUNIFORM1IPROC, Uniform1i) X(PFNGLUNIFORM2FPROC, Uniform2f)                             \
  X(PFNGLDRAWELEMENTSPROC, DrawElements) X(PFNGLDRAWARRAYSPROC, DrawArrays)                     \
  X(PFNGLDRAWELEMENTSINSTANCEDPROC, DrawElementsInstanced)                                      \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers) X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers) \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                                  \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)                                  \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                                    \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers) X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers) \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                                                \
  X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, RenderbufferStorageMultisample)                    \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                                          \
  X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer) X(PFNGLSCISSORPROC, Scissor)                     \
  X(PFNGLGENTEXTURESPROC, GenTextures) X(PFNGLDELETETEXTURESPROC, DeleteTextures)               \
  X(PFNGLBINDTEXTUREPROC, BindTexture) X(PFNGLTEXIMAGE2DPROC, TexImage2D)                       \
  X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D) X(PFNGLTEXPARAMETERIPROC, TexParameteri)

struct Api {
#define PS_GL_DECLARE(type, name) type name = nullptr;
  PS_GL_FUNCTIONS(PS_GL_DECLARE)
#undef PS_GL_DECLARE
};

// The table in use (one GL context per thread of use in this program).
extern Api api;

using GetProc = void* (*)(const char* name);
// Fills `api` through `get` (e.g. eglGetProcAddress). Throws ps::render::RenderError naming the
// first missing entry point.
void load(GetProc get);
bool loaded();

}  // namespace ps::gl
