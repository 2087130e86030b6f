#include "view/tone_pass.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>

#include "core/clock.hpp"
#include "core/error.hpp"
#include "view/gl_program.hpp"

namespace inkline {

namespace {

constexpr int kMaxLights = 8;
// (the shaders spell these out)
static_assert(tone::kMinWidthScale == 0.25 && int(tone::ToneWidthBy::Depth) == 1 && int(tone::ToneWidthBy::EdgeLength) == 2);
constexpr int kMaxBlurRadius = 192;  // 3 sigma at the widest w (256 px, sigma w/4)

// Pass 1: the tone image (r), the specular channel (g), coverage (b) and the line width's scale
// (a, section 3.4), as tone::shade computes them: smooth corner normals, two-sided, diffuse the mean over the lights of max(0, n.L),
// specular the max over lights of max(0, n.h)^e where n.L > 0.
const char* kShadeVs = R"(#version 330 core
layout(location = 0) in vec3 pos;
layout(location = 1) in vec3 normal;
layout(location = 2) in float edge_scale;
uniform mat4 view;
uniform mat4 projection;
out vec3 v_pos;
out vec3 v_normal;
out float v_edge_scale;
void main() {
    v_pos = pos;
    v_normal = normal;
    v_edge_scale = edge_scale;
    gl_Position = projection * view * vec4(pos, 1.0);
}
)";
const char* kShadeFs = R"(#version 330 core
in vec3 v_pos;
in vec3 v_normal;
in float v_edge_scale;
uniform int width_by;        // 0 constant, 1 depth, 2 edge length (tone::ToneWidthBy)
uniform float nearest;       // tone::nearest_model_depth
uniform vec3 eye;
uniform vec3 forward;
uniform bool ortho;
uniform int light_count;
uniform vec3 lights[8];
uniform float exponent;
out vec4 result;
void main() {
    vec3 view = ortho ? -forward : normalize(eye - v_pos);
    float l = length(v_normal);
    vec3 n = l > 0.0 ? v_normal / l : view;
    if (dot(n, view) < 0.0) n = -n;
    float diffuse = 0.0, specular = 0.0;
    for (int i = 0; i < light_count; ++i) {
        float nl = dot(n, lights[i]);
        if (nl <= 0.0) continue;
        diffuse += nl;
        float nh = dot(n, normalize(lights[i] + view));
        if (nh > 0.0) specular = max(specular, pow(nh, exponent));
    }
    float depth = dot(v_pos - eye, forward);
    float scale = width_by == 1 ? clamp(depth > 0.0 ? nearest / depth : 1.0, 0.25, 1.0)
                : width_by == 2 ? v_edge_scale : 1.0;
    result = vec4(min(1.0, diffuse / float(light_count)), min(1.0, specular), 1.0, scale);
}
)";

// A triangle over the viewport (every full-screen pass).
const char* kFullVs = R"(#version 330 core
void main() {
    vec2 p = vec2(float((gl_VertexID & 1) * 4), float((gl_VertexID & 2) * 2)) - 1.0;
    gl_Position = vec4(p, 0.0, 1.0);
}
)";

// Pass 2: one direction of the separable Gaussian (tone::gaussian_blur: the same float kernel,
// the same order of sums, border clamped). (Taps paired into linear fetches cost the same on a
// software rasterizer and round differently from the CPU pass.)
const char* kBlurFs = R"(#version 330 core
uniform sampler2D source;
uniform float kernel[193];
uniform int radius;
uniform ivec2 dir;
out vec4 result;
void main() {
    ivec2 size = textureSize(source, 0);
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec2 acc = vec2(0.0);
    for (int k = -radius; k <= radius; ++k)
        acc += kernel[k + radius] * texelFetch(source, clamp(p + k * dir, ivec2(0), size - 1), 0).rg;
    result = vec4(acc, 0.0, 0.0);
}
)";

// Pass 3: sections 3.1-3.3 at each pixel (tone/ridges.cpp's fit, search, spot and opacity) of the
// tone image (dark and highlight lines) and of the specular channel (highlight lines, the larger
// opacity kept: tone::merge_max). Coordinates are GL's (y up): the fit is the CPU's mirrored, the
// same lines. A software rasterizer runs every branch of the shader for a block of pixels, but
// skips the rest of it where the whole block is discarded: so one first fit of both channels from
// one set of samples, a discard where no search is due (most of the image), and the searches in
// a loop over the channels that are due. INTEGRAL (defined when w/2 is a whole number of pixels):
// the first fit's samples are pixel centres.
const char* kRidgeFs = R"(
uniform sampler2D blurred;  // r: tone, g: specular, both blurred
uniform sampler2D shaded;   // a: the line width's scale (section 3.4)
uniform float H[54];        // (X^T X)^-1 X^T, 6 rows of 9
uniform float spacing;      // w / 2
uniform float beta;
uniform float bound;        // |curvature| bound per unit of the samples' range
uniform int steps;
uniform vec2 dark_c;        // c_l, c_u; c_l above every curvature: those lines not wanted
uniform vec2 light_c;
uniform bool falloff;
uniform bool counterchange;
out vec4 opacity;           // r: dark lines, g: highlight lines

ivec2 size_px;
float sp;                   // this pixel's spacing: w / 2 times its width scale

vec2 texel(ivec2 p) { return texelFetch(blurred, clamp(p, ivec2(0), size_px - 1), 0).rg; }

// Bilinear at a continuous point (pixel centres at +0.5), clamped to the border (Image::sample):
// the texture unit's linear filter (float weights on a float texture), one fetch.
float sample1(vec2 p, vec2 pick) { return dot(texture(blurred, p / vec2(size_px)).rg, pick); }

struct Line {
    float c;       // the curvature of larger magnitude (> 0: valley)
    float other;
    vec2 n;        // across the line
    float offset;  // the line passes through offset * n (sample units)
    vec2 centre;
};

Line ridge_line(float a[6]) {
    float d = 0.5 * (a[0] - a[2]), mean = 0.5 * (a[0] + a[2]), half_diff = sqrt(d * d + a[1] * a[1]);
    Line l;
    l.c = mean >= 0.0 ? mean + half_diff : mean - half_diff;
    l.other = mean >= 0.0 ? mean - half_diff : mean + half_diff;
    vec2 e1 = vec2(a[1], l.c - a[0]), e2 = vec2(l.c - a[2], a[1]);
    vec2 e = dot(e1, e1) >= dot(e2, e2) ? e1 : e2;
    float len = length(e);
    l.n = len > 0.0 ? e / len : vec2(1.0, 0.0);
    l.offset = l.c != 0.0 ? -(a[3] * l.n.x + a[4] * l.n.y) / (2.0 * l.c) : 0.0;
    float det = a[0] * a[2] - a[1] * a[1];
    l.centre = det != 0.0 ? vec2(a[2] * a[3] - a[1] * a[4], a[0] * a[4] - a[1] * a[3]) / (-2.0 * det) : vec2(0.0);
    return l;
}

Line fit_at(vec2 p, vec2 pick) {
    float a[6] = float[6](0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            float t = sample1(p + sp * vec2(i - 1, j - 1), pick);
            for (int r = 0; r < 6; ++r) a[r] += H[9 * r + 3 * j + i] * t;
        }
    return ridge_line(a);
}

// The search from the first fit l toward the line (rejected, 0, when the curvature drops below
// c_l or changes sign, or when it travels over w/2), then the opacity.
float search(Line l, vec2 pick, bool dark, vec2 lim, float t_here) {
    vec2 centre = gl_FragCoord.xy, pos = centre;
    float travel = 0.0;
    for (int step = 0; step <= steps; ++step) {
        if (step > 0) l = fit_at(pos, pick);
        float c = dark ? l.c : -l.c;
        if (!(c >= lim.x) || c <= 0.0) return 0.0;
        if (step == steps) break;
        float move = beta * l.offset * sp;
        travel += abs(move);
        if (travel > sp) return 0.0;
        pos += move * l.n;
    }
    vec2 on_line = pos + l.offset * sp * l.n;
    vec2 n = l.n;
    if (l.other * l.c > 0.0) {  // a spot's centre: one dash through it, across the y axis
        vec2 c = pos + sp * l.centre;
        if (length(c - centre) <= sp) {
            Line at_c = fit_at(c, pick);
            if (at_c.other * at_c.c > 0.0 && abs(at_c.other) > 0.5 * abs(at_c.c)) {
                on_line = c + sp * at_c.centre;
                n = vec2(0.0, 1.0);
            }
        }
    }
    float distance = dot(centre - on_line, n);
    float alpha = lim.y > lim.x ? clamp((abs(l.c) - lim.x) / (lim.y - lim.x), 0.0, 1.0) : 1.0;
    if (falloff) alpha *= max(0.0, 1.0 - abs(distance) / sp);
    if (counterchange) {
        float t = clamp(t_here, 0.0, 1.0);
        alpha *= dark ? 1.0 - t : t;
    }
    return max(alpha, 0.0);
}

void main() {
    size_px = textureSize(blurred, 0);
    vec2 centre = gl_FragCoord.xy;
    float scale = texelFetch(shaded, ivec2(centre), 0).a;
    sp = spacing * scale;
    // (thresholds per (w/2)^2: per spacing^2 they scale by its square)
    vec2 dark_s = dark_c * (scale * scale), light_s = light_c * (scale * scale);
    // The first fit of both channels (x: tone, y: specular), and the range of their samples.
    float a0[6] = float[6](0.0, 0.0, 0.0, 0.0, 0.0, 0.0), a1[6] = a0;
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
#ifdef INTEGRAL
            vec2 t = texel(ivec2(centre) + int(spacing) * ivec2(i - 1, j - 1));
#else
            vec2 t = texture(blurred, (centre + sp * vec2(i - 1, j - 1)) / vec2(size_px)).rg;
#endif
            lo = min(lo, t);
            hi = max(hi, t);
            for (int r = 0; r < 6; ++r) {
                a0[r] += H[9 * r + 3 * j + i] * t.x;
                a1[r] += H[9 * r + 3 * j + i] * t.y;
            }
        }
    // Which searches are due: the stencil's range lets its curvature reach a wanted threshold,
    // and the fit's curvature reaches the threshold of its kind (the specular channel: highlights).
    Line l0 = ridge_line(a0), l1 = ridge_line(a1);
    bool dark0 = l0.c > 0.0;
    vec2 lim0 = dark0 ? dark_s : light_s;
    bool due0 = !((hi.x - lo.x) * bound < min(dark_s.x, light_s.x) || hi.x == lo.x) && abs(l0.c) >= lim0.x;
    bool due1 = !((hi.y - lo.y) * bound < light_s.x || hi.y == lo.y) && l1.c <= 0.0 && -l1.c >= light_s.x;
    if (!due0 && !due1) discard;
    vec2 here = texel(ivec2(centre));
    float dark_a = 0.0, light_a = 0.0;
    for (int k = due0 ? 0 : 1; k < (due1 ? 2 : 1); ++k) {
        bool tone = k == 0;
        bool dark = tone && dark0;
        float alpha = search(tone ? l0 : l1, tone ? vec2(1.0, 0.0) : vec2(0.0, 1.0), dark, dark ? dark_s : light_s,
                             tone ? here.x : here.y);
        if (dark) dark_a = alpha;
        else light_a = max(light_a, alpha);
    }
    if (!(dark_a > 0.0 || light_a > 0.0)) discard;
    opacity = vec4(dark_a, light_a, 0.0, 0.0);
}
)";

// Pass 4: the composite: the toon base coat (or white), highlight lines white, dark lines black.
const char* kCompositeFs = R"(#version 330 core
uniform sampler2D blurred;  // r: tone
uniform sampler2D shaded;   // b: covered
uniform sampler2D lines;    // r: dark opacity, g: highlight opacity
uniform bool show_base;
uniform int bands;
out vec4 colour;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 base = vec3(1.0);
    if (show_base && texelFetch(shaded, px, 0).b > 0.5) {
        int k = clamp(int(texelFetch(blurred, px, 0).r * float(bands)), 0, bands - 1);
        base = vec3(round(110.0 + 125.0 * float(k) / float(bands - 1)) / 255.0);
    }
    vec2 a = texelFetch(lines, px, 0).rg;
    colour = vec4(mix(mix(base, vec3(1.0), a.y), vec3(0.0), a.x), 1.0);
}
)";

const char* kCopyFs = R"(#version 330 core
uniform sampler2D image;
out vec4 colour;
void main() { colour = vec4(texelFetch(image, ivec2(gl_FragCoord.xy), 0).rgb, 1.0); }
)";

// Linear filtering (the search's bilinear samples; texelFetch ignores it).
unsigned make_texture(GLenum internal, GLenum format, GLenum type, int w, int h) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GLint(internal), w, h, 0, format, type, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    return t;
}

unsigned make_fbo(unsigned texture, unsigned depth) {
    GLuint f = 0;
    glGenFramebuffers(1, &f);
    glBindFramebuffer(GL_FRAMEBUFFER, f);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    if (depth) glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) throw Error("view", "the tone pass's framebuffer is incomplete (no float textures?)");
    return f;
}

GLint uniform(unsigned prog, const char* name) { return glGetUniformLocation(prog, name); }

// An upper bound on |curvature| of a fit per unit of its samples' range (tone/ridges.cpp).
double curvature_bound_per_range() {
    double sum[3] = {0, 0, 0};
    for (int r = 0; r < 3; ++r)
        for (double h : tone::fit_matrix()[std::size_t(r)]) sum[r] += std::abs(h);
    return 0.5 * (std::max(sum[0], sum[2]) + sum[1]);
}

}  // namespace

glm::dvec3 light_direction(const Camera& cam, const LightAngles& a) {
    const double az = glm::radians(a.azimuth_deg), el = glm::radians(a.elevation_deg);
    const glm::dvec3 d = std::cos(el) * (std::sin(az) * cam.right() - std::cos(az) * cam.forward()) + std::sin(el) * cam.upward();
    return glm::normalize(d);
}

LightAngles light_angles(const Camera& cam, const glm::dvec3& direction) {
    const glm::dvec3 d = glm::normalize(direction);
    return {glm::degrees(std::atan2(glm::dot(d, cam.right()), -glm::dot(d, cam.forward()))),
            glm::degrees(std::asin(std::clamp(glm::dot(d, cam.upward()), -1.0, 1.0)))};
}

namespace {
bool software_renderer() {
    const char* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    if (!r) return false;
    const std::string name(r);
    for (const char* s : {"llvmpipe", "softpipe", "SwiftShader", "Software Rasterizer"})
        if (name.find(s) != std::string::npos) return true;
    return false;
}
}  // namespace

TonePass::TonePass(const MeshTopology& mesh, TonePassMode mode, int threads)
    : mesh_(mesh), cpu_(mode == TonePassMode::Cpu || (mode == TonePassMode::Auto && software_renderer())),
      threads_(std::max(1, threads)) {
    shade_prog_ = gl_program(kShadeVs, kShadeFs);
    blur_prog_ = gl_program(kFullVs, kBlurFs);
    ridge_prog_[0] = gl_program(kFullVs, (std::string("#version 330 core\n") + kRidgeFs).c_str());
    ridge_prog_[1] = gl_program(kFullVs, (std::string("#version 330 core\n#define INTEGRAL 1\n") + kRidgeFs).c_str());
    composite_prog_ = gl_program(kFullVs, kCompositeFs);
    copy_prog_ = gl_program(kFullVs, kCopyFs);
    glGenVertexArrays(1, &empty_vao_);
}

TonePass::~TonePass() {
    resize(0, 0);
    if (mesh_vao_) {
        glDeleteBuffers(2, mesh_bufs_);
        glDeleteVertexArrays(1, &mesh_vao_);
    }
    glDeleteVertexArrays(1, &empty_vao_);
    for (unsigned p : {shade_prog_, blur_prog_, ridge_prog_[0], ridge_prog_[1], composite_prog_, copy_prog_})
        glDeleteProgram(p);
}

// A GL vertex per distinct (mesh vertex, corner normal): corners around a vertex share one unless
// a crease separates them (tone::prepare_tone_mesh), so most vertices are shaded once, not once a
// face. Positions relative to the box centre (float precision).
void TonePass::upload_mesh() {
    const MeshTopology& m = mesh_;
    const tone::ToneMesh normals = tone::prepare_tone_mesh(m);
    const glm::dvec3 c = m.bounds.center();
    std::vector<float> data;
    std::vector<std::uint32_t> index;
    index.reserve(3 * m.faces.size());
    // For each mesh vertex, the GL vertices made for it so far (usually one): linked by `next`.
    std::vector<std::uint32_t> first(m.positions.size(), UINT32_MAX), next;
    std::vector<glm::vec3> normal_of;
    for (std::size_t f = 0; f < m.faces.size(); ++f)
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t v = m.faces[f][k];
            const glm::vec3 n = normals.corner_normals[f][k];
            std::uint32_t g = first[v];
            while (g != UINT32_MAX && normal_of[g] != n) g = next[g];
            if (g == UINT32_MAX) {
                g = std::uint32_t(normal_of.size());
                normal_of.push_back(n);
                next.push_back(first[v]);
                first[v] = g;
                const glm::dvec3 p = m.positions[v] - c;
                data.insert(data.end(), {float(p.x), float(p.y), float(p.z), n.x, n.y, n.z, normals.vertex_width_scale[v]});
            }
            index.push_back(g);
        }
    if (!mesh_vao_) {
        glGenVertexArrays(1, &mesh_vao_);
        glGenBuffers(2, mesh_bufs_);
    }
    glBindVertexArray(mesh_vao_);
    glBindBuffer(GL_ARRAY_BUFFER, mesh_bufs_[0]);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(data.size() * sizeof(float)), data.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 7 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 7 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, 7 * sizeof(float), reinterpret_cast<const void*>(6 * sizeof(float)));
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh_bufs_[1]);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(index.size() * sizeof(std::uint32_t)), index.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
    index_count_ = index.size();
    uploaded_crease_ = m.crease_degrees;
}

void TonePass::resize(int w, int h) {
    if (w == w_ && h == h_) return;
    if (w_ > 0) {
        const GLuint fbos[5] = {shade_fbo_, ping_fbo_, blurred_fbo_, lines_fbo_, result_fbo_};
        glDeleteFramebuffers(5, fbos);
        const GLuint texs[5] = {shaded_tex_, ping_tex_, blurred_tex_, lines_tex_, result_tex_};
        glDeleteTextures(5, texs);
        glDeleteRenderbuffers(1, &depth_rb_);
    }
    w_ = w, h_ = h;
    last_key_.clear();
    if (w <= 0 || h <= 0) return;
    shaded_tex_ = make_texture(GL_RGBA32F, GL_RGBA, GL_FLOAT, w, h);
    ping_tex_ = make_texture(GL_RG32F, GL_RG, GL_FLOAT, w, h);
    blurred_tex_ = make_texture(GL_RG32F, GL_RG, GL_FLOAT, w, h);
    lines_tex_ = make_texture(GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, w, h);
    result_tex_ = make_texture(GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, w, h);
    glGenRenderbuffers(1, &depth_rb_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    shade_fbo_ = make_fbo(shaded_tex_, depth_rb_);
    ping_fbo_ = make_fbo(ping_tex_, 0);
    blurred_fbo_ = make_fbo(blurred_tex_, 0);
    lines_fbo_ = make_fbo(lines_tex_, 0);
    result_fbo_ = make_fbo(result_tex_, 0);
}

void TonePass::shade(const Camera& cam, const tone::ToneOptions& o) {
    if (!mesh_vao_ || uploaded_crease_ != mesh_.crease_degrees) upload_mesh();
    const MeshTopology& m = mesh_;
    const glm::dvec3 c = m.bounds.center();
    // Near and far around the bounding sphere (as the scene's shading).
    const auto [vf, pf] = gl_camera_matrices(cam, c, m.bounds.half_diagonal(), double(w_) / double(h_));
    glBindFramebuffer(GL_FRAMEBUFFER, shade_fbo_);
    glClearColor(1.0f, 0.0f, 0.0f, 1.0f);  // background: tone 1 (white), no specular, not covered, scale 1
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glUseProgram(shade_prog_);
    glUniformMatrix4fv(uniform(shade_prog_, "view"), 1, GL_FALSE, glm::value_ptr(vf));
    glUniformMatrix4fv(uniform(shade_prog_, "projection"), 1, GL_FALSE, glm::value_ptr(pf));
    const glm::vec3 eye(cam.eye() - c), forward(cam.forward());
    glUniform3fv(uniform(shade_prog_, "eye"), 1, glm::value_ptr(eye));
    glUniform3fv(uniform(shade_prog_, "forward"), 1, glm::value_ptr(forward));
    glUniform1i(uniform(shade_prog_, "ortho"), cam.is_ortho() ? 1 : 0);
    float lights[3 * kMaxLights] = {};
    const int count = std::min(int(o.lights.size()), kMaxLights);
    for (int i = 0; i < count; ++i) {
        const glm::dvec3 l = glm::normalize(o.lights[std::size_t(i)]);
        lights[3 * i] = float(l.x), lights[3 * i + 1] = float(l.y), lights[3 * i + 2] = float(l.z);
    }
    glUniform3fv(uniform(shade_prog_, "lights"), kMaxLights, lights);
    glUniform1i(uniform(shade_prog_, "light_count"), std::max(count, 1));
    glUniform1f(uniform(shade_prog_, "exponent"), float(o.specular_exponent));
    glUniform1i(uniform(shade_prog_, "width_by"), int(o.width_by));
    glUniform1f(uniform(shade_prog_, "nearest"), float(tone::nearest_model_depth(m, cam)));
    glBindVertexArray(mesh_vao_);
    glDrawElements(GL_TRIANGLES, GLsizei(index_count_), GL_UNSIGNED_INT, nullptr);
    glDisable(GL_DEPTH_TEST);
}

void TonePass::blur(double width) {
    // The kernel exactly as tone::gaussian_blur makes it.
    const double sigma = width / 4.0;
    const int radius = std::min(sigma > 0 ? int(std::ceil(3.0 * sigma)) : 0, kMaxBlurRadius);
    std::vector<float> kernel(std::size_t(2 * radius + 1), 1.0f);
    double sum = 0.0;
    for (int k = -radius; k <= radius; ++k) sum += kernel[std::size_t(k + radius)] = float(std::exp(-0.5 * k * k / (sigma * sigma)));
    for (float& k : kernel) k = float(k / sum);
    if (radius == 0) kernel[0] = 1.0f;
    glUseProgram(blur_prog_);
    glUniform1fv(uniform(blur_prog_, "kernel"), GLsizei(kernel.size()), kernel.data());
    glUniform1i(uniform(blur_prog_, "radius"), radius);
    glUniform1i(uniform(blur_prog_, "source"), 0);
    glBindVertexArray(empty_vao_);
    glActiveTexture(GL_TEXTURE0);
    const struct { unsigned fbo, from; int dx, dy; } passes[2] = {{ping_fbo_, shaded_tex_, 1, 0}, {blurred_fbo_, ping_tex_, 0, 1}};
    for (const auto& p : passes) {  // along rows, then along columns
        glBindFramebuffer(GL_FRAMEBUFFER, p.fbo);
        glBindTexture(GL_TEXTURE_2D, p.from);
        glUniform2i(uniform(blur_prog_, "dir"), p.dx, p.dy);
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
}

void TonePass::ridges(const tone::ToneOptions& o, const ToneLayers& layers) {
    static const double bound = curvature_bound_per_range();
    float h[54];
    for (int r = 0; r < 6; ++r)
        for (int i = 0; i < 9; ++i) h[9 * r + i] = float(tone::fit_matrix()[std::size_t(r)][std::size_t(i)]);
    const double spacing = 0.5 * o.width;
    const bool integral = spacing == std::floor(spacing) && o.width_by == tone::ToneWidthBy::Constant;
    const unsigned p = ridge_prog_[integral ? 1 : 0];
    constexpr float kNever = 1e30f;  // a lower threshold no curvature reaches: lines not wanted
    glBindFramebuffer(GL_FRAMEBUFFER, lines_fbo_);
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glUseProgram(p);
    glUniform1fv(uniform(p, "H"), 54, h);
    glUniform1f(uniform(p, "spacing"), float(spacing));
    glUniform1f(uniform(p, "beta"), float(o.beta));
    glUniform1f(uniform(p, "bound"), float(bound));
    glUniform1i(uniform(p, "steps"), o.steps);
    glUniform1i(uniform(p, "falloff"), o.distance_falloff ? 1 : 0);
    glUniform1i(uniform(p, "counterchange"), o.counterchange ? 1 : 0);
    glUniform1i(uniform(p, "blurred"), 0);
    glUniform1i(uniform(p, "shaded"), 1);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, shaded_tex_);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, blurred_tex_);
    glBindVertexArray(empty_vao_);
    glUniform2f(uniform(p, "dark_c"), layers.dark ? float(o.dark_lower) : kNever, layers.dark ? float(o.dark_upper) : kNever);
    glUniform2f(uniform(p, "light_c"), layers.highlight ? float(o.highlight_lower) : kNever,
                layers.highlight ? float(o.highlight_upper) : kNever);
    if (layers.dark || layers.highlight) glDrawArrays(GL_TRIANGLES, 0, 3);
    // The composite into the result.
    const unsigned c = composite_prog_;
    glUseProgram(c);
    glUniform1i(uniform(c, "show_base"), layers.base ? 1 : 0);
    glUniform1i(uniform(c, "bands"), std::clamp(o.toon_bands, 2, 4));
    glUniform1i(uniform(c, "blurred"), 0);
    glUniform1i(uniform(c, "shaded"), 1);
    glUniform1i(uniform(c, "lines"), 2);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, shaded_tex_);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, lines_tex_);
    glBindFramebuffer(GL_FRAMEBUFFER, result_fbo_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE0);
}

// The same stages as render's (tone::render_tone, untraced) and the composite of kCompositeFs:
// the toon base of the blurred tone (or white), highlight lines white, dark lines black.
void TonePass::run_cpu(const Camera& cam, const tone::ToneOptions& o, const ToneLayers& layers) {
    if (cpu_crease_ != mesh_.crease_degrees) {
        cpu_normals_ = tone::prepare_tone_mesh(mesh_);
        cpu_crease_ = mesh_.crease_degrees;
    }
    tone::ToneOptions options = o;
    options.threads = threads_;
    tone::ToneResult& r = cpu_result_;
    tone::render_tone(mesh_, cpu_normals_, cam, options, layers.dark, layers.highlight, r, false);
    const auto t0 = std::chrono::steady_clock::now();
    const int bands = std::clamp(o.toon_bands, 2, 4);
    const std::size_t n = std::size_t(w_) * std::size_t(h_);
    cpu_pixels_.resize(n);
    const auto opacity = [n](const tone::RidgeField& f, std::size_t i) {
        return f.opacity.size() == n ? double(f.opacity[i]) : 0.0;
    };
    for (int y = 0; y < h_; ++y)
        for (int x = 0; x < w_; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(w_) + std::size_t(x);  // image rows top first
            double g = 1.0;
            if (layers.base && r.shaded.covered[i]) {
                const int k = std::clamp(int(r.tone_blurred.pixels[i] * float(bands)), 0, bands - 1);
                g = std::round(110.0 + 125.0 * k / (bands - 1)) / 255.0;
            }
            g += (1.0 - g) * opacity(r.highlight, i);
            g *= 1.0 - opacity(r.dark, i);
            const std::uint32_t c = std::uint32_t(std::lround(std::clamp(g, 0.0, 1.0) * 255.0));
            cpu_pixels_[std::size_t(h_ - 1 - y) * std::size_t(w_) + std::size_t(x)] = 0xff000000u | c << 16 | c << 8 | c;  // GL rows bottom first
        }
    glBindTexture(GL_TEXTURE_2D, result_tex_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w_, h_, GL_RGBA, GL_UNSIGNED_BYTE, cpu_pixels_.data());
    glBindTexture(GL_TEXTURE_2D, 0);
    times_ = {r.seconds.shade, r.seconds.blur, r.seconds.ridges + seconds_since(t0)};
    sum_.shade += times_.shade, sum_.blur += times_.blur, sum_.ridges += times_.ridges;
    ++runs_;
}

void TonePass::run(const Camera& cam, const tone::ToneOptions& o, const ToneLayers& layers) {
    if (cpu_) return run_cpu(cam, o, layers);
    glViewport(0, 0, w_, h_);
    glDisable(GL_BLEND);
    auto t0 = std::chrono::steady_clock::now();
    const auto lap = [&t0] {
        glFinish();
        const double s = seconds_since(t0);
        t0 = std::chrono::steady_clock::now();
        return s;
    };
    shade(cam, o);
    times_.shade = lap();
    blur(o.width);
    times_.blur = lap();
    ridges(o, layers);
    times_.ridges = lap();
    sum_.shade += times_.shade, sum_.blur += times_.blur, sum_.ridges += times_.ridges;
    ++runs_;
}

void TonePass::draw(const Camera& cam, const tone::ToneOptions& o, const ToneLayers& layers) {
    resize(cam.width(), cam.height());
    std::vector<double> key = {cam.eye().x, cam.eye().y, cam.eye().z, cam.target().x, cam.target().y, cam.target().z,
                               cam.up().x, cam.up().y, cam.up().z, cam.fov_deg(), cam.is_ortho() ? cam.ortho_height() : -1.0,
                               o.specular_exponent, o.width, o.beta, double(o.steps), o.dark_lower, o.dark_upper,
                               o.highlight_lower, o.highlight_upper, double(o.distance_falloff), double(o.counterchange),
                               double(o.toon_bands), double(o.width_by), double(layers.dark), double(layers.highlight), double(layers.base),
                               mesh_.crease_degrees};
    for (const glm::dvec3& l : o.lights) key.insert(key.end(), {l.x, l.y, l.z});
    if (key != last_key_) {
        run(cam, o, layers);
        last_key_ = std::move(key);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, w_, h_);
    glDisable(GL_BLEND);
    glUseProgram(copy_prog_);
    glUniform1i(uniform(copy_prog_, "image"), 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, result_tex_);
    glBindVertexArray(empty_vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
}

}  // namespace inkline
