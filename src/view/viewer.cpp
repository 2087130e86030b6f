#include "view/viewer.hpp"

#define GLFW_INCLUDE_NONE
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <cairo.h>
#include <imgui.h>
#include <imgui_internal.h>  // (the panel window's widest line: ImGuiWindow::DC.CursorMaxPos)

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cfloat>
#include <deque>
#include <utility>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "core/clock.hpp"
#include "core/error.hpp"
#include "core/worker_thread.hpp"
#include "output/styled.hpp"
#include "output/writers.hpp"
#include "style/style.hpp"
#include "style/styled_view.hpp"
#include "view/camera_rig.hpp"
#include "view/gl_program.hpp"
#include "view/line_mesh.hpp"
#include "view/ui_layer.hpp"

namespace inkline {

std::string camera_flags(const Camera& cam) {
    const auto v3 = [](const glm::dvec3& v) {
        char buf[128];
        std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g", v.x, v.y, v.z);
        return std::string(buf);
    };
    char buf[512];
    std::snprintf(buf, sizeof buf, "--eye=%s --target=%s --up=%s --%s=%.17g --size=%dx%d", v3(cam.eye()).c_str(),
                  v3(cam.target()).c_str(), v3(cam.up()).c_str(), cam.is_ortho() ? "ortho" : "fov",
                  cam.is_ortho() ? cam.ortho_height() : cam.fov_deg(), cam.width(), cam.height());
    return buf;
}

namespace {

using Clock = StageClock;
double cpu_seconds(clockid_t clock) {
    timespec t{};
    clock_gettime(clock, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

std::string glfw_error() {
    const char* d = nullptr;
    glfwGetError(&d);
    return d ? d : "unknown GLFW error";
}

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
// Flat toon shading: the face normal from screen-space derivatives of the view-space position,
// three bands of light grey under a headlight.
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

// ---- Screenshot: the back buffer to a PNG through Cairo, written atomically --------------------

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

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

// ---- The window -------------------------------------------------------------------------------

struct Glfw {
    Glfw() {
        if (!glfwInit()) throw Error("view", "cannot open a window (no display?): " + glfw_error());
    }
    ~Glfw() { glfwTerminate(); }
    Glfw(const Glfw&) = delete;
    Glfw& operator=(const Glfw&) = delete;
};

struct StageTimes {
    double features = 0, search = 0, chain = 0, visibility = 0, recall = 0, lines = 0, draw = 0, frame = 0, wait = 0;
    double pieces = 0, propagation = 0, walks = 0, rays = 0;  // visibility's stages (DrawingStats)
    double cpu_features = 0, cpu_visibility = 0;  // CPU time of the pipeline thread
    void add(const StageTimes& o, double k = 1.0) {
        cpu_features += k * o.cpu_features, cpu_visibility += k * o.cpu_visibility;
        features += k * o.features, search += k * o.search, chain += k * o.chain, visibility += k * o.visibility;
        pieces += k * o.pieces, propagation += k * o.propagation, walks += k * o.walks, rays += k * o.rays;
        recall += k * o.recall, lines += k * o.lines, draw += k * o.draw, frame += k * o.frame, wait += k * o.wait;
    }
};

class Viewer {
public:
    Viewer(Model& model, const Camera& home, const ViewerOptions& o)
        : model_(model), opt_(o), rig_(home, model.topology().bounds) {
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_RESIZABLE, o.frames > 0 ? GLFW_FALSE : GLFW_TRUE);
        const std::string title = "inkline view - " + o.model_path;
        win_ = glfwCreateWindow(home.width(), home.height(), title.c_str(), nullptr, nullptr);
        if (!win_) throw Error("view", "cannot open an OpenGL 3.3 core window: " + glfw_error());
        glfwMakeContextCurrent(win_);
        glfwSwapInterval(o.frames > 0 ? 0 : 1);
        glfwSetWindowUserPointer(win_, this);
        // Ours first: ImGui's backend chains to them.
        glfwSetScrollCallback(win_, [](GLFWwindow* w, double, double dy) {
            static_cast<Viewer*>(glfwGetWindowUserPointer(w))->scroll_ += dy;
        });
        glfwSetWindowRefreshCallback(win_, [](GLFWwindow* w) {
            static_cast<Viewer*>(glfwGetWindowUserPointer(w))->damaged_ = true;  // contents lost: draw again
        });
        glfwSetKeyCallback(win_, [](GLFWwindow* w, int key, int, int action, int) {
            if (action == GLFW_PRESS) static_cast<Viewer*>(glfwGetWindowUserPointer(w))->key(key);
        });
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the user's directory
        ImGui::StyleColorsLight();
        ImGui_ImplGlfw_InitForOpenGL(win_, true);
        ImGui_ImplOpenGL3_Init("#version 330 core");

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

        crease_ = float(model.topology().crease_degrees);
        fraction_ = float(o.view.finder.fraction);
        hidden_ = o.hidden;
        shading_ = o.shading;
        panel_ = o.panel;
        recall_on_ = o.recall;
        vopt_ = o.view;
        style_names_ = {"lines (GL)", "clean", "technical", "sketchy", "charcoal", "ink-brush", "hatched"};
        if (!o.style.empty()) {
            const auto it = std::find(style_names_.begin(), style_names_.end(), o.style);
            if (it == style_names_.end()) style_names_.push_back(o.style);  // a style file
            style_index_ = int(std::find(style_names_.begin(), style_names_.end(), o.style) - style_names_.begin());
            style_ = std::make_shared<const Style>(load_style(o.style));
        }
        rebuild_session();
    }

    ~Viewer() {
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
        ui_layer_.release();
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        glfwDestroyWindow(win_);
    }
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    // The loop is pipelined: while the main thread draws frame k-1 (OpenGL, the panel, the swap),
    // a worker thread runs the pipeline for frame k's camera. The lines drawn are one frame behind
    // the camera; the shading is drawn at the lines' camera, so the two always agree.
    int run() {
        StageTimes total;
        int measured = 0;
        double cpu_main0 = 0.0, cpu_all0 = 0.0, wall = 0.0;
        auto t_measure = Clock::now();
        for (int frame = 0; !glfwWindowShouldClose(win_); ++frame) {
            // Headless: frames 0..N-1 each start the pipeline for one camera; frame N only draws
            // the last result (screenshot, export).
            const bool finishing = opt_.frames > 0 && frame == opt_.frames;
            const auto t0 = Clock::now();
            // Idle for a few frames (the panel settles after an event): sleep until input.
            // Interactive, the window does not wait for the pipeline: it draws the last view while
            // the next one is computed (the panel and the camera stay responsive on big meshes),
            // yielding the CPU to the pipeline between its frames.
            // The pipeline wakes the loop when its view is done (an empty event), so waiting for it
            // costs no polling; input wakes it too.
            const bool interactive = opt_.frames == 0;
            if (interactive && unchanged_ > 3 && in_flight_.empty()) glfwWaitEventsTimeout(0.5);
            else if (interactive && !in_flight_.empty() && !oldest_done()) glfwWaitEventsTimeout(0.05);
            else glfwPollEvents();
            StageTimes st;
            // Views are taken in the order they were started. Headless: lock-step, the oldest view
            // taken once every lane is busy (one frame behind with one lane, two with two), and all
            // of them at the last frame.
            bool fresh = false;
            if (finishing) fresh = sync_all(st);
            else if (interactive ? oldest_done() : int(in_flight_.size()) >= in_flight_mode()) fresh = sync(st);
            if (fresh) {
                const auto now = Clock::now();
                if (last_fresh_ != Clock::time_point{}) {
                    const double period = std::chrono::duration<double>(now - last_fresh_).count();
                    view_period_ = view_period_ > 0.0 ? 0.9 * view_period_ + 0.1 * period : period;
                }
                last_fresh_ = now;
            }
            if (finishing) wall = seconds_since(t_measure);
            // Options change only while the session is idle.
            if (crease_dirty_ || fraction_dirty_) {
                StageTimes ignored;
                sync_all(ignored);
            }
            if (crease_dirty_) {
                model_.topology().set_crease_angle(crease_);
                crease_dirty_ = false;
                dirty_ = true;
            }
            if (dirty_) {
                rebuild_session();
                dirty_ = false;
            }
            if (fraction_dirty_) {
                for (int i = 0; i < lane_count_; ++i) lanes_[i]->session->finder().set_fraction(fraction_);
                fraction_dirty_ = false;
                force_ = true;
            }
            if (opt_.frames > 0 && opt_.orbit && frame > 0 && !finishing) rig_.orbit(opt_.arc / opt_.frames, 0.0);
            if (panel_) {
                ImGui_ImplOpenGL3_NewFrame();
                ImGui_ImplGlfw_NewFrame();
                ImGui::NewFrame();
            }
            mouse();
            int w = 0, h = 0;
            glfwGetFramebufferSize(win_, &w, &h);
            if (w < 1 || h < 1) {  // minimised
                if (panel_) ImGui::EndFrame();
                glfwWaitEvents();
                continue;
            }
            const Camera cam = rig_.camera(w, h);
            // Interactive and nothing changed: the last view and its quads are still right.
            // (the camera of the newest view, started or drawn)
            const Camera& newest = in_flight_.empty() ? drawn_ : lanes_[in_flight_.back()]->camera;
            const bool again = opt_.frames == 0 && !force_ && view_ && same_camera(cam, newest);
            unchanged_ = again && !fresh && in_flight_.empty() ? unchanged_ + 1 : 0;
            if (!again && !finishing && int(in_flight_.size()) < in_flight_mode()) {
                launch(cam);
                force_ = false;
            }
            if (!view_) sync(st);  // nothing to draw yet (first frame, new session): wait for it

            // The panel's draw data first: its layer is rasterized only when the panel looks
            // different (usually a few times a second, when its numbers are refreshed).
            const auto td = Clock::now();
            bool panel_changed = panel_ != panel_drawn_;
            panel_drawn_ = panel_;
            if (panel_) {
                draw_panel();
                ImGui::Render();
                panel_changed |= ui_layer_.update(ImGui::GetDrawData(), w, h);
            }
            // Interactive, a frame that would show nothing new is not drawn: no new view (the lines
            // are drawn at their view's camera, not the rig's), the panel unchanged and the window
            // not damaged. Redrawing it cost the rasterizer's CPU (Mesa's llvmpipe) many times a
            // view, taken from the pipeline on the same cores.
            const bool resized = w != drawn_w_ || h != drawn_h_;
            const bool redraw = !interactive || fresh || panel_changed || damaged_ || resized;
            if (!redraw) continue;
            damaged_ = false;
            drawn_w_ = w, drawn_h_ = h;
            draw_scene(drawn_);
            const bool shot = finishing && !opt_.screenshot.empty();
            if (shot && !opt_.screenshot_ui) save_screenshot(opt_.screenshot, drawn_.width(), drawn_.height());
            if (panel_) ui_layer_.composite();
            if (shot && opt_.screenshot_ui) {
                save_screenshot(opt_.screenshot, drawn_.width(), drawn_.height());
                if (panel_)
                    std::printf("panel: %.0f x %.0f px, its widest line %.0f px past its clipped edge\n", panel_size_.x,
                                panel_size_.y, panel_overflow_);
            }
            if (finishing && !opt_.export_path.empty()) export_view(opt_.export_path);
            glfwSwapBuffers(win_);
            st.draw = seconds_since(td);
            st.frame = seconds_since(t0);
            if (fresh) {
                shown_.add(shown_, -0.1);  // what the panel shows: a moving average
                shown_.add(st, 0.1);
            } else {  // the window's own frame: no new view
                shown_.draw = 0.9 * shown_.draw + 0.1 * st.draw;
            }
            // The window's frame rate: between frames drawn (the first waits for the lazy indexes).
            const auto now = Clock::now();
            if (frame > 0 && last_drawn_ != Clock::time_point{}) {
                const double period = std::chrono::duration<double>(now - last_drawn_).count();
                window_period_ = window_period_ > 0.0 ? 0.9 * window_period_ + 0.1 * period : period;
            }
            last_drawn_ = now;
            if (finishing) break;
            if (frame == 0) {
                shown_ = st;
                t_measure = Clock::now();  // the first frame builds the lazy indexes: not measured
                cpu_main0 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
                cpu_all0 = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID);
                measuring_ = true;  // the views taken from now on
            } else {
                total.add(st);
                ++measured;
            }
        }
        StageTimes st;
        sync_all(st);  // views still in flight (window closed)
        if (opt_.fps && measured > 0) {
            if (opt_.frames == 0) wall = seconds_since(t_measure);
            const double k = 1000.0 / measured;
            const double kv = 1000.0 / std::max(views_measured_, 1);  // per view (as many as frames)
            const StageTimes& v = view_total_;
            const double cpu_main = cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - cpu_main0;
            const double cpu_all = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID) - cpu_all0;
            // (With two views at once, a view's stages take about twice a frame: they overlap.)
            std::printf("fps: %.1f over %d frames (after the first) of %d triangles, %.2f ms/frame; views: %d one at "
                        "a time on %d thread%s, %d two at once on %d thread%s each; pipeline per view: features %.2f "
                        "(search %.2f, chain %.2f), visibility %.2f (pieces %.2f, propagation %.2f, walks %.2f, ray "
                        "tests %.2f), line quads %.2f; main thread: GL draw+swap %.2f, waiting for the pipeline %.2f; "
                        "%zu silhouette edges, %zu line vertices in the last frame\n",
                        measured / wall, measured, int(model_.topology().face_count()), wall * k, views_by_mode_[0],
                        threads_, threads_ > 1 ? "s" : "", views_by_mode_[1], std::max(1, threads_ / 2),
                        threads_ / 2 > 1 ? "s" : "", v.features * kv, v.search * kv, v.chain * kv,
                        v.visibility * kv, v.pieces * kv, v.propagation * kv, v.walks * kv, v.rays * kv, v.lines * kv,
                        total.draw * k, total.wait * k, last_silhouettes_, lines_.size());
            // On a loaded machine wall time is inflated; CPU time is the work itself (Mesa's
            // llvmpipe rasterizes on threads of its own).
            // (The rest: the visibility's helper threads, with one view at a time, and Mesa's rasterizer.)
            const double cpu_rest = cpu_all - cpu_main - worker_cpu_;
            std::printf("cpu: pipeline %.2f ms/view on its lane's thread (features %.2f, visibility %.2f), main thread "
                        "%.2f ms/frame, all threads of the process %.2f ms/frame, of which other threads %.2f (X server "
                        "not included)\n",
                        worker_cpu_ * kv, v.cpu_features * kv, v.cpu_visibility * kv, cpu_main * k, cpu_all * k,
                        cpu_rest * k);
        }
        // Interactive, the camera may have moved after the last view was drawn: the rig's is printed.
        const Camera final_camera = opt_.frames > 0 ? drawn_ : rig_.camera(drawn_.width(), drawn_.height());
        std::printf("camera: %s\n", camera_flags(final_camera).c_str());
        return 0;
    }

private:
    void rebuild_session() {
        vopt_.exact_hidden = hidden_ || (style_ && style_->draw_hidden);
        vopt_.finder.fraction = fraction_;
        StageTimes st;
        sync_all(st);  // never while the old sessions are in use
        // The lanes: two sessions where there are two threads (unless --in-flight=1), one view at a
        // time on all the threads or two at once, the threads split (in_flight_mode()).
        threads_ = std::max(1, vopt_.threads);
        lane_count_ = opt_.in_flight == 1 || threads_ < 2 ? 1 : 2;
        for (int i = 0; i < lane_count_; ++i) {
            if (!lanes_[i]) lanes_[i] = std::make_unique<Lane>();
            lanes_[i]->session = std::make_unique<ViewSession>(model_, vopt_);
        }
        for (int i = lane_count_; i < 2; ++i) lanes_[i].reset();
        last_lane_ = -1;
        two_at_once_ = false;  // (until a few views have shown the camera's step)
        step_ = 0.0;
        steps_seen_ = 0;
        view_ = nullptr;  // it belonged to an old session
    }

    // Views computed at once now: 1 or 2. Two sessions taking the views in turn each follow a view
    // two frames back, so each finder's follow costs about twice as much; on armadillo@2 two at
    // once gave more views a second than one at a time on both threads while the camera moved
    // less than about 1.8 degrees a view, and fewer above (bench/results/view_fps.md). --in-flight
    // fixes it; by default it follows the camera's step (smoothed over about four views, from the
    // fourth view on: a second lane started and left at once would cost its first view for
    // nothing), with a margin either side so that it does not flip-flop.
    int in_flight_mode() {
        if (lane_count_ < 2) return 1;
        if (opt_.in_flight == 2) return 2;
        constexpr double kDeg = M_PI / 180.0;
        if (two_at_once_ && step_ > 1.6 * kDeg) two_at_once_ = false;
        else if (!two_at_once_ && steps_seen_ >= 4 && step_ < 1.0 * kDeg) two_at_once_ = true;
        return two_at_once_ ? 2 : 1;
    }

    // Starts the pipeline for `cam` on the next lane's thread: features -> visibility -> line quads.
    // It reads the model and uses the lane's session; the main thread touches neither until that
    // view is taken (sync()).
    void launch(const Camera& cam) {
        const int mode = in_flight_mode();
        // One at a time: the lane of the last view goes on (a step of one view); two: the other
        // lane (the last view's lane is busy, or was the last to start).
        const int lane = last_lane_ < 0 ? 0 : mode == 2 ? 1 - last_lane_ : last_lane_;
        if (last_lane_ >= 0) {  // the camera's step: the eye's and the target's moves over the distance
            const Camera& prev = lanes_[last_lane_]->camera;
            const double dist = std::max(glm::length(prev.eye() - prev.target()), 1e-300);
            const double step = (glm::length(cam.eye() - prev.eye()) + glm::length(cam.target() - prev.target())) / dist;
            const double clamped = std::min(step, 10.0);
            step_ = steps_seen_++ == 0 ? clamped : 0.75 * step_ + 0.25 * clamped;
        }
        last_lane_ = lane;
        Lane& L = *lanes_[lane];
        L.session->set_threads(std::max(1, threads_ / mode));  // (the lane is idle: not in flight)
        in_flight_.push_back(lane);
        L.camera = cam;
        L.mode = mode;
        LineMeshOptions lo;
        lo.hidden = hidden_;
        lo.simplify_px = 0.25;  // invisible at the line widths drawn, fewer triangles
        const bool recall = recall_on_;
        const FeatureOptions kinds = vopt_.features;  // the panel may change vopt_ meanwhile
        const std::shared_ptr<const Style> style = style_;
        const bool hidden = hidden_;
        L.done = false;
        L.job = L.thread.post([this, &L, cam, lo, recall, kinds, style, hidden] {
            const double cpu0 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
            Job& j = L.result;
            ViewSession& session = *L.session;
            session.find(cam);  // find, then visibility: the same as render(), timed apart
            const double cpu1 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
            View& view = session.visibility(cam);
            j.cpu_features = cpu1 - cpu0;
            j.cpu_visibility = cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - cpu1;
            j.view = &view;
            j.camera = cam;
            j.times = StageTimes{};
            j.times.features = session.seconds_features();
            j.times.search = view.features.stats.seconds_search;
            j.times.chain = view.features.stats.seconds_chain;
            j.times.visibility = view.drawing.stats.seconds_visibility;
            j.recall = -1.0;
            if (recall) {
                const auto tr = Clock::now();
                const Features ref = extract_features(model_.topology(), cam, kinds);
                const double all = edges_length(model_.topology(), ref.silhouette_edges);
                j.recall = all > 0.0 ? edges_length(model_.topology(), view.features.silhouette_edges) / all : 1.0;
                j.times.recall = seconds_since(tr);
            }
            const auto tl = Clock::now();
            j.styled = style != nullptr;
            if (style) {  // what render --style writes, as pixels
                styled_to_pixels(stylize_view(model_, cam, view, *style, hidden), j.pixels);
                j.lines.clear();
            } else {
                build_line_mesh(view.drawing, lo, j.lines);
            }
            j.times.lines = seconds_since(tl);
            j.cpu = cpu_seconds(CLOCK_THREAD_CPUTIME_ID) - cpu0;
            L.done = true;
            glfwPostEmptyEvent();  // (thread-safe) wakes the loop's wait
        });
    }

    // Whether the oldest view in flight is done (then taking it does not wait).
    bool oldest_done() {
        if (in_flight_.empty()) return false;
        Lane& L = *lanes_[in_flight_.front()];
        // (done is set as the job's last step, just before its future is ready: then wait for it)
        return L.done.load() ? (L.job.wait(), true) : L.job.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
    }

    // Every view in flight taken, oldest first (the lanes idle after). Returns whether there was one.
    bool sync_all(StageTimes& st) {
        bool any = false;
        while (sync(st)) any = true;
        return any;
    }

    // Waits for the oldest view in flight, if any (its exception, if any, is thrown here), and
    // makes it the one drawn. Returns whether there was one.
    bool sync(StageTimes& st) {
        if (in_flight_.empty()) return false;
        Lane& L = *lanes_[in_flight_.front()];
        in_flight_.pop_front();
        const auto t = Clock::now();
        L.job.get();
        st.wait += seconds_since(t);
        const Job& j = L.result;
        std::swap(lines_, L.result.lines);
        std::swap(pixels_, L.result.pixels);
        styled_ = j.styled;
        pixels_new_ = styled_;
        view_ = j.view;
        drawn_ = j.camera;
        stats_ = j.view->drawing.stats;
        recall_ = j.recall;
        StageTimes v;  // the view's own times (st may gather several views: sync_all)
        v.cpu_features = j.cpu_features;
        v.cpu_visibility = j.cpu_visibility;
        v.features = j.times.features;
        v.search = j.times.search;
        v.chain = j.times.chain;
        v.visibility = j.times.visibility;
        v.pieces = stats_.seconds_pieces;
        v.propagation = stats_.seconds_propagation;
        v.walks = stats_.seconds_walks;
        v.rays = stats_.seconds_ray_tests;
        v.recall = j.times.recall;
        v.lines = j.times.lines;
        st.add(v);
        if (measuring_) {  // (--fps: the views after the first frame's, however many a frame takes)
            view_total_.add(v);
            ++views_measured_;
            ++views_by_mode_[L.mode - 1];
            worker_cpu_ += j.cpu;
        }
        last_silhouettes_ = stats_.silhouette_edges;
        return true;
    }

    static bool same_camera(const Camera& a, const Camera& b) {
        return a.eye() == b.eye() && a.target() == b.target() && a.up() == b.up() && a.fov_deg() == b.fov_deg() &&
               a.is_ortho() == b.is_ortho() && a.ortho_height() == b.ortho_height() && a.width() == b.width() &&
               a.height() == b.height();
    }

    void key(int k) {
        if (panel_ && ImGui::GetIO().WantCaptureKeyboard) return;
        switch (k) {
            case GLFW_KEY_R: rig_.reset(); break;
            case GLFW_KEY_1: rig_.front(); break;
            case GLFW_KEY_2: rig_.side(); break;
            case GLFW_KEY_3: rig_.top(); break;
            case GLFW_KEY_O: rig_.toggle_ortho(); break;
            case GLFW_KEY_H: panel_ = !panel_; break;
            case GLFW_KEY_ESCAPE:
            case GLFW_KEY_Q: glfwSetWindowShouldClose(win_, GLFW_TRUE); break;
            default: break;
        }
    }

    void mouse() {
        double x = 0, y = 0;
        glfwGetCursorPos(win_, &x, &y);
        const double dx = x - mouse_x_, dy = y - mouse_y_;
        mouse_x_ = x;
        mouse_y_ = y;
        const bool ui = panel_ && ImGui::GetIO().WantCaptureMouse;
        const double scroll = scroll_;
        scroll_ = 0.0;
        if (ui) return;
        if (scroll != 0.0) rig_.zoom(scroll);
        int h = 0;
        glfwGetWindowSize(win_, nullptr, &h);
        if (glfwGetMouseButton(win_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) rig_.orbit(-0.4 * dx, -0.4 * dy);
        else if (glfwGetMouseButton(win_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
                 glfwGetMouseButton(win_, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS)
            rig_.pan(dx, dy, h);
    }

    void upload_mesh() {
        const MeshTopology& m = model_.topology();
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

    void draw_scene(const Camera& cam) {
        const int w = cam.width(), h = cam.height();
        glViewport(0, 0, w, h);
        glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        if (shading_) {
            if (!mesh_vao_) upload_mesh();
            const MeshTopology& m = model_.topology();
            const glm::dvec3 c = m.bounds.center();
            const double R = std::max(m.bounds.half_diagonal(), 1e-12);
            const double dist = glm::dot(c - cam.eye(), cam.forward());
            const double near = cam.is_ortho() ? dist - 1.01 * R : std::max(dist - 1.01 * R, 1e-3 * R);
            const double far = dist + 1.01 * R;
            const glm::dmat4 view = glm::lookAt(cam.eye() - c, cam.target() - c, cam.upward());
            const double aspect = double(w) / double(h);
            glm::dmat4 proj;
            if (cam.is_ortho()) {
                const double hh = 0.5 * cam.ortho_height();
                proj = glm::ortho(-hh * aspect, hh * aspect, -hh, hh, near, far);
            } else {
                proj = glm::perspective(glm::radians(cam.fov_deg()), aspect, near, far);
            }
            const glm::mat4 vf(view), pf(proj);
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
        // The lines: their visibility is already decided; drawn over everything, the darker wins.
        glEnable(GL_BLEND);
        glBlendEquation(GL_MIN);
        if (styled_) {  // the stylized drawing: its white paper lets the shading through
            glBindTexture(GL_TEXTURE_2D, image_tex_);
            if (pixels_new_ && pixels_.size() == std::size_t(w) * std::size_t(h)) {
                glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
                glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_BGRA, GL_UNSIGNED_BYTE, pixels_.data());
                pixels_new_ = false;
            }
            glUseProgram(image_prog_);
            glUniform1i(glGetUniformLocation(image_prog_, "image"), 0);
            glBindVertexArray(line_vao_);  // core profile: some VAO must be bound; the shader makes the quad
            glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
            glBindVertexArray(0);
            glBindTexture(GL_TEXTURE_2D, 0);
            glBlendEquation(GL_FUNC_ADD);
            glDisable(GL_BLEND);
            return;
        }
        glUseProgram(line_prog_);
        glUniform2f(glGetUniformLocation(line_prog_, "size"), float(w), float(h));
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
        const std::size_t bytes = lines_.size() * sizeof(LineVertex);
        if (bytes > line_capacity_) {
            line_capacity_ = std::max(bytes, 2 * line_capacity_);
            glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(line_capacity_), nullptr, GL_STREAM_DRAW);
        }
        if (bytes > 0) {
            glBufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(bytes), lines_.data());
            glDrawArrays(GL_TRIANGLES, 0, GLsizei(lines_.size()));
        }
        glBindVertexArray(0);
        glBlendEquation(GL_FUNC_ADD);
        glDisable(GL_BLEND);
    }

    void draw_panel();
    // Writes the current drawing (format from the extension) and prints the `render` line for it.
    void export_view(const std::string& path);
    std::string render_command(const Camera& cam, const std::string& output) const;

    Model& model_;
    ViewerOptions opt_;
    CameraRig rig_;
    GLFWwindow* win_ = nullptr;
    ViewOptions vopt_;
    std::vector<LineVertex> lines_;
    View* view_ = nullptr;  // the session's last view (lines_ are its quads), drawn at drawn_
    Camera drawn_;
    DrawingStats stats_;    // of view_ (the panel reads this copy: view_ is rewritten by the worker)
    struct Job {            // written by a lane's thread, read after its job's get()
        View* view = nullptr;
        Camera camera;
        StageTimes times;
        double recall = -1.0, cpu = 0.0, cpu_features = 0.0, cpu_visibility = 0.0;
        std::vector<LineVertex> lines;
        bool styled = false;
        std::vector<std::uint32_t> pixels;  // styled: the drawing, camera.width() x camera.height()
    };
    // A lane: a session and the thread that computes its views, one at a time. The thread lives as
    // long as the lane: the stages keep per-thread working storage from view to view (build_pieces'
    // scratch arrays are thread_local: tens of megabytes on a large model), which a new thread per
    // view would allocate again.
    struct Lane {
        std::unique_ptr<ViewSession> session;
        Camera camera;  // of the view started last
        int mode = 1;   // views at once when it started
        Job result;
        std::future<void> job;
        std::atomic<bool> done{false};  // set by the job as it ends (its future is ready just after)
        WorkerThread thread;            // (last: stopped first, after its job in flight)
    };
    std::unique_ptr<Lane> lanes_[2];
    int lane_count_ = 1, last_lane_ = -1, threads_ = 1;
    bool two_at_once_ = false;  // the default's current choice (in_flight_mode())
    double step_ = 0.0;         // the camera's step between views started, radians, smoothed
    int steps_seen_ = 0;        // steps measured since the sessions were made
    std::deque<int> in_flight_;  // lanes with a view started and not taken, oldest first
    // --fps: the views taken after the first frame, their times and their lanes' CPU time.
    bool measuring_ = false;
    StageTimes view_total_;
    int views_measured_ = 0, views_by_mode_[2] = {0, 0};  // (by views at once when each started)
    double worker_cpu_ = 0.0;
    Clock::time_point last_fresh_{};  // when the last view arrived
    double view_period_ = 0.0;        // moving average of the time between views
    double window_period_ = 0.0;      // moving average of the window's frame time
    bool force_ = false, fraction_dirty_ = false;  // a new view needed though the camera is the same
    int unchanged_ = 0;     // frames in a row without a new view
    std::vector<std::string> style_names_;  // the panel's choices: GL lines, the presets, a --style file
    int style_index_ = 0;
    std::shared_ptr<const Style> style_;     // null: GL lines
    std::vector<std::uint32_t> pixels_;      // the styled drawing of view_
    bool styled_ = false, pixels_new_ = false;
    GLuint image_prog_ = 0, image_tex_ = 0;
    GLuint line_prog_ = 0, mesh_prog_ = 0, line_vao_ = 0, line_vbo_ = 0, mesh_vao_ = 0, mesh_bufs_[2] = {0, 0};
    std::size_t line_capacity_ = 0, last_silhouettes_ = 0;
    double mouse_x_ = 0, mouse_y_ = 0, scroll_ = 0;
    bool hidden_ = false, shading_ = false, panel_ = true, recall_on_ = false;
    float crease_ = 40.0f, fraction_ = 0.05f;
    double recall_ = -1.0;
    StageTimes shown_;
    UiLayer ui_layer_;  // the panel, rasterized again only when it changes
    float panel_overflow_ = 0.0f;  // the panel's widest line past its inner right edge, px (draw_panel)
    ImVec2 panel_size_{0.0f, 0.0f};
    bool panel_drawn_ = false, damaged_ = false;  // the panel shown in the last frame drawn; an expose
    int drawn_w_ = 0, drawn_h_ = 0;               // the framebuffer size of the last frame drawn
    Clock::time_point last_drawn_{};
    // What the panel's statistics show: a snapshot taken a few times a second (numbers that change
    // every frame cannot be read, and would make the panel be rasterized every frame).
    struct PanelNumbers {
        StageTimes times;
        DrawingStats stats;
        double views_per_s = 0.0, fps = 0.0, recall = -1.0;
    } panel_numbers_;
    Clock::time_point panel_numbers_at_{};
    char export_name_[256] = "inkline-view";
    std::string status_, command_;
    bool dirty_ = false, crease_dirty_ = false;  // options changed: a new session next frame
};

std::string Viewer::render_command(const Camera& cam, const std::string& output) const {
    std::string c = "inkline render " + opt_.model_path;
    if (opt_.subdivide > 0) c += " --subdivide=" + std::to_string(opt_.subdivide);
    char buf[64];
    std::snprintf(buf, sizeof buf, " --crease=%g", double(crease_));
    c += buf;
    std::string kinds;
    for (int k = 0; k < kLineKindCount; ++k)
        if (vopt_.features.kinds[k]) kinds += std::string(kinds.empty() ? "" : ",") + to_string(LineKind(k));
    if (kinds.empty()) kinds = "none";
    c += " --lines=" + kinds;
    if (vopt_.visibility == VisibilityMethod::Rays) c += " --visibility=rays";
    if (!vopt_.walk) c += " --no-walk";
    // (Followed exactly from an exhaustive first view, the randomized finder's silhouette is the
    // exhaustive one: render's default finder draws it.)
    if (vopt_.finder.kind == FinderKind::Randomized && !(vopt_.finder.coherence && vopt_.finder.first_full)) {
        std::snprintf(buf, sizeof buf, " --finder=randomized --fraction=%g --seed=%llu", double(fraction_),
                      static_cast<unsigned long long>(vopt_.finder.seed));
        c += buf;
    }
    if (hidden_) c += " --hidden";
    if (style_) c += " --style=" + style_names_[std::size_t(style_index_)];
    return c + " " + camera_flags(cam) + " -o " + output;
}

void Viewer::draw_panel() {
    const Camera& cam = drawn_;
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(360, 0), ImGuiCond_FirstUseEver);
    // (no taller than the window: a scroll bar shows the rest)
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(FLT_MAX, std::max(ImGui::GetIO().DisplaySize.y - 16.0f, 64.0f)));
    ImGui::SetNextWindowBgAlpha(0.8f);  // the drawing shows through; H hides the panel
    ImGui::Begin("inkline (H hides)");
    if (ImGui::CollapsingHeader("Lines", ImGuiTreeNodeFlags_DefaultOpen)) {
        for (int k = 0; k < kLineKindCount; ++k) {
            if (k > 0) ImGui::SameLine();
            dirty_ |= ImGui::Checkbox(to_string(LineKind(k)), &vopt_.features.kinds[k]);
        }
        dirty_ |= ImGui::Checkbox("hidden lines (dashed by QI)", &hidden_);
        ImGui::Checkbox("shading under the lines", &shading_);
        const int before = style_index_;
        if (ImGui::BeginCombo("style", style_names_[std::size_t(style_index_)].c_str())) {
            for (int i = 0; i < int(style_names_.size()); ++i)
                if (ImGui::Selectable(style_names_[std::size_t(i)].c_str(), i == style_index_)) style_index_ = i;
            ImGui::EndCombo();
        }
        if (style_index_ != before) {
            try {
                style_ = style_index_ == 0 ? nullptr
                                           : std::make_shared<const Style>(load_style(style_names_[std::size_t(style_index_)]));
                status_.clear();
            } catch (const Error& e) {
                status_ = e.what();
                style_index_ = before;
            }
            dirty_ = true;  // a style may draw hidden lines: a new session
        }
        if (ImGui::SliderFloat("crease angle", &crease_, 0.0f, 180.0f, "%.1f deg")) crease_dirty_ = true;
    }
    if (ImGui::CollapsingHeader("Finder and visibility", ImGuiTreeNodeFlags_DefaultOpen)) {
        int finder = vopt_.finder.kind == FinderKind::Randomized ? 1 : 0;
        bool changed = ImGui::RadioButton("exhaustive", &finder, 0);
        ImGui::SameLine();
        changed |= ImGui::RadioButton("randomized", &finder, 1);
        if (changed) {
            vopt_.finder.kind = finder ? FinderKind::Randomized : FinderKind::Exhaustive;
            dirty_ = true;
        }
        if (finder) {
            if (ImGui::SliderFloat("fraction", &fraction_, 0.0001f, 1.0f, "%.4f", ImGuiSliderFlags_Logarithmic))
                fraction_dirty_ = true;  // applied when the session is idle
            dirty_ |= ImGui::Checkbox("frame coherence", &vopt_.finder.coherence);
            if (vopt_.finder.coherence)
                dirty_ |= ImGui::Checkbox("exhaustive first view, then followed", &vopt_.finder.first_full);
        }
        int vis = vopt_.visibility == VisibilityMethod::Rays ? 1 : 0;
        changed = ImGui::RadioButton("appel (QI propagation)", &vis, 0);
        ImGui::SameLine();
        changed |= ImGui::RadioButton("rays", &vis, 1);
        if (changed) {
            vopt_.visibility = vis ? VisibilityMethod::Rays : VisibilityMethod::Appel;
            dirty_ = true;
        }
        if (!vis) dirty_ |= ImGui::Checkbox("walk before ray tests", &vopt_.walk);
        if (ImGui::Checkbox("recall against exhaustive (this frame)", &recall_on_)) force_ = true;
    }
    if (ImGui::CollapsingHeader("Statistics", ImGuiTreeNodeFlags_DefaultOpen)) {
        const auto now = Clock::now();
        // (and sooner while the snapshot has no view's numbers yet: a short run's panel showed zeros)
        const bool empty = panel_numbers_.stats.triangles == 0 || panel_numbers_.views_per_s == 0.0;
        if (empty || now - panel_numbers_at_ >= std::chrono::milliseconds(250)) {
            panel_numbers_ = {shown_, stats_, view_period_ > 0 ? 1.0 / view_period_ : 0.0,
                              window_period_ > 0 ? 1.0 / window_period_ : 0.0, recall_};
            panel_numbers_at_ = now;
        }
        const DrawingStats& s = panel_numbers_.stats;
        const StageTimes& t = panel_numbers_.times;
        ImGui::Text("%.1f views/s (pipeline), window %.1f fps", panel_numbers_.views_per_s, panel_numbers_.fps);
        const int at_once = lane_count_ < 2 ? 1 : opt_.in_flight == 2 || two_at_once_ ? 2 : 1;
        ImGui::Text("views at once: %d (%s)", at_once, opt_.in_flight > 0 || lane_count_ < 2 ? "fixed" : "by the camera's step");
        ImGui::Text("features %.2f ms (search %.2f, chain %.2f)", 1e3 * t.features, 1e3 * t.search, 1e3 * t.chain);
        ImGui::Text("visibility %.2f ms, %s %.2f ms", 1e3 * t.visibility, styled_ ? "style + raster" : "line quads",
                    1e3 * t.lines);
        ImGui::Text("  pieces %.2f, propagation %.2f,", 1e3 * t.pieces, 1e3 * t.propagation);
        ImGui::Text("  walks %.2f, ray tests %.2f", 1e3 * t.walks, 1e3 * t.rays);
        ImGui::Text("GL draw + swap %.2f ms%s", 1e3 * t.draw, recall_on_ ? " (+ recall reference)" : "");
        ImGui::Text("%zu triangles, %zu silhouette edges", s.triangles, s.silhouette_edges);
        ImGui::Text("%.3g silhouette edges/s (finder)", s.seconds_features > 0 ? s.silhouette_edges / s.seconds_features : 0.0);
        ImGui::Text("%zu crease, %zu border edges, %zu cusps", s.crease_edges, s.border_edges, s.cusps);
        ImGui::Text("%zu pieces, %zu crossings, %zu clusters", s.pieces, s.crossings, s.clusters);
        ImGui::Text("%zu ray tests, %zu walks", s.ray_tests, s.walks);
        ImGui::Text("clusters decided: %zu box, %zu upper bound,", s.clusters_bbox, s.clusters_bounded);
        ImGui::Text("  %zu occluded, %zu inconsistent", s.clusters_occluded, s.clusters_inconsistent);
        if (recall_on_) ImGui::Text("recall of silhouette length: %.4f", panel_numbers_.recall);
    }
    if (ImGui::CollapsingHeader("Camera and export", ImGuiTreeNodeFlags_DefaultOpen)) {
        ImGui::TextUnformatted("left drag: orbit; right/middle drag: pan");
        ImGui::TextUnformatted("wheel: zoom; H hides this panel");
        ImGui::TextUnformatted("R reset, 1/2/3 front/side/top, O ortho/persp");
        ImGui::Text("%s", rig_.ortho() ? "orthographic" : "perspective");
        ImGui::InputText("file name", export_name_, sizeof export_name_);
        for (const char* label : {"SVG", "PDF", "PNG", "JSON"}) {
            if (label[0] != 'S') ImGui::SameLine();
            if (ImGui::Button(label)) {
                std::string ext = label;
                for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
                export_view(std::string(export_name_) + "." + ext);
            }
        }
        ImGui::SameLine();
        if (ImGui::Button("render command")) {
            command_ = render_command(cam, std::string(export_name_) + ".svg");
            std::printf("%s\n", command_.c_str());
            std::fflush(stdout);
        }
        if (!status_.empty()) ImGui::TextWrapped("%s", status_.c_str());
        if (!command_.empty()) ImGui::TextWrapped("%s", command_.c_str());
    }
    // How far the widest line reaches past where the panel clips its contents (0: every line is
    // whole; more: some text is cut off). Printed with a screenshot of the panel; a test checks it.
    const ImGuiWindow* win = ImGui::GetCurrentWindow();
    panel_overflow_ = std::max(0.0f, win->DC.CursorMaxPos.x - win->InnerClipRect.Max.x);
    panel_size_ = win->Size;
    ImGui::End();
}

void Viewer::export_view(const std::string& path) {
    StageTimes st;
    sync_all(st);  // the newest view, and the lanes idle
    const View& view = *view_;
    const Camera& cam = drawn_;
    OutputOptions oo;
    oo.hidden = hidden_;
    try {
        const Format format = output_format(path, "");
        if (style_ && format != Format::Json) {
            write_styled(stylize_view(model_, cam, view, *style_, hidden_), path, format);
        } else {
            write_drawing(view.drawing, path, format, oo);
        }
        status_ = "wrote " + path;
        command_ = render_command(cam, path);
        std::printf("wrote %s; the same with: %s\n", path.c_str(), command_.c_str());
        std::fflush(stdout);
    } catch (const Error& e) {
        if (opt_.frames > 0) throw;  // headless: the error is the result
        status_ = e.what();
        std::fprintf(stderr, "inkline: %s\n", e.what());
    }
}

}  // namespace

int run_viewer(Model& model, const Camera& home, const ViewerOptions& options) {
    Glfw glfw;
    Viewer viewer(model, home, options);
    return viewer.run();
}

}  // namespace inkline
