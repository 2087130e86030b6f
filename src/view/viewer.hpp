// `inkline view`: the preview window. A GLFW window with an OpenGL 3.3 core context runs the real
// pipeline (ViewSession: features -> visibility, view_scheduler.hpp) on the CPU every frame and
// draws the pieces (gl_scene.hpp) as antialiased line quads (hidden ones grey and dashed by QI),
// optionally over flat-shaded triangles; a Dear ImGui panel sets the options, shows the statistics
// (frame_stats.hpp) and exports the view.
// Headless driving (--frames): N frames, optionally along an orbit, a screenshot of the last one.
#pragma once

#include <string>

#include "core/camera.hpp"
#include "pipeline.hpp"
#include "tone/tone.hpp"
#include "view/detail_source.hpp"
#include "view/tone_pass.hpp"

namespace inkline {

struct ViewerOptions {
    std::string model_path;   // shown in the title and in the printed `inkline render` line
    int subdivide = 0;
    ViewOptions view;         // pipeline options (finder, visibility, line kinds)
    bool hidden = false;      // draw hidden lines
    bool shading = false;     // flat grey triangles under the lines
    std::string style;        // --style NAME|FILE: the drawing stylized as render --style draws it (a
                              // Cairo image shown as a texture); empty: antialiased GL line quads
    bool panel = true;        // the ImGui panel
    int frames = 0;           // > 0: run that many frames, then exit
    bool orbit = false;       // turn the camera along an orbit, `arc` degrees over the frames
    double arc = 90.0;
    std::string screenshot;   // PNG of the last frame's drawing (without the panel)
    bool screenshot_ui = false;  // the screenshot includes the panel
    std::string export_path;  // the last frame exported as the panel's buttons do (SVG/PDF/PNG/JSON)
    bool recall = false;      // recall of silhouette length against the exhaustive finder, per view
    bool fps = false;         // print the measured frames per second and where the time goes
    // Views computed at once, each by its own session on its own thread: 1, 2, or 0 (two sessions
    // where there are two threads, two views at once while the camera moves slowly, one when it
    // moves fast: view_scheduler.hpp). Two: the sessions take the views in turn, the threads split
    // between them: more views a second while each session's follow of its last view (two views
    // back) stays cheap, one frame more behind the camera (bench/results/view_fps.md).
    int in_flight = 0;
    // --detail=PX: the lines of the model's features at about PX pixels, by the multiscale or pm
    // method (view/detail_source.hpp), one view at a time, over a toon-shaded base coat; the
    // panel's slider changes PX live.
    double detail_px = 0.0;
    std::string detail_method = "multiscale";
    double detail_depth = 0.0;
    DetailPreprocess detail_preprocess;  // the levels' options and --cache
    // The tone pass in GLSL (tone_pass.hpp), on when any of its layers is asked: render's
    // --lines=...,tone-dark,tone-highlight and --base=toon, with render's parameters. One light,
    // turning with the camera (the panel's two angles; empty: render's default headlight).
    bool tone_dark = false, tone_highlight = false, toon_base = false;
    tone::ToneOptions tone;
    TonePassMode tone_pass = TonePassMode::Auto;  // --tone-pass: GLSL, or the CPU pass on a software GL
};

// Opens the window on `home` (its size is the window's drawing area) and runs until closed, or
// for options.frames frames. Prints the camera flags of the last frame as `render` does.
// Throws inkline::Error when no window can be opened (no display, no OpenGL 3.3).
int run_viewer(Model& model, const Camera& home, const ViewerOptions& options);

}  // namespace inkline
