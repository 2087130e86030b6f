// `inkline view MODEL ...`: parses the flags (camera, lines, finder and visibility defined once
// for every command in app/flags.hpp) and opens the preview window (src/view/).
#include <string>

#include "app/cli.hpp"
#include "app/flags.hpp"
#include "core/error.hpp"
#include "detail/cache_file.hpp"
#include "style/style.hpp"
#include "output/writers.hpp"
#include "pipeline.hpp"
#include "view/viewer.hpp"

namespace inkline {

int run_view(int argc, char** argv) {
    ViewerOptions o;
    std::string model_path;
    CameraFlags camera;
    double crease = 40.0;
    bool strict = false;  // --strict: refuse what tolerant loading repairs
    bool frames_given = false, lines_given = false;
    ToneKinds tone_kinds;
    std::vector<glm::dvec3> lights;
    // A window follows one camera path: its randomized finder starts from an exhaustive view by
    // default (then follows it exactly), since a first view with holes keeps them, and each hole
    // leaves a cluster inconsistent, decided by a ray test per piece.
    o.view.finder.first_full = true;
    // Frame coherence on by default: that first view, then the silhouette followed from view to
    // view (exact, so the window still draws what `render` writes, and cheaper than a scan while
    // the camera moves a few degrees a frame). Every hardware thread for the views (the same
    // drawing; the scheduler divides them between two views in flight).
    o.view.finder.kind = FinderKind::Randomized;
    o.view.finder.coherence = true;
    o.view.threads = hardware_threads();
    camera.height = 768;  // a window of 1024x768 unless --size says otherwise
    FlagTable flags("view", "view MODEL [FLAGS]",
                    "A window that draws MODEL's lines live while you turn the camera (drag: orbit, right drag: "
                    "pan, wheel: zoom), with the same pipeline as render.");
    flags.group("Camera (default framed: the whole model in view, fov 30, +Y up)")
        .add(camera_flags(camera));
    flags.group("Lines")
        .add(lines_flag(o.view.features, o.view.surface, &lines_given, &tone_kinds))
        .add(crease_flag(crease))
        .add(suggestive_threshold_flag(o.view.surface))
        .add(ridge_threshold_flag(o.view.surface))
        .add(switch_flag("--hidden", o.hidden, true, "also draw hidden lines (grey, dashed by QI)"))
        .add(subdivide_flag(o.subdivide))
        .add(strict_flag(strict))
        .add(switch_flag("--shading", o.shading, true, "flat grey triangles under the lines"));
    flags.group("Tone lines (--lines=...,tone-dark,tone-highlight) and base coat, in GLSL: docs/tone.md")
        .add(tone_flags(o.tone, o.toon_base))
        .add(light_flag(lights))
        .add({"--tone-pass", "auto|glsl|cpu",
              "where the tone pass runs: GLSL, or render's CPU pass on every thread (auto, the default: the CPU "
              "where OpenGL is a software renderer, which runs the C++ pass several times faster)",
              [&o](const std::string& v) {
                  if (v == "auto") o.tone_pass = TonePassMode::Auto;
                  else if (v == "glsl") o.tone_pass = TonePassMode::Glsl;
                  else if (v == "cpu") o.tone_pass = TonePassMode::Cpu;
                  else throw Error("--tone-pass", "unknown place '" + v + "' (expected auto, glsl or cpu)");
              }});
    flags.group("Silhouette finder (default: randomized with frame coherence, from an exhaustive first view)")
        .add(finder_flag(o.view.finder.kind))
        .add(fraction_flag(o.view.finder.fraction))
        .add(seed_flag(o.view.finder.seed))
        .add(first_view_flag(o.view.finder.first_full))
        .add(switch_flag("--no-coherence", o.view.finder.coherence, false,
                         "randomized: search every view afresh instead of following the last one"))
        .add(switch_flag("--recall", o.recall, true, "recall of silhouette length against the exhaustive finder"));
    flags.group("Visibility")
        .add(visibility_flag(o.view.visibility))
        .add(fast_buffer_flag(o.view.fast.buffer_px))
        .add(switch_flag("--no-walk", o.view.walk, false, "appel: a ray test where a walk on the surface would do"))
        .add(threads_flag(o.view.threads, "the machine's hardware threads"))
        .add({"--in-flight", "1|2",
              "views computed at once (default: two while the camera moves less than about a degree a view, "
              "else one on every thread)",
              [&o](const std::string& v) { o.in_flight = parse_integer("--in-flight", v, 1, 2); }});
    DetailFlags detail;
    flags.group("Detail control (live: the panel's slider changes the target; docs/progressive_mesh.md)")
        .add(detail_flags(detail));
    flags.group("Style").add(style_flag(o.style));
    flags.group("Window")
        .add(switch_flag("--no-panel", o.panel, false, "hide the settings panel"))
        .add(frames_flag(o.frames, "run N frames, then exit", &frames_given))
        .add(orbit_flag(o.orbit, "with --frames: turn the camera along an orbit"))
        .add(arc_flag(o.arc, "with --orbit: degrees turned over the frames"))
        .add({"--screenshot", "FILE.png", "with --frames: the last frame's drawing as PNG",
              [&o](const std::string& v) {
                  if (v.empty()) throw Error("--screenshot", "expected a file name");
                  o.screenshot = v;
              }})
        .add(switch_flag("--screenshot-ui", o.screenshot_ui, true, "the screenshot includes the panel"))
        .add({"--export", "FILE", "with --frames: the last frame written as .svg, .pdf, .png or .json",
              [&o](const std::string& v) {
                  if (v.empty()) throw Error("--export", "expected a file name");
                  output_format(v, "");  // refuse an unknown format before any work
                  o.export_path = v;
              }})
        .add(switch_flag("--fps", o.fps, true, "with --frames: print the frames per second and where the time goes"));
    if (!flags.parse(argc, argv, 2, model_path)) return 0;  // --help
    detail.check("view");
    if (detail.levels || detail.ratio) throw Usage("--levels and --detail-ratio: render and bench only for now", "view");
    o.detail_px = detail.target_px;
    o.detail_method = detail.method;
    o.detail_depth = detail.depth_exponent.value_or(0.0);
    if (!detail.object_target_px.empty()) throw Usage("--detail-object: render and bench only for now", "view");
    o.detail_preprocess = {.levels = detail.levels_options(), .cache_dir = detail.cache_dir, .model_path = model_path,
                           .variant = loader_variant(o.subdivide, strict)};
    check_fast_visibility(o.view.visibility, o.hidden, "--hidden");
    bool style_kinds = false;  // the style chose the line kinds
    if (!o.style.empty()) {  // a bad style file fails before the window opens
        const Style style = load_style(o.style);
        if (!lines_given && !style.kinds.empty()) set_line_kinds(style.kinds, o.view.features, o.view.surface, &tone_kinds);
        style_kinds = !style.kinds.empty();
    }
    if (!frames_given && (o.orbit || !o.screenshot.empty() || o.fps || !o.export_path.empty()))
        throw Usage("--orbit, --screenshot, --export and --fps drive the window for --frames=N frames", "view");
    if (lights.size() > 1) throw BadValue("--light: the window takes one light (its panel turns it); render takes several");
    o.tone.lights = lights;
    o.tone_dark = tone_kinds.dark;
    o.tone_highlight = tone_kinds.highlight;
    if (const std::string e = tone::tone_options_error(o.tone); !e.empty()) throw BadValue(e);
    o.model_path = model_path;
    Model model = load_model_file(model_path, strict, crease, o.subdivide, true, o.view.threads);
    default_intersection_lines(o.view.features, model, lines_given || style_kinds);
    const Camera home = make_camera(camera, model);
    return run_viewer(model, home, o);
}

}  // namespace inkline
