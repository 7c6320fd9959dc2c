// OpenGL declarations for the display module's sources (private). Core 3.3 entry points are
// called directly: glvnd's libOpenGL exports them and dispatches to whichever context is current
// (EGL headless or GLFW's GLX), so no loader library is needed.
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <string>

namespace holo::display::gl {

// Throws holo::Error naming `what` when OpenGL reports an error.
void check(const char* what);

}  // namespace holo::display::gl
