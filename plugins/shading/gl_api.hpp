// The OpenGL 4.5 core functions the rasterizer calls, as a table of function
// pointers resolved at run time (OSMesaGetProcAddress): Loom never links
// libGL, so the editor's process can link GLFW's GL beside it.
#pragma once

#include <GL/glcorearb.h>

namespace loom::shading {

#define LOOM_GL_FUNCTIONS(X)                                                            \
  X(PFNGLGETSTRINGPROC, GetString)                                                      \
  X(PFNGLGETERRORPROC, GetError)                                                        \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                  \
  X(PFNGLENABLEPROC, Enable)                                                            \
  X(PFNGLDISABLEPROC, Disable)                                                          \
  X(PFNGLVIEWPORTPROC, Viewport)                                                        \
  X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                                              \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                                      \
  X(PFNGLDEPTHMASKPROC, DepthMask)                                                      \
  X(PFNGLCULLFACEPROC, CullFace)                                                        \
  X(PFNGLPOLYGONMODEPROC, PolygonMode)                                                  \
  X(PFNGLPOLYGONOFFSETPROC, PolygonOffset)                                              \
  X(PFNGLLINEWIDTHPROC, LineWidth)                                                      \
  X(PFNGLFINISHPROC, Finish)                                                            \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                                    \
  X(PFNGLREADBUFFERPROC, ReadBuffer)                                                    \
  X(PFNGLDRAWBUFFERPROC, DrawBuffer)                                                    \
  X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                                                  \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                  \
  X(PFNGLCREATESHADERPROC, CreateShader)                                                \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                                                \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                                              \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                  \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                        \
  X(PFNGLDELETESHADERPROC, DeleteShader)                                                \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                              \
  X(PFNGLATTACHSHADERPROC, AttachShader)                                                \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                  \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                                \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                      \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                              \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                                    \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                    \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                                      \
  X(PFNGLUNIFORM1IVPROC, Uniform1iv)                                                    \
  X(PFNGLUNIFORM1FPROC, Uniform1f)                                                      \
  X(PFNGLUNIFORM1FVPROC, Uniform1fv)                                                    \
  X(PFNGLUNIFORM2FPROC, Uniform2f)                                                      \
  X(PFNGLUNIFORM3FPROC, Uniform3f)                                                      \
  X(PFNGLUNIFORM3FVPROC, Uniform3fv)                                                    \
  X(PFNGLUNIFORMMATRIX3FVPROC, UniformMatrix3fv)                                        \
  X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)                                        \
  X(PFNGLPATCHPARAMETERIPROC, PatchParameteri)                                          \
  X(PFNGLCREATEBUFFERSPROC, CreateBuffers)                                              \
  X(PFNGLNAMEDBUFFERDATAPROC, NamedBufferData)                                          \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                              \
  X(PFNGLCREATEVERTEXARRAYSPROC, CreateVertexArrays)                                    \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                    \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                          \
  X(PFNGLVERTEXARRAYVERTEXBUFFERPROC, VertexArrayVertexBuffer)                          \
  X(PFNGLVERTEXARRAYELEMENTBUFFERPROC, VertexArrayElementBuffer)                        \
  X(PFNGLVERTEXARRAYATTRIBFORMATPROC, VertexArrayAttribFormat)                          \
  X(PFNGLVERTEXARRAYATTRIBBINDINGPROC, VertexArrayAttribBinding)                        \
  X(PFNGLENABLEVERTEXARRAYATTRIBPROC, EnableVertexArrayAttrib)                          \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)                                                \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                                    \
  X(PFNGLCREATETEXTURESPROC, CreateTextures)                                            \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                            \
  X(PFNGLTEXTURESTORAGE2DPROC, TextureStorage2D)                                        \
  X(PFNGLTEXTURESTORAGE2DMULTISAMPLEPROC, TextureStorage2DMultisample)                  \
  X(PFNGLTEXTURESUBIMAGE2DPROC, TextureSubImage2D)                                      \
  X(PFNGLTEXTUREPARAMETERIPROC, TextureParameteri)                                      \
  X(PFNGLTEXTUREPARAMETERIVPROC, TextureParameteriv)                                    \
  X(PFNGLTEXTUREPARAMETERFVPROC, TextureParameterfv)                                    \
  X(PFNGLGENERATETEXTUREMIPMAPPROC, GenerateTextureMipmap)                              \
  X(PFNGLBINDTEXTUREUNITPROC, BindTextureUnit)                                          \
  X(PFNGLCREATEFRAMEBUFFERSPROC, CreateFramebuffers)                                    \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                    \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                          \
  X(PFNGLNAMEDFRAMEBUFFERTEXTUREPROC, NamedFramebufferTexture)                          \
  X(PFNGLNAMEDFRAMEBUFFERTEXTURELAYERPROC, NamedFramebufferTextureLayer)                \
  X(PFNGLNAMEDFRAMEBUFFERDRAWBUFFERSPROC, NamedFramebufferDrawBuffers)                  \
  X(PFNGLNAMEDFRAMEBUFFERREADBUFFERPROC, NamedFramebufferReadBuffer)                    \
  X(PFNGLCHECKNAMEDFRAMEBUFFERSTATUSPROC, CheckNamedFramebufferStatus)                  \
  X(PFNGLBLITNAMEDFRAMEBUFFERPROC, BlitNamedFramebuffer)

struct GlApi {
#define LOOM_GL_MEMBER(type, name) type name = nullptr;
  LOOM_GL_FUNCTIONS(LOOM_GL_MEMBER)
#undef LOOM_GL_MEMBER

  // Resolves every function through `resolve` (a GetProcAddress); throws
  // loom::Error naming the first one missing.
  void load(void* (*resolve)(const char* name));
  // Throws loom::Error with the pending GL error, if any, naming `where`.
  void check(const char* where) const;
};

}  // namespace loom::shading
