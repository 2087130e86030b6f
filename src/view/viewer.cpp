#include "view/viewer.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <imgui_internal.h>  // (the panel window's widest line: ImGuiWindow::DC.CursorMaxPos)

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/clock.hpp"
#include "core/error.hpp"
#include "output/styled.hpp"
#include "output/writers.hpp"
#include "style/style.hpp"
#include "style/styled_view.hpp"
#include "view/camera_rig.hpp"
#include "view/frame_stats.hpp"
#include "view/gl_scene.hpp"
#include "view/tone_pass.hpp"
#include "view/ui_layer.hpp"
#include "view/view_scheduler.hpp"

namespace inkline {

namespace {

using Clock = StageClock;

std::string glfw_error() {
    const char* d = nullptr;
    glfwGetError(&d);
    return d ? d : "unknown GLFW error";
}

struct Glfw {
    Glfw() {
        if (!glfwInit()) throw Error("view", "cannot open a window (no display?): " + glfw_error());
    }
    ~Glfw() { glfwTerminate(); }
    Glfw(const Glfw&) = delete;
    Glfw& operator=(const Glfw&) = delete;
};

// The window with its OpenGL 3.3 core context, current on this thread.
class Window {
public:
    Window(const Camera& home, const ViewerOptions& o) {
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
    }
    ~Window() { glfwDestroyWindow(win_); }
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;
    GLFWwindow* get() const { return win_; }

private:
    GLFWwindow* win_ = nullptr;
};

// Dear ImGui on the window (its GLFW backend chains to the callbacks installed before it).
class ImGuiContextScope {
public:
    explicit ImGuiContextScope(GLFWwindow* win) {
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the user's directory
        ImGui::StyleColorsLight();
        ImGui_ImplGlfw_InitForOpenGL(win, true);
        ImGui_ImplOpenGL3_Init("#version 330 core");
    }
    ~ImGuiContextScope() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    ImGuiContextScope(const ImGuiContextScope&) = delete;
    ImGuiContextScope& operator=(const ImGuiContextScope&) = delete;
};

bool same_camera(const Camera& a, const Camera& b) {
    return a.eye() == b.eye() && a.target() == b.target() && a.up() == b.up() && a.fov_deg() == b.fov_deg() &&
           a.is_ortho() == b.is_ortho() && a.ortho_height() == b.ortho_height() && a.width() == b.width() &&
           a.height() == b.height();
}

// The window: input, the views asked of the scheduler and taken from it, the drawing, the panel.
class Viewer {
public:
    Viewer(Model& model, const Camera& home, const ViewerOptions& o)
        : model_(model), opt_(o), rig_(home, std::as_const(model).topology().bounds), window_(home, o),
          imgui_(with_callbacks(window_.get())), scene_(std::as_const(model).topology()),
          scheduler_(model, o.detail_px > 0.0 ? 1 : o.in_flight, [] { glfwPostEmptyEvent(); }) {
        if (o.detail_px > 0.0)  // (a stateful session: its views one at a time, in order)
            detail_ = std::make_unique<DetailSource>(model, o.detail_method, o.detail_px, o.detail_depth,
                                                     o.detail_preprocess, [] { glfwPostEmptyEvent(); });
        crease_ = float(std::as_const(model).topology().crease_degrees);
        fraction_ = float(o.view.finder.fraction);
        hidden_ = o.hidden;
        shading_ = o.shading;
        panel_ = o.panel;
        recall_on_ = o.recall;
        vopt_ = o.view;
        tone_ = o.tone;
        tone_layers_ = {o.tone_dark, o.tone_highlight, o.toon_base};
        light_ = light_angles(home, o.tone.lights.empty() ? tone::default_light(home) : o.tone.lights[0]);
        style_names_ = {"lines (GL)", "clean", "technical", "sketchy", "charcoal", "ink-brush", "hatched"};
        if (!o.style.empty()) {
            const auto it = std::find(style_names_.begin(), style_names_.end(), o.style);
            if (it == style_names_.end()) style_names_.push_back(o.style);  // a style file
            style_index_ = int(std::find(style_names_.begin(), style_names_.end(), o.style) - style_names_.begin());
            style_ = std::make_shared<const Style>(load_style(o.style));
        }
        rebuild_session();
        if (detail_ && o.frames > 0) start_detail();  // headless: every view with the detail control
    }
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    // The loop is pipelined: while the main thread draws frame k-1 (OpenGL, the panel, the swap),
    // worker threads run the pipeline for frame k's camera (ViewScheduler). The lines drawn are
    // one frame behind the camera (two with two views at once); the shading is drawn at the
    // lines' camera, so the two always agree.
    int run() {
        for (int frame = 0; !glfwWindowShouldClose(window_.get()); ++frame) {
            // Headless: frames 0..N-1 each start the pipeline for one camera; frame N only draws
            // the last result (screenshot, export).
            const bool finishing = opt_.frames > 0 && frame == opt_.frames;
            const auto t0 = Clock::now();
            wait_for_input();
            StageTimes st;
            const bool fresh = take_finished_views(finishing, st);
            if (finishing) frame_stats_.stop_clock();
            apply_option_changes();
            if (detail_ && !detail_live_ && detail_->ready()) start_detail();
            if (opt_.frames > 0 && opt_.orbit && frame > 0 && !finishing) rig_.orbit(opt_.arc / opt_.frames, 0.0);
            int w = 0, h = 0;
            if (!begin_frame(w, h)) continue;  // minimised
            schedule_view(rig_.camera(w, h), fresh, finishing, st);
            if (!draw_frame(w, h, fresh, finishing, st)) continue;
            st.frame = seconds_since(t0);
            frame_stats_.frame_drawn(st, fresh, frame, finishing);
            if (finishing) break;
        }
        StageTimes st;
        take_all(st);  // views still in flight (window closed)
        if (opt_.fps)
            frame_stats_.print_report({std::as_const(model_).topology().face_count(), scheduler_.threads(), shown_.lines.size(),
                                       opt_.frames == 0});
        if (opt_.fps && tone_pass_ && tone_pass_->runs() > 0) {
            const TonePass::Times& t = tone_pass_->summed_times();
            const double n = double(tone_pass_->runs()) / 1e3;
            std::printf("tone pass (%s, each pass finished): %zu runs, mean ms: shade %.2f, blur %.2f, ridges %.2f, "
                        "total %.2f\n", tone_pass_->on_cpu() ? "CPU" : "GLSL", tone_pass_->runs(), t.shade / n, t.blur / n, t.ridges / n, t.total() / n);
        }
        // Interactive, the camera may have moved after the last view was drawn: the rig's is printed.
        const Camera& drawn = shown_.camera;
        const Camera final_camera = opt_.frames > 0 ? drawn : rig_.camera(drawn.width(), drawn.height());
        std::printf("camera: %s\n", camera_flags(final_camera).c_str());
        return 0;
    }

private:
    // Our GLFW callbacks, installed before ImGui's backend (which chains to them).
    GLFWwindow* with_callbacks(GLFWwindow* win) {
        glfwSetWindowUserPointer(win, this);
        glfwSetScrollCallback(win, [](GLFWwindow* w, double, double dy) {
            static_cast<Viewer*>(glfwGetWindowUserPointer(w))->scroll_ += dy;
        });
        glfwSetWindowRefreshCallback(win, [](GLFWwindow* w) {
            static_cast<Viewer*>(glfwGetWindowUserPointer(w))->damaged_ = true;  // contents lost: draw again
        });
        glfwSetKeyCallback(win, [](GLFWwindow* w, int key, int, int action, int) {
            if (action == GLFW_PRESS) static_cast<Viewer*>(glfwGetWindowUserPointer(w))->key(key);
        });
        return win;
    }

    // Idle for a few frames (the panel settles after an event): sleeps until input. Interactive,
    // the window does not wait for the pipeline: it draws the last view while the next one is
    // computed (the panel and the camera stay responsive on big meshes), yielding the CPU to the
    // pipeline between its frames. The pipeline wakes the loop when its view is done (an empty
    // event), so waiting for it costs no polling; input wakes it too.
    void wait_for_input() {
        const bool interactive = opt_.frames == 0;
        const bool busy = scheduler_.in_flight() > 0;
        const bool asleep = interactive && unchanged_ > 3 && !busy;
        frame_stats_.slept(asleep);
        if (asleep) glfwWaitEventsTimeout(0.5);
        else if (interactive && busy && !scheduler_.oldest_done()) glfwWaitEventsTimeout(0.05);
        else glfwPollEvents();
    }

    // Views are taken in the order they were started. Interactive: the oldest when it is done.
    // Headless: lock-step, the oldest view taken once every lane is busy (one frame behind with
    // one lane, two with two), and all of them at the last frame. Returns whether one was taken.
    bool take_finished_views(bool finishing, StageTimes& st) {
        bool fresh = false;
        if (finishing) fresh = take_all(st);
        else if (opt_.frames == 0 ? scheduler_.oldest_done() : scheduler_.in_flight() >= scheduler_.views_at_once())
            fresh = take(st);
        if (fresh) frame_stats_.view_arrived();
        return fresh;
    }

    // Options change only while the sessions are idle.
    void apply_option_changes() {
        if (crease_dirty_ || fraction_dirty_ || surface_dirty_) {
            StageTimes ignored;
            take_all(ignored);
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
            scheduler_.set_fraction(fraction_);
            fraction_dirty_ = false;
            force_ = true;
        }
        if (surface_dirty_) {  // the same sessions: only the lines' extraction changes
            scheduler_.set_surface_lines(vopt_.surface);
            if (detail_live_) detail_->reset(vopt_);
            surface_dirty_ = false;
            force_ = true;
        }
    }

    // The panel's frame begun and the mouse read; `w` x `h` the framebuffer. False when the
    // window is minimised (then it has waited for an event).
    bool begin_frame(int& w, int& h) {
        if (panel_) {
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
        }
        mouse();
        glfwGetFramebufferSize(window_.get(), &w, &h);
        if (w >= 1 && h >= 1) return true;
        if (panel_) ImGui::EndFrame();
        glfwWaitEvents();
        return false;
    }

    // Starts a view at `cam` when a lane is free and the view would differ from the newest (started
    // or drawn); interactive and nothing changed, the last view and its quads are still right.
    void schedule_view(const Camera& cam, bool fresh, bool finishing, StageTimes& st) {
        const bool busy = scheduler_.in_flight() > 0;
        const Camera& newest = busy ? scheduler_.newest_camera() : shown_.camera;
        const bool morphing = detail_live_ && detail_->morphing();  // geomorphs run on at a still camera
        const bool again = opt_.frames == 0 && !force_ && !morphing && shown_.view && same_camera(cam, newest);
        unchanged_ = again && !fresh && !busy ? unchanged_ + 1 : 0;
        if (!again && !finishing && scheduler_.in_flight() < scheduler_.views_at_once()) {
            ViewRequest request;
            request.camera = cam;
            request.lines.hidden = hidden_;
            request.lines.simplify_px = 0.25;  // invisible at the line widths drawn, fewer triangles
            request.style = style_;
            request.hidden = hidden_;
            request.recall = recall_on_;
            request.kinds = vopt_.features;
            request.detail = detail_live_ ? detail_.get() : nullptr;
            scheduler_.start(request);
            force_ = false;
        }
        if (!shown_.view) take(st);  // nothing to draw yet (first frame, new sessions): wait for it
    }

    // The panel, the view's drawing, the screenshot and export of the last headless frame, the
    // swap (st.draw: their time). Interactive, a frame that would show nothing new is not drawn
    // (returns false): no new view (the lines are drawn at their view's camera, not the rig's), the
    // panel unchanged and the window not damaged; redrawing would take the software rasterizer's
    // CPU from the pipeline (bench/results/view_fps.md, "the panel as a layer").
    bool draw_frame(int w, int h, bool fresh, bool finishing, StageTimes& st) {
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
        const bool resized = w != drawn_w_ || h != drawn_h_;
        const bool redraw = opt_.frames > 0 || fresh || panel_changed || damaged_ || resized;
        if (!redraw) return false;
        damaged_ = false;
        drawn_w_ = w, drawn_h_ = h;
        const Camera& drawn = shown_.camera;
        std::function<void()> underlay;  // in place of the shading: the tone pass, or the detail's coat
        if (tone_on()) underlay = [&] { draw_tone(drawn); };
        else if (shown_.has_coat) underlay = [&] { coat_.draw(drawn, shown_.coat, fresh); };
        scene_.draw(drawn, shading_, shown_.lines, shown_.styled ? &shown_.pixels : nullptr, underlay);
        const bool shot = finishing && !opt_.screenshot.empty();
        if (shot && !opt_.screenshot_ui) save_screenshot(opt_.screenshot, drawn.width(), drawn.height());
        if (panel_) ui_layer_.composite();
        if (shot && opt_.screenshot_ui) {
            save_screenshot(opt_.screenshot, drawn.width(), drawn.height());
            if (panel_)
                std::printf("panel: %.0f x %.0f px, its widest line %.0f px past its clipped edge\n", panel_size_.x,
                            panel_size_.y, panel_overflow_);
        }
        if (finishing && !opt_.export_path.empty()) export_view(opt_.export_path);
        glfwSwapBuffers(window_.get());
        st.draw = seconds_since(td);
        return true;
    }

    void rebuild_session() {
        vopt_.exact_hidden = hidden_ || (style_ && style_->draw_hidden);
        vopt_.finder.fraction = fraction_;
        StageTimes st;
        take_all(st);  // never while the old sessions are in use
        scheduler_.reset(vopt_);
        if (detail_live_) detail_->reset(vopt_);
        shown_.view = nullptr;  // it belonged to an old session
    }

    // The detail control's pre-process is done (or waited for): its sessions made, views from now
    // on drawn by it. Until then the window draws the model as it is (the same lines as without
    // --detail) and the panel shows the pre-process's progress.
    void start_detail() {
        detail_->wait_ready();  // (throws what the pre-process threw)
        if (!detail_->cache_warning().empty())
            std::fprintf(stderr, "inkline: warning: --cache: %s\n", detail_->cache_warning().c_str());
        detail_->reset(vopt_);  // (no view of it can be in flight: none was started)
        detail_live_ = true;
        force_ = true;
    }

    // Waits for the oldest view in flight, if any, and makes it the one drawn. Returns whether
    // there was one.
    bool take(StageTimes& st) {
        if (!scheduler_.take_oldest(shown_)) return false;
        st.wait += shown_.waited;
        st.add(shown_.times);  // (st may gather several views: take_all)
        if (shown_.styled) scene_.image_changed();
        frame_stats_.view_taken(shown_.times, shown_.views_at_once, shown_.cpu, shown_.stats.silhouette_edges);
        return true;
    }

    // Every view in flight taken, oldest first (the lanes idle after). Returns whether there was one.
    bool take_all(StageTimes& st) {
        bool any = false;
        while (take(st)) any = true;
        return any;
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
            case GLFW_KEY_Q: glfwSetWindowShouldClose(window_.get(), GLFW_TRUE); break;
            default: break;
        }
    }

    void mouse() {
        double x = 0, y = 0;
        glfwGetCursorPos(window_.get(), &x, &y);
        const double dx = x - mouse_x_, dy = y - mouse_y_;
        mouse_x_ = x;
        mouse_y_ = y;
        const bool ui = panel_ && ImGui::GetIO().WantCaptureMouse;
        const double scroll = scroll_;
        scroll_ = 0.0;
        if (ui) return;
        if (scroll != 0.0) rig_.zoom(scroll);
        int h = 0;
        glfwGetWindowSize(window_.get(), nullptr, &h);
        if (glfwGetMouseButton(window_.get(), GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) rig_.orbit(-0.4 * dx, -0.4 * dy);
        else if (glfwGetMouseButton(window_.get(), GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
                 glfwGetMouseButton(window_.get(), GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS)
            rig_.pan(dx, dy, h);
    }

    bool tone_on() const { return tone_layers_.dark || tone_layers_.highlight || tone_layers_.base; }
    // The tone pass's options at `cam`: the panel's light turned into a world direction.
    tone::ToneOptions tone_options(const Camera& cam) const {
        tone::ToneOptions o = tone_;
        o.lights = {light_direction(cam, light_)};
        return o;
    }
    void draw_tone(const Camera& cam) {
        if (!tone_pass_) tone_pass_ = std::make_unique<TonePass>(std::as_const(model_).topology(), opt_.tone_pass, vopt_.threads);
        tone_pass_->draw(cam, tone_options(cam), tone_layers_);
    }
    void add_tone_lines(const Camera& cam, Drawing& d) const;
    std::string tone_flags(const Camera& cam) const;  // render's flags for the tone pass shown

    void draw_panel();
    void panel_lines();
    void panel_detail();
    void panel_tone();
    void panel_surface_lines();
    void panel_finder();
    void panel_statistics();
    void panel_camera_and_export();
    // Writes the current drawing (format from the extension) and prints the `render` line for it.
    void export_view(const std::string& path);
    std::string render_command(const Camera& cam, const std::string& output) const;

    Model& model_;
    ViewerOptions opt_;
    CameraRig rig_;
    // (in this order: the window and ImGui made first and destroyed last, the GL objects of the
    // scene and the panel's layer before them, the lanes' threads stopped first)
    Window window_;
    ImGuiContextScope imgui_;
    GlScene scene_;
    std::unique_ptr<DetailSource> detail_;  // --detail
    bool detail_live_ = false;              // its pre-process done and its sessions made
    ToonCoat coat_;
    UiLayer ui_layer_;  // the panel, rasterized again only when it changes
    std::unique_ptr<TonePass> tone_pass_;  // the tone pass's GL objects, made on first use
    ViewScheduler scheduler_;
    FrameStats frame_stats_;
    ViewOptions vopt_;
    FinishedView shown_;  // the view drawn (its view is null after new sessions), at shown_.camera
    bool force_ = false, fraction_dirty_ = false, surface_dirty_ = false;  // a new view needed though the camera is the same
    int unchanged_ = 0;     // frames in a row without a new view
    std::vector<std::string> style_names_;  // the panel's choices: GL lines, the presets, a --style file
    int style_index_ = 0;
    std::shared_ptr<const Style> style_;     // null: GL lines
    double mouse_x_ = 0, mouse_y_ = 0, scroll_ = 0;
    bool hidden_ = false, shading_ = false, panel_ = true, recall_on_ = false;
    float crease_ = 40.0f, fraction_ = 0.05f;
    float panel_overflow_ = 0.0f;  // the panel's widest line past its inner right edge, px (draw_panel)
    ImVec2 panel_size_{0.0f, 0.0f};
    bool panel_drawn_ = false, damaged_ = false;  // the panel shown in the last frame drawn; an expose
    int drawn_w_ = 0, drawn_h_ = 0;               // the framebuffer size of the last frame drawn
    tone::ToneOptions tone_;  // the tone pass's parameters (its lights from light_)
    ToneLayers tone_layers_;
    LightAngles light_;
    char export_name_[256] = "inkline-view";
    std::string status_, command_;
    bool dirty_ = false, crease_dirty_ = false;  // options changed: new sessions next frame
};

std::string Viewer::render_command(const Camera& cam, const std::string& output) const {
    std::string c = "inkline render " + opt_.model_path;
    if (opt_.subdivide > 0) c += " --subdivide=" + std::to_string(opt_.subdivide);
    char buf[64];
    std::snprintf(buf, sizeof buf, " --crease=%g", double(crease_));
    c += buf;
    std::string kinds;
    auto add_kind = [&](LineKind k) { kinds += std::string(kinds.empty() ? "" : ",") + to_string(k); };
    for (int k = 0; k < kLineKindCount; ++k)
        if (vopt_.features.kinds[k]) add_kind(LineKind(k));
    const SurfaceLineOptions& s = vopt_.surface;
    if (s.suggestive) add_kind(LineKind::Suggestive);
    if (s.smooth_contour) add_kind(LineKind::SmoothContour);
    if (s.ridge) add_kind(LineKind::Ridge);
    if (s.valley) add_kind(LineKind::Valley);
    if (vopt_.features.intersection) add_kind(LineKind::Intersection);
    if (tone_layers_.dark) add_kind(LineKind::ToneDark);
    if (tone_layers_.highlight) add_kind(LineKind::ToneHighlight);
    c += " --lines=" + kinds;
    c += tone_flags(cam);  // (empty: no line kind, as render takes it)
    if (s.suggestive && s.suggestive_threshold != SurfaceLineOptions{}.suggestive_threshold) {
        std::snprintf(buf, sizeof buf, " --suggestive-threshold=%.17g", s.suggestive_threshold);
        c += buf;
    }
    if ((s.ridge || s.valley) && s.ridge_threshold != SurfaceLineOptions{}.ridge_threshold) {
        std::snprintf(buf, sizeof buf, " --ridge-threshold=%.17g", s.ridge_threshold);
        c += buf;
    }
    if (vopt_.visibility == VisibilityMethod::Rays) c += " --visibility=rays";
    if (vopt_.visibility == VisibilityMethod::Fast) c += " --visibility=fast";
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
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(360, 0), ImGuiCond_FirstUseEver);
    // (no taller than the window: a scroll bar shows the rest)
    ImGui::SetNextWindowSizeConstraints(ImVec2(0, 0), ImVec2(FLT_MAX, std::max(ImGui::GetIO().DisplaySize.y - 16.0f, 64.0f)));
    ImGui::SetNextWindowBgAlpha(0.8f);  // the drawing shows through; H hides the panel
    ImGui::Begin("inkline (H hides)");
    if (ImGui::CollapsingHeader("Lines", ImGuiTreeNodeFlags_DefaultOpen)) panel_lines();
    if (detail_ && ImGui::CollapsingHeader("Detail", ImGuiTreeNodeFlags_DefaultOpen)) panel_detail();
    if (ImGui::CollapsingHeader("Tone lines (abstracted shading)", tone_on() ? ImGuiTreeNodeFlags_DefaultOpen : 0))
        panel_tone();
    if (ImGui::CollapsingHeader("Finder and visibility", ImGuiTreeNodeFlags_DefaultOpen)) panel_finder();
    if (ImGui::CollapsingHeader("Statistics", ImGuiTreeNodeFlags_DefaultOpen)) panel_statistics();
    if (ImGui::CollapsingHeader("Camera and export", ImGuiTreeNodeFlags_DefaultOpen)) panel_camera_and_export();
    // How far the widest line reaches past where the panel clips its contents (0: every line is
    // whole; more: some text is cut off). Printed with a screenshot of the panel; a test checks it.
    const ImGuiWindow* win = ImGui::GetCurrentWindow();
    panel_overflow_ = std::max(0.0f, win->DC.CursorMaxPos.x - win->InnerClipRect.Max.x);
    panel_size_ = win->Size;
    ImGui::End();
}

// Lines from the surface's curvature: toggles and thresholds, applied from the next view on.
void Viewer::panel_surface_lines() {
    SurfaceLineOptions& s = vopt_.surface;
    surface_dirty_ |= ImGui::Checkbox("suggestive", &s.suggestive);
    ImGui::SameLine();
    surface_dirty_ |= ImGui::Checkbox("smooth contour", &s.smooth_contour);
    surface_dirty_ |= ImGui::Checkbox("ridge", &s.ridge);
    ImGui::SameLine();
    surface_dirty_ |= ImGui::Checkbox("valley", &s.valley);
    if (s.suggestive) {
        float t = float(s.suggestive_threshold);
        if (ImGui::SliderFloat("SC threshold", &t, 0.0f, 1.0f, "%.3f", ImGuiSliderFlags_Logarithmic)) {
            s.suggestive_threshold = t;
            surface_dirty_ = true;
        }
    }
    if (s.ridge || s.valley) {
        float t = float(s.ridge_threshold);
        if (ImGui::SliderFloat("RV threshold", &t, 0.0f, 2.0f, "%.3f", ImGuiSliderFlags_Logarithmic)) {
            s.ridge_threshold = t;
            surface_dirty_ = true;
        }
    }
}

// The detail's target size (applied from the next view) and what the last view made of it.
void Viewer::panel_detail() {
    float px = float(detail_->target());
    if (ImGui::SliderFloat("target px", &px, 0.5f, 64.0f, "%.1f", ImGuiSliderFlags_Logarithmic)) {
        detail_->set_target(px);
        force_ = true;
    }
    if (detail_live_) {
        ImGui::TextUnformatted(detail_->summary().c_str());
        return;
    }
    ImGui::TextUnformatted(detail_->preparation_text().c_str());
    ImGui::ProgressBar(float(detail_->preparation_fraction()));
    ImGui::TextUnformatted("(drawn at full detail until then)");
}

void Viewer::panel_lines() {
    for (int k = 0; k < kLineKindCount; ++k) {
        if (k > 0) ImGui::SameLine();
        dirty_ |= ImGui::Checkbox(to_string(LineKind(k)), &vopt_.features.kinds[k]);
    }
    dirty_ |= ImGui::Checkbox("intersection", &vopt_.features.intersection);
    panel_surface_lines();
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

// The tone pass's layers and parameters (tone::ToneOptions, as render's --tone-* flags take
// them); a slider's value rounded to the digits it shows, so the printed render command is short.
void Viewer::panel_tone() {
    ImGui::Checkbox("tone-dark", &tone_layers_.dark);
    ImGui::SameLine();
    ImGui::Checkbox("tone-highlight", &tone_layers_.highlight);
    ImGui::SameLine();
    ImGui::Checkbox("toon base", &tone_layers_.base);
    if (!tone_on()) return;
    const auto slider = [](const char* label, double& value, float lo, float hi, const char* format, double step,
                           ImGuiSliderFlags flags = 0) {
        float v = float(value);
        if (!ImGui::SliderFloat(label, &v, lo, hi, format, flags)) return;
        value = std::max(double(lo), std::round(double(v) / step) * step);
    };
    const auto thresholds = [](const char* label, double& lower, double& upper) {
        float v[2] = {float(lower), float(upper)};
        if (!ImGui::SliderFloat2(label, v, 0.0f, 0.5f, "%.3f", ImGuiSliderFlags_Logarithmic)) return;
        const double lo = std::round(double(v[0]) * 1e3) / 1e3, hi = std::round(double(v[1]) * 1e3) / 1e3;
        // c_l <= c_u: the edited one pushes the other
        if (lo != lower) lower = lo, upper = std::max(upper, lo);
        else upper = hi, lower = std::min(lower, hi);
    };
    // (narrower sliders: the labels are longer than the other sections')
    ImGui::PushItemWidth(-(ImGui::CalcTextSize("highlight c_l, c_u").x + ImGui::GetStyle().ItemInnerSpacing.x));
    slider("w (line width)", tone_.width, 1.0f, 32.0f, "%.1f px", 0.1);
    slider("beta", tone_.beta, 0.0f, 1.0f, "%.2f", 0.01);
    thresholds("dark c_l, c_u", tone_.dark_lower, tone_.dark_upper);
    thresholds("highlight c_l, c_u", tone_.highlight_lower, tone_.highlight_upper);
    slider("light azimuth", light_.azimuth_deg, -180.0f, 180.0f, "%.0f deg", 1.0);
    slider("light elevation", light_.elevation_deg, -90.0f, 90.0f, "%.0f deg", 1.0);
    slider("specular exponent", tone_.specular_exponent, 1.0f, 1000.0f, "%.0f", 1.0, ImGuiSliderFlags_Logarithmic);
    ImGui::SliderInt("toon bands", &tone_.toon_bands, 2, 4);
    int width_by = int(tone_.width_by);
    if (ImGui::Combo("line width by", &width_by, "constant\0depth\0edge length\0")) tone_.width_by = tone::ToneWidthBy(width_by);
    ImGui::PopItemWidth();
    ImGui::Checkbox("distance fall-off", &tone_.distance_falloff);
    ImGui::SameLine();
    ImGui::Checkbox("counterchange", &tone_.counterchange);
}

std::string Viewer::tone_flags(const Camera& cam) const {
    if (!tone_on()) return "";
    const tone::ToneOptions d;
    std::string c = tone_layers_.base ? " --base=toon" : "";
    char buf[160];
    const auto number = [&](const char* flag, double v, double def) {
        if (v == def) return;
        std::snprintf(buf, sizeof buf, " %s=%g", flag, v);
        c += buf;
    };
    const auto pair = [&](const char* flag, double lo, double hi, double dlo, double dhi) {
        if (lo == dlo && hi == dhi) return;
        std::snprintf(buf, sizeof buf, " %s=%g,%g", flag, lo, hi);
        c += buf;
    };
    number("--tone-width", tone_.width, d.width);
    number("--tone-beta", tone_.beta, d.beta);
    pair("--tone-dark", tone_.dark_lower, tone_.dark_upper, d.dark_lower, d.dark_upper);
    pair("--tone-highlight", tone_.highlight_lower, tone_.highlight_upper, d.highlight_lower, d.highlight_upper);
    number("--specular", tone_.specular_exponent, d.specular_exponent);
    number("--toon-bands", tone_.toon_bands, d.toon_bands);
    if (tone_.width_by != d.width_by)
        c += tone_.width_by == tone::ToneWidthBy::Depth ? " --tone-line-width=depth" : " --tone-line-width=edge-length";
    const glm::dvec3 l = light_direction(cam, light_);
    std::snprintf(buf, sizeof buf, " --light=%.17g,%.17g,%.17g", l.x, l.y, l.z);
    return c + buf;
}

// render's tone pass on the CPU at `cam`: the traced lines (vectors) and the base coat join the
// export, as `inkline render` adds them.
void Viewer::add_tone_lines(const Camera& cam, Drawing& d) const {
    tone::ToneResult result;
    tone::ToneOptions o = tone_options(cam);
    o.threads = std::max(1, vopt_.threads);
    tone::render_tone(std::as_const(model_).topology(), tone::prepare_tone_mesh(std::as_const(model_).topology()), cam, o, tone_layers_.dark,
                      tone_layers_.highlight, result);
    std::uint32_t curves = 0;  // numbered after the drawing's curves
    for (const Piece& p : d.pieces) curves = std::max(curves, p.curve + 1);
    for (Piece& p : result.pieces) {
        p.curve += curves;
        d.pieces.push_back(std::move(p));
    }
    d.stats.pieces = d.pieces.size();
    if (tone_layers_.base) d.base = tone::toon_base(result.tone_blurred, result.shaded.covered, o.toon_bands);
}

void Viewer::panel_finder() {
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
    int vis = int(vopt_.visibility == VisibilityMethod::Rays) + 2 * int(vopt_.visibility == VisibilityMethod::Fast);
    changed = ImGui::RadioButton("appel (QI propagation)", &vis, 0);
    ImGui::SameLine();
    changed |= ImGui::RadioButton("rays", &vis, 1);
    changed |= ImGui::RadioButton("fast (depth buffer)", &vis, 2);  // (its own line: the panel's width)
    if (changed) {
        vopt_.visibility = vis == 1 ? VisibilityMethod::Rays : vis == 2 ? VisibilityMethod::Fast : VisibilityMethod::Appel;
        dirty_ = true;
    }
    if (vis == 2) ImGui::TextUnformatted("fast: hidden lines at QI 1 (a lower bound)");
    if (!vis) dirty_ |= ImGui::Checkbox("walk before ray tests", &vopt_.walk);
    if (ImGui::Checkbox("recall against exhaustive (this frame)", &recall_on_)) force_ = true;
}

void Viewer::panel_statistics() {
    const PanelNumbers& numbers = frame_stats_.panel_numbers(shown_.stats, shown_.recall);
    const DrawingStats& s = numbers.stats;
    const StageTimes& t = numbers.times;
    if (numbers.still)  // (no view asked and the window sleeps: a rate would be stale or zero)
        ImGui::TextUnformatted("still: no view asked, window drawn on input");
    else
        ImGui::Text("%.1f views/s (pipeline), window %.1f fps", numbers.views_per_s, numbers.fps);
    ImGui::Text("views at once: %d (%s)", scheduler_.views_at_once_now(),
                scheduler_.fixed() ? "fixed" : "by the camera's step");
    ImGui::Text("features %.2f ms (search %.2f, chain %.2f)", 1e3 * t.features, 1e3 * t.search, 1e3 * t.chain);
    ImGui::Text("visibility %.2f ms, %s %.2f ms", 1e3 * t.visibility, shown_.styled ? "style + raster" : "line quads",
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
    if (recall_on_) ImGui::Text("recall of silhouette length: %.4f", numbers.recall);
    if (tone_on() && tone_pass_) {
        const TonePass::Times& tt = tone_pass_->last_times();
        ImGui::Text("tone pass on the %s: %.1f ms", tone_pass_->on_cpu() ? "CPU" : "GPU (GLSL)", 1e3 * tt.total());
        ImGui::Text("  shade %.1f, blur %.1f,", 1e3 * tt.shade, 1e3 * tt.blur);
        ImGui::Text("  ridges and composite %.1f", 1e3 * tt.ridges);
    }
}

void Viewer::panel_camera_and_export() {
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
        command_ = render_command(shown_.camera, std::string(export_name_) + ".svg");
        std::printf("%s\n", command_.c_str());
        std::fflush(stdout);
    }
    if (!status_.empty()) ImGui::TextWrapped("%s", status_.c_str());
    if (!command_.empty()) ImGui::TextWrapped("%s", command_.c_str());
}

void Viewer::export_view(const std::string& path) {
    StageTimes st;
    take_all(st);  // the newest view, and the lanes idle
    const View& view = *shown_.view;
    const Camera& cam = shown_.camera;
    OutputOptions oo;
    oo.hidden = hidden_;
    try {
        const Format format = output_format(path, "");
        if (style_ && format != Format::Json) {
            write_styled(stylize_view(model_, cam, view, *style_, hidden_), path, format);
        } else if (tone_on()) {
            Drawing d = view.drawing;
            add_tone_lines(cam, d);
            write_drawing(d, path, format, oo);
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
