#include "view/ui_layer.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "view/gl_program.hpp"

namespace inkline {

namespace {

// A quad over `rect` (normalized device coordinates x0, y0, x1, y1) whose fragments take their
// texel unfiltered at their own pixel: the layer is premultiplied (ImGui blends colour by alpha
// and adds alpha by one minus alpha, over a transparent clear), so it is blended with ONE,
// ONE_MINUS_SRC_ALPHA: the same result as drawing the panel's quads over the frame directly, up
// to 8-bit rounding.
const char* kVs = R"(#version 330 core
uniform vec4 rect;
void main() {
    vec2 t = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
    gl_Position = vec4(mix(rect.xy, rect.zw, t), 0.0, 1.0);
}
)";
const char* kFs = R"(#version 330 core
uniform sampler2D layer;
out vec4 colour;
void main() { colour = texelFetch(layer, ivec2(gl_FragCoord.xy), 0); }
)";

template <class T>
void put(std::vector<unsigned char>& out, const T& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(&v);
    out.insert(out.end(), p, p + sizeof v);
}

void put_bytes(std::vector<unsigned char>& out, const void* data, std::size_t n) {
    put(out, n);
    const auto* p = static_cast<const unsigned char*>(data);
    out.insert(out.end(), p, p + n);
}

}  // namespace

UiLayer::~UiLayer() { release(); }

void UiLayer::release() {
    if (fbo_) glDeleteFramebuffers(1, &fbo_);
    if (tex_) glDeleteTextures(1, &tex_);
    if (prog_) glDeleteProgram(prog_);
    if (vao_) glDeleteVertexArrays(1, &vao_);
    fbo_ = tex_ = prog_ = vao_ = 0;
    w_ = h_ = 0;
    last_.clear();
}

// Everything the OpenGL3 backend reads from the draw data (vertices, indices, commands with
// their clip rectangles and textures, the display rectangle), in one byte string.
bool UiLayer::same_as_last(ImDrawData* data) {
    now_.clear();
    put(now_, data->DisplayPos);
    put(now_, data->DisplaySize);
    put(now_, data->FramebufferScale);
    put(now_, data->CmdListsCount);
    for (int i = 0; i < data->CmdListsCount; ++i) {
        const ImDrawList* l = data->CmdLists[i];
        put_bytes(now_, l->VtxBuffer.Data, std::size_t(l->VtxBuffer.Size) * sizeof(ImDrawVert));
        put_bytes(now_, l->IdxBuffer.Data, std::size_t(l->IdxBuffer.Size) * sizeof(ImDrawIdx));
        put(now_, l->CmdBuffer.Size);
        for (const ImDrawCmd& c : l->CmdBuffer) {
            put(now_, c.ClipRect);
            put(now_, c.TextureId);
            put(now_, c.VtxOffset);
            put(now_, c.IdxOffset);
            put(now_, c.ElemCount);
            put(now_, c.UserCallback);
            put(now_, c.UserCallbackData);
        }
    }
    if (now_ == last_) return true;
    last_.swap(now_);
    return false;
}

void UiLayer::setup() {
    prog_ = gl_program(kVs, kFs);
    glGenVertexArrays(1, &vao_);  // core profile: some VAO must be bound
    glGenTextures(1, &tex_);
    glGenFramebuffers(1, &fbo_);
}

bool UiLayer::update(ImDrawData* data, int fb_w, int fb_h) {
    if (!data || fb_w < 1 || fb_h < 1) return false;
    if (!prog_) setup();
    GLint bound = 0, viewport[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &bound);
    glGetIntegerv(GL_VIEWPORT, viewport);
    bool resized = false;
    if (fb_w != w_ || fb_h != h_) {
        glBindTexture(GL_TEXTURE_2D, tex_);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, fb_w, fb_h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glBindTexture(GL_TEXTURE_2D, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex_, 0);
        const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        glBindFramebuffer(GL_FRAMEBUFFER, GLuint(bound));
        if (status != GL_FRAMEBUFFER_COMPLETE) throw Error("view", "panel layer framebuffer is incomplete");
        w_ = fb_w, h_ = fb_h;
        resized = true;
    }
    if (same_as_last(data) && !resized) return false;
    // The pixels the panel covers: its vertices' box (ImGui clips within it), one pixel wider for
    // antialiased edges; GL rows count from the bottom.
    float x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (int i = 0; i < data->CmdListsCount; ++i)
        for (const ImDrawVert& v : data->CmdLists[i]->VtxBuffer) {
            x0 = std::min(x0, v.pos.x), x1 = std::max(x1, v.pos.x);
            y0 = std::min(y0, v.pos.y), y1 = std::max(y1, v.pos.y);
        }
    const float sx = data->FramebufferScale.x, sy = data->FramebufferScale.y;
    if (x0 <= x1) {
        x0_ = std::clamp(int(std::floor((x0 - data->DisplayPos.x) * sx)) - 1, 0, fb_w);
        x1_ = std::clamp(int(std::ceil((x1 - data->DisplayPos.x) * sx)) + 1, 0, fb_w);
        y0_ = std::clamp(fb_h - int(std::ceil((y1 - data->DisplayPos.y) * sy)) - 1, 0, fb_h);
        y1_ = std::clamp(fb_h - int(std::floor((y0 - data->DisplayPos.y) * sy)) + 1, 0, fb_h);
    } else {
        x0_ = x1_ = y0_ = y1_ = 0;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, fb_w, fb_h);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(data);
    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(bound));
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    ++rasterized_;
    return true;
}

void UiLayer::composite() const {
    if (x0_ >= x1_ || y0_ >= y1_ || !prog_) return;
    glViewport(0, 0, w_, h_);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(prog_);
    const auto ndc = [](int p, int n) { return 2.0f * float(p) / float(n) - 1.0f; };
    glUniform4f(glGetUniformLocation(prog_, "rect"), ndc(x0_, w_), ndc(y0_, h_), ndc(x1_, w_), ndc(y1_, h_));
    glUniform1i(glGetUniformLocation(prog_, "layer"), 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, tex_);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glUseProgram(0);
    glDisable(GL_BLEND);
}

}  // namespace inkline
