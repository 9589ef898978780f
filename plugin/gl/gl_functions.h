/* SPDX-License-Identifier: MIT */
/* gl_functions.h - the one table of GL entry points the backend uses, filled per context from
 * its get_proc (OSMesaGetProcAddress, eglGetProcAddress, ...). Nothing in the plugin calls a
 * gl* symbol directly: with libOSMesa and libGL both exporting every gl* name, whichever was
 * loaded first would silently win. The types come from Khronos' glcorearb.h (no prototypes).
 */
#ifndef DDOF_GL_FUNCTIONS_H
#define DDOF_GL_FUNCTIONS_H

#include "gl_context.h"

#include <GL/glcorearb.h>

/* X(type, name): the function gl<name> of type <type>. */
#define GL_FUNCTION_LIST(X)                                                                \
    X(PFNGLGETSTRINGPROC, GetString)                                                       \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                   \
    X(PFNGLGETINTEGER64VPROC, GetInteger64v)                                               \
    X(PFNGLGETERRORPROC, GetError)                                                         \
    X(PFNGLFINISHPROC, Finish)                                                             \
    X(PFNGLCREATESHADERPROC, CreateShader)                                                 \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                                                 \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                                               \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                   \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                         \
    X(PFNGLDELETESHADERPROC, DeleteShader)                                                 \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                               \
    X(PFNGLATTACHSHADERPROC, AttachShader)                                                 \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                   \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                                 \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                       \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                               \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                                                     \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                     \
    X(PFNGLPROGRAMUNIFORM1UIPROC, ProgramUniform1ui)                                       \
    X(PFNGLPROGRAMUNIFORM1FPROC, ProgramUniform1f)                                         \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                                                     \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                               \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                                                     \
    X(PFNGLBUFFERDATAPROC, BufferData)                                                     \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                                               \
    X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                                             \
    X(PFNGLBINDBUFFERRANGEPROC, BindBufferRange)                                           \
    X(PFNGLMAPBUFFERRANGEPROC, MapBufferRange)                                             \
    X(PFNGLUNMAPBUFFERPROC, UnmapBuffer)                                                   \
    X(PFNGLGETBUFFERSUBDATAPROC, GetBufferSubData)                                         \
    X(PFNGLDISPATCHCOMPUTEPROC, DispatchCompute)                                           \
    X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)                                               \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                               \
    X(PFNGLBINDTEXTUREPROC, BindTexture)                                                   \
    X(PFNGLBINDIMAGETEXTUREPROC, BindImageTexture)                                         \
    X(PFNGLGETTEXLEVELPARAMETERIVPROC, GetTexLevelParameteriv)                             \
    X(PFNGLISTEXTUREPROC, IsTexture)                                                       \
    X(PFNGLGENTEXTURESPROC, GenTextures)                                                   \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                             \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                                     \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                               \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                                           \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                           \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)                                 \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                             \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                     \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                                           \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                           \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                     \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                   \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                           \
    X(PFNGLDRAWARRAYSPROC, DrawArrays)                                                     \
    X(PFNGLVIEWPORTPROC, Viewport)                                                         \
    X(PFNGLENABLEPROC, Enable)                                                             \
    X(PFNGLDISABLEPROC, Disable)                                                           \
    X(PFNGLBLENDFUNCPROC, BlendFunc)                                                       \
    X(PFNGLCLEARCOLORPROC, ClearColor)                                                     \
    X(PFNGLCLEARPROC, Clear)                                                               \
    X(PFNGLREADPIXELSPROC, ReadPixels)                                                     \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                   \
    X(PFNGLPROGRAMUNIFORM1IPROC, ProgramUniform1i)                                         \
    X(PFNGLPROGRAMUNIFORM2IPROC, ProgramUniform2i)                                         \
    X(PFNGLPROGRAMUNIFORM2FPROC, ProgramUniform2f)                                         \
    X(PFNGLPROGRAMUNIFORM3FPROC, ProgramUniform3f)                                         \
    X(PFNGLPROGRAMUNIFORM4FPROC, ProgramUniform4f)                                         \
    X(PFNGLPROGRAMUNIFORM3DPROC, ProgramUniform3d)                                         \
    X(PFNGLPROGRAMUNIFORM4DPROC, ProgramUniform4d)                                         \
    X(PFNGLPROGRAMUNIFORM1FVPROC, ProgramUniform1fv)                                       \
    X(PFNGLTEXTUREBARRIERPROC, TextureBarrier)

typedef struct gl_functions {
#define GL_FUNCTION_MEMBER(type, name) type name;
    GL_FUNCTION_LIST(GL_FUNCTION_MEMBER)
#undef GL_FUNCTION_MEMBER
} gl_functions;

/* Fills the table from the context (which must be current: some get_procs only answer then).
 * 0 with the first missing name in message when any entry point is absent. */
int gl_functions_load(gl_functions *gl, gl_context *context, char *message, size_t size);

#endif
