#include "view/gl_program.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <string>

#include "core/error.hpp"

namespace inkline {

namespace {

GLuint compile(GLenum type, const char* src) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = {};
        glGetShaderInfoLog(s, sizeof log, nullptr, log);
        glDeleteShader(s);
        throw Error("view", std::string("shader does not compile: ") + log);
    }
    return s;
}

}  // namespace

unsigned gl_program(const char* vertex_source, const char* fragment_source) {
    const GLuint v = compile(GL_VERTEX_SHADER, vertex_source);
    GLuint f = 0;
    try {
        f = compile(GL_FRAGMENT_SHADER, fragment_source);
    } catch (...) {
        glDeleteShader(v);
        throw;
    }
    const GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024] = {};
        glGetProgramInfoLog(p, sizeof log, nullptr, log);
        glDeleteProgram(p);
        throw Error("view", std::string("shader program does not link: ") + log);
    }
    return p;
}

}  // namespace inkline
