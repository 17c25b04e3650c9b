// OpenGL 3.3 core for the control client's renderer, with no loader library: Mesa's and
// every glvnd libOpenGL export the whole core API, so the prototypes are declared and the
// functions linked directly. The context comes from whoever made it current (EGL offscreen,
// GLFW in the window).
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
