#include "view/gl_program.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <algorithm>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

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

GlCameraMatrices gl_camera_matrices(const Camera& cam, const glm::dvec3& centre, double radius, double aspect) {
    const double R = std::max(radius, 1e-12);
    const double dist = glm::dot(centre - cam.eye(), cam.forward());
    const double near = cam.is_ortho() ? dist - 1.01 * R : std::max(dist - 1.01 * R, 1e-3 * R);
    const double far = dist + 1.01 * R;
    const glm::dmat4 view = glm::lookAt(cam.eye() - centre, cam.target() - centre, cam.upward());
    const double hh = 0.5 * cam.ortho_height();
    const glm::dmat4 proj = cam.is_ortho() ? glm::ortho(-hh * aspect, hh * aspect, -hh, hh, near, far)
                                           : glm::perspective(glm::radians(cam.fov_deg()), aspect, near, far);
    return {glm::mat4(view), glm::mat4(proj)};
}

}  // namespace inkline
