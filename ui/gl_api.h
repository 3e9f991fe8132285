// OpenGL 3.3 core declarations for the preview's drawing code. The functions are resolved when an
// executable links: libOpenGL in caustica-view, libOSMesa in caustica-view-headless (never both).
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
