#include "view/toon_coat.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <algorithm>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "view/gl_program.hpp"

namespace inkline {
namespace {

const char* kCoatVs = R"(#version 330 core
layout(location = 0) in vec3 pos;
layout(location = 1) in vec3 normal;
uniform mat4 view;
uniform mat4 projection;
out vec3 n_view;
void main() {
    n_view = mat3(view) * normal;
    gl_Position = projection * view * vec4(pos, 1.0);
}
)";
// Three tones (a toon shade): lit, half-lit, shadow; the light above-left of the eye.
const char* kCoatFs = R"(#version 330 core
in vec3 n_view;
out vec4 color;
void main() {
    vec3 n = normalize(n_view);
    if (!gl_FrontFacing) n = -n;
    float d = dot(n, normalize(vec3(-0.45, 0.55, 0.7)));
    float tone = d > 0.6 ? 1.0 : (d > 0.15 ? 0.86 : 0.7);
    color = vec4(vec3(0.96, 0.93, 0.87) * tone, 1.0);
}
)";

}  // namespace

void CoatMesh::build(const MeshTopology& mesh, const glm::dvec3& c, double r) {
    centre = c;
    radius = r;
    std::vector<glm::dvec3> normal(mesh.positions.size(), glm::dvec3(0.0));
    for (const auto& t : mesh.faces) {
        const glm::dvec3 n = glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]);
        for (std::uint32_t v : t) normal[v] += n;  // area-weighted
    }
    vertices.resize(6 * mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::dvec3 p = mesh.positions[v] - c;
        const double len = glm::length(normal[v]);
        const glm::dvec3 n = len > 0.0 ? normal[v] / len : glm::dvec3(0.0, 0.0, 1.0);
        const float f[6] = {float(p.x), float(p.y), float(p.z), float(n.x), float(n.y), float(n.z)};
        std::copy(f, f + 6, vertices.begin() + 6 * v);
    }
    triangles.resize(3 * mesh.faces.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f)
        for (int j = 0; j < 3; ++j) triangles[3 * f + j] = mesh.faces[f][j];
}

ToonCoat::~ToonCoat() {
    if (vao_) glDeleteVertexArrays(1, &vao_);
    if (bufs_[0]) glDeleteBuffers(2, bufs_);
    if (prog_) glDeleteProgram(prog_);
}

void ToonCoat::draw(const Camera& cam, const CoatMesh& mesh, bool fresh) {
    if (!prog_) {
        prog_ = gl_program(kCoatVs, kCoatFs);
        glGenVertexArrays(1, &vao_);
        glGenBuffers(2, bufs_);
        fresh = true;
    }
    glBindVertexArray(vao_);
    if (fresh) {
        glBindBuffer(GL_ARRAY_BUFFER, bufs_[0]);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.vertices.size() * sizeof(float)), mesh.vertices.data(), GL_DYNAMIC_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, bufs_[1]);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.triangles.size() * sizeof(std::uint32_t)),
                     mesh.triangles.data(), GL_DYNAMIC_DRAW);
        indices_ = mesh.triangles.size();
    }
    // The same projection as the flat shading (GlScene::draw_shading): depth range from the bounds.
    const auto [vf, pf] = gl_camera_matrices(cam, mesh.centre, mesh.radius, double(cam.width()) / double(cam.height()));
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    glUseProgram(prog_);
    glUniformMatrix4fv(glGetUniformLocation(prog_, "view"), 1, GL_FALSE, glm::value_ptr(vf));
    glUniformMatrix4fv(glGetUniformLocation(prog_, "projection"), 1, GL_FALSE, glm::value_ptr(pf));
    glDrawElements(GL_TRIANGLES, GLsizei(indices_), GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_DEPTH_TEST);
}

}  // namespace inkline
