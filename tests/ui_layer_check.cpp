// Run by test_view under Xvfb: draws one Dear ImGui frame (a translucent panel with text, check
// boxes, a slider and buttons) over a coloured pattern twice, directly with ImGui's OpenGL3 backend
// and through UiLayer (rasterized once, then blended), and prints how far the two images differ.
// Then asks the layer about the same draw data again (it must not rasterize) and about a frame with
// one number changed (it must). Output, one line:
//   max_diff=D differing=N panel_pixels=P first=0|1 same_again=0|1 changed_again=0|1 rasterized=R
#define GLFW_INCLUDE_NONE
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "view/ui_layer.hpp"

namespace {

constexpr int kW = 480, kH = 360;

struct Target {
    GLuint fbo = 0, tex = 0;
    Target() {
        glGenTextures(1, &tex);
        glBindTexture(GL_TEXTURE_2D, tex);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, kW, kH, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        glBindTexture(GL_TEXTURE_2D, 0);
        glGenFramebuffers(1, &fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    }
    // Stripes of four colours under the panel, so that its translucency shows in the result.
    void pattern() const {
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, kW, kH);
        glEnable(GL_SCISSOR_TEST);
        const float colours[4][3] = {{1, 1, 1}, {0.1f, 0.2f, 0.9f}, {0.9f, 0.3f, 0.1f}, {0, 0, 0}};
        for (int i = 0; i < 12; ++i) {
            glScissor(i * kW / 12, 0, kW / 12 + 1, kH);
            glClearColor(colours[i % 4][0], colours[i % 4][1], colours[i % 4][2], 1.0f);
            glClear(GL_COLOR_BUFFER_BIT);
        }
        glDisable(GL_SCISSOR_TEST);
    }
    std::vector<unsigned char> pixels() const {
        std::vector<unsigned char> p(std::size_t(kW) * kH * 4);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glReadPixels(0, 0, kW, kH, GL_RGBA, GL_UNSIGNED_BYTE, p.data());
        return p;
    }
};

ImDrawData* frame(float value) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(20, 20));
    ImGui::SetNextWindowBgAlpha(0.8f);
    ImGui::Begin("panel");
    static bool a = true, b = false;
    ImGui::Checkbox("silhouette", &a);
    ImGui::SameLine();
    ImGui::Checkbox("border", &b);
    ImGui::SliderFloat("crease angle", &value, 0.0f, 180.0f, "%.1f deg");
    ImGui::Text("%.2f ms visibility, %d walks", double(value) / 7.0, int(value));
    ImGui::Button("SVG");
    ImGui::SameLine();
    ImGui::Button("render command");
    ImGui::End();
    ImGui::Render();
    return ImGui::GetDrawData();
}

}  // namespace

int main() {
    if (!glfwInit()) return 2;
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    GLFWwindow* win = glfwCreateWindow(kW, kH, "ui_layer_check", nullptr, nullptr);
    if (!win) return 3;
    glfwMakeContextCurrent(win);
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::StyleColorsLight();
    ImGui_ImplGlfw_InitForOpenGL(win, false);
    ImGui_ImplOpenGL3_Init("#version 330 core");
    ImGui::GetIO().DisplaySize = ImVec2(kW, kH);
    int rc = 0;
    {
        // A window that fits its contents takes a few frames to settle.
        for (int i = 0; i < 3; ++i) frame(40.0f);
        ImDrawData* data = frame(40.0f);
        Target direct, layered;
        direct.pattern();
        ImGui_ImplOpenGL3_RenderDrawData(data);
        const auto a = direct.pixels();

        inkline::UiLayer layer;
        layered.pattern();
        const bool first = layer.update(data, kW, kH);
        layer.composite();
        const auto b = layered.pixels();
        layered.pattern();
        const auto bare = layered.pixels();

        int max_diff = 0;
        std::size_t differing = 0, panel = 0;
        for (std::size_t i = 0; i < a.size(); i += 4) {
            int d = 0;
            bool covered = false;
            for (int c = 0; c < 3; ++c) {
                d = std::max(d, std::abs(int(a[i + c]) - int(b[i + c])));
                covered |= a[i + c] != bare[i + c];
            }
            max_diff = std::max(max_diff, d);
            differing += d > 0;
            panel += covered;
        }
        const bool same_again = !layer.update(frame(40.0f), kW, kH);
        const bool changed_again = layer.update(frame(41.0f), kW, kH);
        std::printf("max_diff=%d differing=%zu panel_pixels=%zu first=%d same_again=%d changed_again=%d rasterized=%zu\n",
                    max_diff, differing, panel, int(first), int(same_again), int(changed_again), layer.rasterized());
        layer.release();
        if (glGetError() != GL_NO_ERROR) rc = 4;
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(win);
    glfwTerminate();
    return rc;
}
