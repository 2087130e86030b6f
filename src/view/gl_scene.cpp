#include "view/gl_scene.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <cairo.h>

#include <algorithm>
#include <cstddef>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "core/error.hpp"
#include "output/writers.hpp"
#include "view/gl_program.hpp"

namespace inkline {

namespace {

// Line quads in pixels (line_mesh.hpp): coverage across the line for antialiasing, dashes along it.
const char* kLineVs = R"(#version 330 core
layout(location = 0) in vec2 pos;
layout(location = 1) in float across;
layout(location = 2) in float along;
layout(location = 3) in float half_width;
layout(location = 4) in float style;
layout(location = 5) in float u;
layout(location = 6) in float seg_length;
uniform vec2 size;
out float v_across;
out float v_along;
out float v_u;
flat out float v_half;
flat out float v_length;
flat out int v_style;
void main() {
    gl_Position = vec4(2.0 * pos.x / size.x - 1.0, 1.0 - 2.0 * pos.y / size.y, 0.0, 1.0);
    v_across = across;
    v_along = along;
    v_half = half_width;
    v_u = u;
    v_length = seg_length;
    v_style = int(style + 0.5);
}
)";
const char* kLineFs = R"(#version 330 core
in float v_across;
in float v_along;
in float v_u;
flat in float v_half;
flat in float v_length;
flat in int v_style;
uniform vec4 styles[4];  // grey, dash on, dash off, unused
out vec4 colour;
void main() {
    vec4 s = styles[v_style];
    if (s.y > 0.0 && mod(v_along, s.y + s.z) >= s.y) discard;
    // Distance to the segment: round caps, and round joins where segments overlap.
    float beyond = max(max(-v_u, v_u - v_length), 0.0);
    float cover = clamp(v_half + 0.5 - length(vec2(beyond, v_across)), 0.0, 1.0);
    if (cover <= 0.0) discard;
    // Blended with GL_MIN (dark on light): overlapping quads at the joins do not darken twice.
    colour = vec4(vec3(mix(1.0, s.x, cover)), 1.0);
}
)";
// The stylized drawing (a Cairo RGB24 image, top row first) over the whole viewport.
const char* kImageVs = R"(#version 330 core
out vec2 uv;
void main() {
    vec2 p = vec2(float((gl_VertexID & 1) * 2), float((gl_VertexID & 2)));  // 0,0 2,0 0,2 2,2
    uv = vec2(p.x * 0.5, 1.0 - p.y * 0.5);
    gl_Position = vec4(p - 1.0, 0.0, 1.0);
}
)";

const char* kImageFs = R"(#version 330 core
in vec2 uv;
uniform sampler2D image;
out vec4 colour;
void main() { colour = vec4(texture(image, uv).rgb, 1.0); }
)";

// Flat toon shading: the face normal from screen-space derivatives of the view-space position,
// three bands of light grey under a headlight.
const char* kMeshVs = R"(#version 330 core
layout(location = 0) in vec3 pos;
uniform mat4 view;
uniform mat4 projection;
out vec3 v_view;
void main() {
    vec4 p = view * vec4(pos, 1.0);
    v_view = p.xyz;
    gl_Position = projection * p;
}
)";
const char* kMeshFs = R"(#version 330 core
in vec3 v_view;
uniform int ortho;
out vec4 colour;
void main() {
    vec3 n = normalize(cross(dFdx(v_view), dFdy(v_view)));
    vec3 to_eye = ortho == 1 ? vec3(0.0, 0.0, 1.0) : normalize(-v_view);
    float l = abs(dot(n, to_eye));
    float g = l > 0.75 ? 0.93 : (l > 0.35 ? 0.84 : 0.75);
    colour = vec4(vec3(g), 1.0);
}
)";

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

}  // namespace

void save_screenshot(const std::string& path, int w, int h) {
    const int stride = cairo_format_stride_for_width(CAIRO_FORMAT_RGB24, w);
    std::vector<unsigned char> rows(std::size_t(stride) * std::size_t(h)), flipped(rows.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ROW_LENGTH, stride / 4);
    glReadBuffer(GL_BACK);
    // BGRA as 8_8_8_8_REV is Cairo's native-endian 0x00RRGGBB.
    glReadPixels(0, 0, w, h, GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV, rows.data());
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    for (int y = 0; y < h; ++y)  // GL rows are bottom-up, PNG rows top-down
        std::copy_n(rows.data() + std::size_t(h - 1 - y) * stride, stride, flipped.data() + std::size_t(y) * stride);
    cairo_surface_t* s = cairo_image_surface_create_for_data(flipped.data(), CAIRO_FORMAT_RGB24, w, h, stride);
    std::string png;
    const cairo_status_t st = cairo_surface_write_to_png_stream(s, append, &png);
    cairo_surface_destroy(s);
    if (st != CAIRO_STATUS_SUCCESS) throw Error(path, std::string("cairo: ") + cairo_status_to_string(st));
    write_text_file(path, png);
}

GlScene::GlScene(const MeshTopology& mesh) : mesh_(mesh) {
    line_prog_ = gl_program(kLineVs, kLineFs);
    mesh_prog_ = gl_program(kMeshVs, kMeshFs);
    image_prog_ = gl_program(kImageVs, kImageFs);
    glGenTextures(1, &image_tex_);
    glBindTexture(GL_TEXTURE_2D, image_tex_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenVertexArrays(1, &line_vao_);
    glGenBuffers(1, &line_vbo_);
    glBindVertexArray(line_vao_);
    glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
    const auto attr = [](GLuint i, GLint n, std::size_t offset) {
        glEnableVertexAttribArray(i);
        glVertexAttribPointer(i, n, GL_FLOAT, GL_FALSE, sizeof(LineVertex), reinterpret_cast<const void*>(offset));
    };
    attr(0, 2, offsetof(LineVertex, x));
    attr(1, 1, offsetof(LineVertex, across));
    attr(2, 1, offsetof(LineVertex, along));
    attr(3, 1, offsetof(LineVertex, half));
    attr(4, 1, offsetof(LineVertex, style));
    attr(5, 1, offsetof(LineVertex, u));
    attr(6, 1, offsetof(LineVertex, length));
    glBindVertexArray(0);
}

GlScene::~GlScene() {
    glDeleteBuffers(1, &line_vbo_);
    glDeleteVertexArrays(1, &line_vao_);
    if (mesh_vao_) {
        glDeleteBuffers(2, mesh_bufs_);
        glDeleteVertexArrays(1, &mesh_vao_);
    }
    glDeleteProgram(line_prog_);
    glDeleteProgram(mesh_prog_);
    glDeleteProgram(image_prog_);
    glDeleteTextures(1, &image_tex_);
}

void GlScene::upload_mesh() {
    const MeshTopology& m = mesh_;
    const glm::dvec3 c = m.bounds.center();  // float positions relative to the box centre
    std::vector<float> pos;
    pos.reserve(3 * m.positions.size());
    for (const glm::dvec3& p : m.positions) pos.insert(pos.end(), {float(p.x - c.x), float(p.y - c.y), float(p.z - c.z)});
    glGenVertexArrays(1, &mesh_vao_);
    glGenBuffers(2, mesh_bufs_);
    glBindVertexArray(mesh_vao_);
    glBindBuffer(GL_ARRAY_BUFFER, mesh_bufs_[0]);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(pos.size() * sizeof(float)), pos.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh_bufs_[1]);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(m.faces.size() * sizeof(m.faces[0])), m.faces.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
}

void GlScene::draw(const Camera& cam, bool shading, const std::vector<LineVertex>& lines,
                   const std::vector<std::uint32_t>* image, const std::function<void()>& underlay) {
    glViewport(0, 0, cam.width(), cam.height());
    glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (underlay) underlay();
    else if (shading) draw_shading(cam);
    // The lines: their visibility is already decided; drawn over everything, the darker wins.
    glEnable(GL_BLEND);
    glBlendEquation(GL_MIN);
    if (image) draw_image(cam, *image);
    else draw_lines(cam, lines);
    glBlendEquation(GL_FUNC_ADD);
    glDisable(GL_BLEND);
}

void GlScene::draw_shading(const Camera& cam) {
    if (!mesh_vao_) upload_mesh();
    const MeshTopology& m = mesh_;
    const auto [vf, pf] =
        gl_camera_matrices(cam, m.bounds.center(), m.bounds.half_diagonal(), double(cam.width()) / double(cam.height()));
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    // Pushed back a little so lines on the surface are never under it (they are drawn on top anyway).
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
    glUseProgram(mesh_prog_);
    glUniformMatrix4fv(glGetUniformLocation(mesh_prog_, "view"), 1, GL_FALSE, glm::value_ptr(vf));
    glUniformMatrix4fv(glGetUniformLocation(mesh_prog_, "projection"), 1, GL_FALSE, glm::value_ptr(pf));
    glUniform1i(glGetUniformLocation(mesh_prog_, "ortho"), cam.is_ortho() ? 1 : 0);
    glBindVertexArray(mesh_vao_);
    glDrawElements(GL_TRIANGLES, GLsizei(3 * m.faces.size()), GL_UNSIGNED_INT, nullptr);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_DEPTH_TEST);
}

// The stylized drawing: its white paper lets the shading through.
void GlScene::draw_image(const Camera& cam, const std::vector<std::uint32_t>& image) {
    const int w = cam.width(), h = cam.height();
    glBindTexture(GL_TEXTURE_2D, image_tex_);
    if (image_new_ && image.size() == std::size_t(w) * std::size_t(h)) {
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_BGRA, GL_UNSIGNED_BYTE, image.data());
        image_new_ = false;
    }
    glUseProgram(image_prog_);
    glUniform1i(glGetUniformLocation(image_prog_, "image"), 0);
    glBindVertexArray(line_vao_);  // core profile: some VAO must be bound; the shader makes the quad
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
}

void GlScene::draw_lines(const Camera& cam, const std::vector<LineVertex>& lines) {
    glUseProgram(line_prog_);
    glUniform2f(glGetUniformLocation(line_prog_, "size"), float(cam.width()), float(cam.height()));
    float styles[16];
    for (int i = 0; i < 4; ++i) {
        const LineStyleGl& s = line_style(i);
        styles[4 * i + 0] = s.grey;
        styles[4 * i + 1] = s.dash_on;
        styles[4 * i + 2] = s.dash_off;
        styles[4 * i + 3] = 0.0f;
    }
    glUniform4fv(glGetUniformLocation(line_prog_, "styles"), 4, styles);
    glBindVertexArray(line_vao_);
    glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
    const std::size_t bytes = lines.size() * sizeof(LineVertex);
    if (bytes > line_capacity_) {
        line_capacity_ = std::max(bytes, 2 * line_capacity_);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(line_capacity_), nullptr, GL_STREAM_DRAW);
    }
    if (bytes > 0) {
        glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(bytes), lines.data());
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(lines.size()));
    }
    glBindVertexArray(0);
}

}  // namespace inkline
