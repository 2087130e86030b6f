// OpenGL shader programs for the preview window (a current GL 3.3 core context is needed).
#pragma once

namespace inkline {

// The program of a vertex and a fragment shader (GLSL source); a compile or link error is thrown
// as Error("view", ...) with the driver's log.
unsigned gl_program(const char* vertex_source, const char* fragment_source);

}  // namespace inkline
