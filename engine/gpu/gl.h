#pragma once
// The one place that includes OpenGL. Under Emscripten the GPU path is GLES 3.0
// (WebGL2); natively it is desktop GL with the prototypes declared by the system
// headers, so no loader is needed: the binary links the library of its context
// (libOSMesa for headless runs, libGL or EGL for windows), never two of them.

#ifdef __EMSCRIPTEN__
#include <GLES3/gl3.h>
#else
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/gl.h>
#include <GL/glext.h>
#endif
