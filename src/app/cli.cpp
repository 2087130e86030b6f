#include "app/cli.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/batch.hpp"
#include "app/flags.hpp"
#include "app/freeform_cli.hpp"
#include "app/progress.hpp"
#include "core/clock.hpp"
#include "app/version.hpp"
#include "core/error.hpp"
#include "detail/multiscale.hpp"
#include "detail/multiscale_cache.hpp"
#include "detail/progressive_mesh_cache.hpp"
#include "detail/progressive_mesh.hpp"
#include "detail/progressive_mesh_session.hpp"
#include "output/styled.hpp"
#include "output/writers.hpp"
#include "pipeline.hpp"
#include "style/style.hpp"
#include "style/styled_view.hpp"
#include "style/stylize.hpp"
#include "view/camera_rig.hpp"

namespace inkline {

namespace {

const char* kOverview =
    "inkline draws 3D models as line drawings: silhouettes, creases and borders, with hidden lines\n"
    "found by quantitative invisibility (Appel, Markosian).\n"
    "\n"
    "usage: inkline COMMAND MODEL [FLAGS]\n"
    "\n"
    "commands:\n"
    "  render   draw a model (.obj .off .ply .stl, or .bpt/.json surfaces) to SVG, PDF, PNG or JSON\n"
    "  view     a window that draws the model live while you turn the camera\n"
    "  bench    time the silhouette finders along a camera path, against the exhaustive one\n"
    "\n"
    "inkline COMMAND --help for its flags; inkline --version for the version.\n";

struct RenderArgs {
    std::vector<std::string> models;
    std::string output, format;
    CameraFlags camera;
    double crease = 40.0;
    int subdivide = 0;
    bool walk = true;
    bool hidden = false, quiet = false, recall = false;
    bool keep_specks = false;  // --keep-specks: SVG, PDF, PNG keep lone strokes shorter than a pixel
    bool strict = false;  // --strict: refuse what tolerant loading repairs
    FeatureOptions features;
    SurfaceLineOptions surface{.suggestive = false};
    bool lines_given = false;  // --lines (else a style's kinds apply)
    FinderOptions finder;
    VisibilityMethod visibility = VisibilityMethod::Appel;
    int fast_buffer = 0;  // not given: fast_buffer_px gives the default
    FreeformArgs freeform;  // line art of freeform surfaces (app/freeform_cli.hpp)
    std::string style;  // --style: NAME or FILE; empty: the default drawing (unchanged)
    // A sequence (docs/batch.md): several models, or --frames=N along --orbit.
    int frames = 1;
    bool frames_given = false, orbit = false, verbose = false;
    double arc = 360.0;  // a turntable: frame N would be frame 0 again
    double frame_rate = 25.0;  // --frame-rate: a pm sequence's pace (the seed's 25 frames a second)
    bool frame_rate_given = false;
    FrameRange range;
    int jobs = hardware_threads();
    // --threads: each drawing's threads (0 until resolved by split_cores).
    int threads = 0;
    bool jobs_given = false, threads_given = false;
    ToneKinds tone;     // tone-dark, tone-highlight (src/tone/)
    tone::ToneOptions tone_options;
    bool toon_base = false;           // --base=toon
    std::vector<glm::dvec3> lights;   // --light (tone lines and the freeform shaders)
    DetailFlags detail;  // --detail: features of a target size in the image (detail/)
};

FlagTable render_flags(RenderArgs& a) {
    FlagTable t("render", "render MODEL... [-o OUT] [FLAGS]",
                "Draws MODEL's lines to a file. MODEL: .obj .off .ply .stl (a triangle or polygon mesh), "
                "a scene Assimp reads (.gltf .glb .fbx .dae .3ds .blend ...), or SURFACES: .bpt Bezier patches or .json "
                "surfaces (formats: docs/freeform.md; installed in share/doc/inkline). Prints what it drew and the camera flags that reproduce it. "
                "Several models, or --frames=N --orbit, write a numbered sequence (-o out_%04d.svg or -o DIR/).");
    t.group("Output")
        .add({"--output", "FILE", "the drawing; its extension gives the format (default: MODEL's name .svg); for a "
                                  "sequence a pattern with one frame number (out_%04d.svg) or a directory (DIR/)",
              [&a](const std::string& v) { a.output = v; }, "-o"})
        .add(text_flag("--format", "svg|pdf|png|json", a.format, "the format, whatever the extension"))
        .add(switch_flag("--keep-specks", a.keep_specks, true,
                         "svg, pdf, png: keep lone strokes shorter than a pixel (dropped by default; the JSON keeps every piece)"))
        .add(switch_flag("--quiet", a.quiet, true, "print nothing"));
    t.group("Camera (default framed: the whole model in view, fov 30, +Y up)")
        .add(camera_flags(a.camera));
    t.group("Lines")
        .add(lines_flag(a.features, a.surface, &a.lines_given, &a.tone))
        .add(crease_flag(a.crease))
        .add(suggestive_threshold_flag(a.surface))
        .add(ridge_threshold_flag(a.surface))
        .add(switch_flag("--hidden", a.hidden, true, "also draw hidden lines (dashed, by QI)"))
        .add(subdivide_flag(a.subdivide))
        .add(strict_flag(a.strict));
    t.group("Detail control").add(detail_flags(a.detail));
    t.group("Silhouette finder")
        .add(finder_flag(a.finder.kind))
        .add(fraction_flag(a.finder.fraction))
        .add(seed_flag(a.finder.seed))
        .add(switch_flag("--recall", a.recall, true,
                         "also run the exhaustive finder and report the recall of silhouette length"));
    t.group("Visibility")
        .add(visibility_flag(a.visibility))
        .add(fast_buffer_flag(a.fast_buffer))
        .add(switch_flag("--no-walk", a.walk, false, "appel: a ray test where a walk on the surface would do"));
    t.group("Threads (docs/threads.md)")
        .add(threads_flag(a.threads, "the machine's hardware threads divided among the drawings made at once",
                          &a.threads_given));
    t.group("Lighting").add(light_flag(a.lights));
    t.group("Tone lines (--lines=...,tone-dark,tone-highlight) and base coat: docs/tone.md")
        .add(tone_flags(a.tone_options, a.toon_base));
    t.group("Style").add(style_flag(a.style));
    t.group("Surfaces (.bpt, .json): silhouettes and borders of the tessellation, and Elber's line art")
        .add(freeform_flags(a.freeform));
    t.group("Sequence (several models, or a camera path; frames numbered from 0)")
        .add(frames_flag(a.frames, "with --orbit: N frames along the camera path", &a.frames_given))
        .add(orbit_flag(a.orbit, "turn the camera about its up axis around the target, as the window's --orbit"))
        .add(arc_flag(a.arc, "with --orbit: degrees turned over the frames (frame k at k*DEG/N)"))
        .add(frame_range_flag(a.range))
        .add(jobs_flag(a.jobs, &a.jobs_given))
        .add(frame_rate_flag(a.frame_rate, &a.frame_rate_given))
        .add(switch_flag("--verbose", a.verbose, true, "print each frame's report and exact camera flags"));
    return t;
}

std::string default_output(const std::string& model) {
    const auto slash = model.find_last_of('/');
    std::string stem = slash == std::string::npos ? model : model.substr(slash + 1);
    const auto dot = stem.find_last_of('.');
    if (dot != std::string::npos && dot > 0) stem = stem.substr(0, dot);
    return stem + ".svg";
}

// printf onto a string (a drawing's report is printed whole, in frame order, by the batch).
[[gnu::format(printf, 2, 3)]] void appendf(std::string& out, const char* format, ...) {
    char buf[2048];
    va_list args;
    va_start(args, format);
    std::vsnprintf(buf, sizeof buf, format, args);
    va_end(args);
    out += buf;
}

// Tone options checked before any work: relations between flags, and the image's size (the pass
// holds about 80 bytes a pixel).
void check_tone(const tone::ToneOptions& options, const CameraFlags& camera) {
    if (const std::string e = tone::tone_options_error(options); !e.empty()) throw BadValue(e);
    const long pixels = long(camera.width.value_or(1024)) * long(camera.height.value_or(1024));
    if (pixels > 8192L * 8192L)
        throw BadValue("--size: tone lines and the base coat need at most 8192 x 8192 pixels (about 80 bytes each)");
}

// The tone pass (src/tone/) at the camera's size: its pieces join the drawing's, its base coat
// goes under the lines.
void add_tone(const Model& model, const Camera& cam, const RenderArgs& a, Drawing& d, tone::ToneResult& result) {
    const tone::ToneMesh normals = tone::prepare_tone_mesh(model.topology());
    tone::render_tone(model.topology(), normals, cam, a.tone_options, a.tone.dark, a.tone.highlight, result);
    std::uint32_t curves = 0;  // tone lines numbered after the drawing's curves
    for (const Piece& p : d.pieces) curves = std::max(curves, p.curve + 1);
    for (Piece p : result.pieces) {
        p.curve += curves;
        d.pieces.push_back(std::move(p));
    }
    d.stats.pieces = d.pieces.size();
    if (a.toon_base) d.base = tone::toon_base(result.tone_blurred, result.shaded.covered, a.tone_options.toon_bands);
    d.stats.seconds_tone_shade = result.seconds.shade;
    d.stats.seconds_tone_blur = result.seconds.blur;
    d.stats.seconds_tone_ridges = result.seconds.ridges;
    d.stats.seconds_tone_trace = result.seconds.trace;
}

// What every drawing of a run shares, read once before any work.
struct RenderSetup {
    std::optional<Style> style;
    ViewOptions view;
    OutputOptions output;
    const MultiscaleLevels* detail = nullptr;  // --detail: the model's smoothed levels (every frame's)
    std::string detail_source;                 // how this run got them ("built", "read from the cache", ...)
};

// --detail's smoothed levels of `model` (loaded from `path`): built, or with --cache read from the
// cache folder or built and written there, with a progress line and at most one warning line.
MultiscaleLevels detail_levels(const RenderArgs& a, const Model& model, const std::string& path, std::string& source) {
    MultiscaleOptions options = a.detail.levels_options();
    const std::unique_ptr<ProgressLine> line = ProgressLine::on_stderr(
        "detail: smoothed levels", std::size_t(options.build_steps()), "steps", !a.quiet);
    options.progress = [&line](int done, int) { line->set_done(std::size_t(done)); };
    MultiscaleLevels levels;
    source = "built";
    if (a.detail.cache_dir.empty()) {
        levels = build_multiscale_levels(model, options);
    } else {
        CachedLevels cached =
            cached_multiscale_levels(model, path, loader_variant(a.subdivide, a.strict), options, a.detail.cache_dir);
        levels = std::move(cached.levels);
        source = cache_outcome_text(cached.outcome, cached.path);
        if (!cached.problem.empty()) {
            line->finish();
            std::fprintf(stderr, "inkline: warning: --cache: %s\n", cached.problem.c_str());
        }
    }
    line->finish();
    if (!levels.note.empty()) std::fprintf(stderr, "inkline: warning: %s: %s\n", path.c_str(), levels.note.c_str());
    return levels;
}

// --detail-method=pm's hierarchy of `model` (loaded from `path`): built, or with --cache read from
// the cache folder or built and written there (at most one warning line); `source` says which.
std::unique_ptr<ProgressiveMesh> pm_hierarchy(const RenderArgs& a, const Model& model, const std::string& path,
                                              std::string& source) {
    const std::size_t most = ProgressiveMesh::most_collapses(model.topology().vertex_count());
    const std::unique_ptr<ProgressLine> line = ProgressLine::on_stderr("detail: pm hierarchy", most, "collapses", !a.quiet);
    const ProgressiveMesh::BuildProgress progress = [&line](std::size_t done, std::size_t) { line->set_done(done); };
    if (a.detail.cache_dir.empty()) {
        source = "built";
        return std::make_unique<ProgressiveMesh>(model.topology(), progress);
    }
    CachedHierarchy cached = cached_progressive_mesh(model.topology(), path, loader_variant(a.subdivide, a.strict),
                                                     a.detail.cache_dir, progress);
    line->finish();
    source = cache_outcome_text(cached.outcome, cached.path);
    if (!cached.problem.empty()) std::fprintf(stderr, "inkline: warning: --cache: %s\n", cached.problem.c_str());
    return std::move(cached.pm);
}

// The view options for `model`: the run's, with intersection lines on for a scene of several
// objects unless the kinds were chosen (app/flags.hpp).
ViewOptions view_options(const RenderArgs& a, const RenderSetup& setup, const Model& model) {
    ViewOptions options = setup.view;
    default_intersection_lines(options.features, model, a.lines_given || (setup.style && !setup.style->kinds.empty()));
    return options;
}

// One drawing: `model` seen by `cam`, written to `out`. Returns its report (what it drew, the
// times, the camera flags that reproduce it); `t0`: the start its total seconds count from.
std::string render_drawing(const RenderArgs& a, const RenderSetup& setup, const Model& model, FreeformRender* freeform,
                           const Camera& cam, const std::string& out, Format format, StageClock::time_point t0,
                           bool in_batch = false, View* drawn_view = nullptr) {
    const std::optional<Style>& style = setup.style;
    std::unique_ptr<MultiscaleSession> detail;  // --detail: the session drawing the blended shape
    if (setup.detail)
        detail = std::make_unique<MultiscaleSession>(
            model, *setup.detail, view_options(a, setup, model),
            MultiscaleViewOptions{.target_px = a.detail.target_px, .depth_exponent = a.detail.depth_exponent.value_or(0.0),
                                  .object_target_px = a.detail.object_target_px});
    // (drawn_view: a view its caller drew of `model`, e.g. a pm sequence's frame)
    View view = drawn_view ? std::move(*drawn_view)
                : detail   ? std::move(detail->render(cam))
                           : render_view(model, cam, view_options(a, setup, model));
    // (with --detail the lines are those of the blended shape: the recall compares with its own)
    const MeshTopology& drawn = detail ? detail->blended().topology() : model.topology();
    if (a.recall) {
        const Features reference = extract_features(drawn, cam);
        // The reference's edges that the view found, summed in the reference's order: a subset's
        // sum, so never above the total (summed in the view's order it could round past it).
        std::vector<bool> found(drawn.edge_count(), false);
        for (const auto e : view.features.silhouette_edges) found[e] = true;
        std::vector<std::uint32_t> found_edges;
        for (const auto e : reference.silhouette_edges)
            if (found[e]) found_edges.push_back(e);
        const double total = edges_length(drawn, reference.silhouette_edges);
        view.drawing.stats.recall = total > 0.0 ? edges_length(drawn, found_edges) / total : 1.0;
    }
    if (freeform) freeform->add_strokes(cam, view.drawing, a.quiet || in_batch);  // (it prints as it goes)
    tone::ToneResult tone_result;
    const bool tone_pass = a.tone.any() || a.toon_base;
    if (tone_pass) add_tone(model, cam, a, view.drawing, tone_result);
    const auto t_out = std::chrono::steady_clock::now();
    view.drawing.stats.seconds_output = 0.0;
    view.drawing.stats.seconds_total =
        std::chrono::duration<double>(t_out - t0).count();  // load + features + visibility
    StylizeStats style_stats;
    HatchStats hatch_stats;
    double t_style = 0.0;
    WriteSummary written;  // the default writers' strokes (a style counts its own)
    if (style) {
        const auto t_s = std::chrono::steady_clock::now();
        StyledViewStats sv;
        const StyledDrawing sd = stylize_view(detail ? detail->blended() : model, cam, view, *style, a.hidden, &sv);
        style_stats = sv.stylize;
        hatch_stats = sv.hatching;
        t_style = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_s).count();
        write_styled(sd, out, format);
    } else {
        written = write_drawing(view.drawing, out, format, setup.output);
    }
    const double t_write = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_out).count();
    std::string report;
    const auto& s = view.drawing.stats;
    appendf(report, "%s: %zu triangles, %zu silhouette edges, %zu crease, %zu border, %zu curves, %zu cusps, "
            "%zu crossings, %zu pieces, %zu ray tests (%s, %zu clusters)\n",
            out.c_str(), s.triangles, s.silhouette_edges, s.crease_edges, s.border_edges, s.curves, s.cusps,
            s.crossings, s.pieces, s.ray_tests, s.visibility.c_str(), s.clusters);
    appendf(report, "finder: %s (fraction %g)", s.finder.c_str(), s.fraction);
    if (s.recall >= 0.0) appendf(report, ", recall of silhouette length %.4f", s.recall);
    appendf(report, "\n");
    appendf(report, "seconds: load %.4f, features %.4f, visibility %.4f (pieces %.4f, propagation %.4f, walks "
            "%.4f, ray tests %.4f), output %.4f\n",
            s.seconds_load, s.seconds_features, s.seconds_visibility, s.seconds_pieces, s.seconds_propagation,
            s.seconds_walks, s.seconds_ray_tests, t_write);
    if (format == Format::Json)
        appendf(report, "paths: the JSON keeps every piece (svg, pdf, png would leave out %zu as specks)\n",
                written.specks_dropped);
    else if (!style)  // (a style's line below counts its strokes)
        appendf(report, "paths: %zu strokes, %zu specks dropped (pieces shorter than a pixel, alone)\n",
                written.strokes, written.specks_dropped);
    if (style)
        appendf(report, "style: %s, %zu strokes, %zu points, %zu hatching strokes (%zu ray tests), %zu specks dropped, %.4f s\n",
                style->name.c_str(), style_stats.strokes, style_stats.points, style_stats.hatches,
                hatch_stats.ray_tests, style_stats.specks_dropped, t_style);
    if (const MultiscaleLevels* levels = setup.detail)
        appendf(report, "detail: multiscale, target %g px, %d levels%s (%zu of %zu vertices collapsed), pre-process %.4f s (%s), "
                "%.1f bytes a vertex a level, blend %.4f s\n",
                a.detail.target_px, levels->levels, a.detail.smoothing_thin_guarded ? ", thin-guarded smoothing" : "",
                levels->collapses, levels->vertices, levels->seconds,
                setup.detail_source.c_str(),
                levels->levels > 1 ? double(levels->bytes()) / double(levels->vertices * std::size_t(levels->levels - 1)) : 0.0,
                detail->seconds_blend());
    if (tone_pass) {
        std::size_t dark = 0, light = 0;
        for (const Piece& p : tone_result.pieces) (p.kind == LineKind::ToneDark ? dark : light) += 1;
        const tone::ToneTimes& ts = tone_result.seconds;
        appendf(report, "tone: %zu dark lines, %zu highlight lines%s; seconds: shade %.4f, blur %.4f, ridges %.4f, trace %.4f\n",
                dark, light, a.toon_base ? ", toon base" : "", ts.shade, ts.blur, ts.ridges, ts.trace);
    }
    appendf(report, "camera: %s\n", camera_flags(cam).c_str());
    return report;
}

// --detail=PX by the view-dependent progressive mesh: the model converged to the criterion at
// `cam` (a single frame: no geomorphs), and a report line on what was kept and what it cost.
Model detail_model(const Model& model, const ProgressiveMesh& pm, const std::string& pm_source, const Camera& cam,
                   const RenderArgs& a, std::string& report) {
    DetailCriterion criterion;
    criterion.target_area_px = a.detail.target_area_px();
    AdaptStats s;
    Model adapted(pm.adapt(cam, criterion, &s), a.crease);
    appendf(report, "detail: pm, target %g px (T = %g px^2): %zu of %zu triangles kept, %zu collapses in %zu passes, "
            "%.4f s; hierarchy of %zu collapses in %.4f s (%s)\n",
            a.detail.target_px, criterion.target_area_px, s.triangles, model.topology().faces.size(), s.collapses,
            s.passes, s.seconds, pm.collapses(), pm.build_seconds(), pm_source.c_str());
    return adapted;
}

// Frame k of N along the orbit: the window's orbit (view/camera_rig.hpp), k * arc / N degrees
// about the home camera's up axis, computed from the home camera alone so that a frame does not
// depend on which frames the run renders before it.
Camera orbit_frame(const Camera& home, const Bounds3& box, long k, long n, double arc_deg) {
    // Frame 0 is the home camera itself: the rig re-orthogonalizes the up vector, and a camera
    // equal only to the last bit can draw a different sub-pixel piece (the still must match).
    if (k == 0) return home;
    CameraRig rig(home, box);
    rig.orbit(arc_deg * double(k) / double(n), 0.0);
    return rig.camera(home.width(), home.height());
}

// What a run renders: one output name per item (a model of several, or a frame of the orbit).
struct RenderPlan {
    bool models = false;  // items are a.models; else frames of a.models[0]
    long count = 1;       // items in the whole run (--frame-range picks a slice)
    long first = 0, last = 0;
    std::vector<std::string> outputs;  // per item of the whole run
    std::string pattern;               // the numbered pattern (sequence reports)
};

// "DIR/": only a trailing slash makes -o a directory (an existing directory named as the file
// stays an error, as for one drawing: nothing is written into it unasked).
bool is_directory_name(const std::string& s) { return !s.empty() && s.back() == '/'; }

std::string stem_of(const std::string& model) {
    const std::string name = default_output(model);
    return name.substr(0, name.size() - 4);  // ".svg"
}

RenderPlan plan_render(const RenderArgs& a) {
    RenderPlan p;
    p.models = a.models.size() > 1;
    if (p.models && a.frames_given && a.frames > 1)
        throw Usage("several models or --frames=N, not both (one orbit a run)", "render");
    if (a.orbit && !a.frames_given) throw Usage("--orbit turns the camera over --frames=N frames", "render");
    if (a.frames > 1 && !a.orbit) throw Usage("--frames=N needs a camera path (--orbit)", "render");
    p.count = p.models ? long(a.models.size()) : a.frames;
    a.range.check(p.count);
    p.first = a.range.given() ? a.range.first : 0;
    p.last = a.range.given() ? a.range.last : p.count - 1;
    const std::string ext = "." + (a.format.empty() ? std::string("svg") : a.format);
    if (is_directory_name(a.output)) {
        const std::string& dir = a.output;
        p.pattern = dir + (p.models ? "MODEL" : stem_of(a.models[0]) + "_%04d") + ext;
        for (long i = 0; i < p.count; ++i)
            p.outputs.push_back(p.models ? dir + stem_of(a.models[std::size_t(i)]) + ext
                                         : OutputPattern(p.pattern).name(i));
    } else if (a.output.empty() && p.models) {
        p.pattern = "MODEL.svg";
        for (const std::string& m : a.models) p.outputs.push_back(default_output(m));
    } else {
        p.pattern = !a.output.empty() ? a.output : p.count > 1 ? stem_of(a.models[0]) + "_%04d.svg"
                                                               : default_output(a.models[0]);
        const OutputPattern pattern(p.pattern);
        if (p.count > 1 && !pattern.numbered())
            throw Usage("-o " + a.output + ": one file for " + std::to_string(p.count) +
                            " drawings; put a frame number in it (out_%04d.svg) or name a directory (DIR/)",
                        "render");
        for (long i = 0; i < p.count; ++i) p.outputs.push_back(pattern.name(i));
    }
    std::vector<std::string> sorted = p.outputs;
    std::sort(sorted.begin(), sorted.end());
    if (const auto dup = std::adjacent_find(sorted.begin(), sorted.end()); dup != sorted.end())
        throw BadValue("--output: two drawings of the run would both be written to " + *dup);
    if (is_directory_name(a.output)) {  // made if new (a pattern's directory must exist, as for one file)
        std::error_code ec;
        std::filesystem::create_directories(a.output, ec);
        if (ec) throw Error(a.output, "cannot make the directory: " + ec.message());
    }
    return p;
}

// Renders items first..last of the plan on a.jobs threads. Reports go to stdout in item order
// (a sequence's per frame only with --verbose); a progress line on stderr when it is a terminal.
void render_items(const RenderArgs& a, const RenderSetup& setup, const RenderPlan& plan, const Model* shared,
                  const Camera& home, Format format) {
    const std::size_t n = std::size_t(plan.last - plan.first + 1);
    const bool print_each = !a.quiet && (plan.models || a.verbose);
    auto progress = ProgressLine::on_stderr("render", n, plan.models ? "models" : "frames", !a.quiet);
    std::vector<std::optional<std::string>> reports(n);
    std::size_t next_report = 0;
    std::mutex report_mutex;
    run_jobs(a.jobs, n, [&](std::size_t j) {
        const long item = plan.first + long(j);
        const auto t0 = std::chrono::steady_clock::now();
        std::string report;
        if (plan.models) {  // each model loaded by the job that draws it (no subdivision progress lines)
            const std::string& path = a.models[std::size_t(item)];
            if (is_freeform_model(path)) {
                FreeformRender ff(path, a.freeform);
                const Model model(ff.mesh(), a.crease);
                report = render_drawing(a, setup, model, &ff, make_camera(a.camera, model),
                                        plan.outputs[std::size_t(item)], format, t0, true);
            } else {
                // (load_model_file's loading, with its warnings printed above the progress line)
                const Model model = Model::load(path, LoadOptions{.strict = a.strict}, a.crease, a.subdivide);
                for (const std::string& w : model.repairs().warnings(path))
                    progress->print_above([&] { std::fprintf(stderr, "inkline: warning: %s\n", w.c_str()); });
                report = render_drawing(a, setup, model, nullptr, make_camera(a.camera, model),
                                        plan.outputs[std::size_t(item)], format, t0, true);
            }
        } else {
            // Freeform line art keeps per-view state: a frame's own copy keeps frames independent
            // (without line-art flags the shared tessellation is all there is to draw).
            std::unique_ptr<FreeformRender> ff;
            if (is_freeform_model(a.models[0]) && a.freeform.any())
                ff = std::make_unique<FreeformRender>(a.models[0], a.freeform);
            const Camera cam = orbit_frame(home, shared->topology().bounds, item, plan.count, a.arc);
            report = render_drawing(a, setup, *shared, ff.get(), cam, plan.outputs[std::size_t(item)], format, t0, true);
        }
        progress->advance();
        if (!print_each) return;
        std::lock_guard<std::mutex> lock(report_mutex);
        reports[j] = std::move(report);
        for (; next_report < n && reports[next_report]; ++next_report)
            progress->print_above([&] { std::fputs(reports[next_report]->c_str(), stdout); });
    });
    progress->finish();
}

// A --detail-method=pm sequence: one session draws the frames in order (its mesh and smoothed
// curvature carry from frame to frame, with geomorphs at --frame-rate), so they are drawn one at
// a time, each on all of --threads, whatever --jobs. A frame must not depend on the range the
// run renders (--frame-range: the same file), so the frames before the range are made too
// (their meshes and smoothed curvature), not drawn. Frame 0 is the front converged at the home camera, as when a window opens.
void render_pm_sequence(const RenderArgs& a, const RenderSetup& setup, const RenderPlan& plan, const Model& model,
                        const ProgressiveMesh& pm, const Camera& home, Format format) {
    model.self_intersections(a.threads);  // (searched on the run's threads before for_path asks)
    PmSession session(pm, view_options(a, setup, model), PmViewOptions::for_path(model, a.detail.target_px));
    session.settle(home);
    const bool print_each = !a.quiet && a.verbose;
    auto progress = ProgressLine::on_stderr("render", std::size_t(plan.last + 1), "frames", !a.quiet);
    for (long k = 0; k <= plan.last; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        const Camera cam = orbit_frame(home, model.topology().bounds, k, plan.count, a.arc);
        if (k < plan.first) {
            session.advance(cam, 1.0 / a.frame_rate);
            progress->advance();
            continue;
        }
        View& view = session.render(cam, 1.0 / a.frame_rate);
        progress->advance();
        std::string report = render_drawing(a, setup, session.adapted(), nullptr, cam,
                                            plan.outputs[std::size_t(k)], format, t0, true, &view);
        const FrontStats& s = session.stats();
        appendf(report, "detail: pm, target %g px: %zu of %zu triangles, %zu splits, %zu collapses, %zu geomorphs "
                "running, adaptation %.4f s\n",
                a.detail.target_px, s.triangles, model.topology().faces.size(), s.splits, s.collapses,
                s.morphs_running, s.seconds);
        if (print_each) progress->print_above([&] { std::fputs(report.c_str(), stdout); });
    }
    progress->finish();
}

// The run's last lines: what was written, and for an orbit the flags that render the whole
// sequence again (add --frame-range=K for frame K alone, the same file).
void print_summary(const RenderArgs& a, const RenderPlan& plan, double seconds, const std::string& home_flags) {
    if (a.quiet) return;
    std::printf("render: %ld %s (%ld to %ld of %ld) written as %s in %.2f s, %d jobs\n", plan.last - plan.first + 1,
                plan.models ? "drawings" : "frames", plan.first, plan.last, plan.count, plan.pattern.c_str(), seconds,
                a.jobs);
    if (!plan.models) {
        char arc[32];
        std::snprintf(arc, sizeof arc, "%.17g", a.arc);
        std::printf("camera: %s --frames=%ld --orbit --arc=%s\n", home_flags.c_str(), plan.count, arc);
    }
}

// The machine's cores between drawings (--jobs) and each drawing's threads (--threads), when not
// both given: jobs x threads about the hardware threads. A sequence's frames are independent, so
// by default they go on every core one frame each (no frame waits for a split stage); one drawing
// takes every core; a short sequence gives each of its frames the cores left over.
void split_cores(RenderArgs& a, long drawings) {
    const int cores = hardware_threads();
    if (!a.jobs_given) a.jobs = a.threads_given ? std::max(1, cores / a.threads) : cores;
    const int at_once = int(std::clamp<long>(drawings, 1, a.jobs));
    if (!a.threads_given) a.threads = std::max(1, cores / at_once);
}

}  // namespace

int run_render(int argc, char** argv) {
    const auto t0 = std::chrono::steady_clock::now();
    RenderArgs a;
    if (!render_flags(a).parse(argc, argv, 2, a.models)) return 0;  // --help
    const RenderPlan plan = plan_render(a);
    // (a pm sequence draws its frames one after another: render_pm_sequence)
    const bool pm_sequence = a.detail.target_px > 0.0 && a.detail.method == "pm" && !plan.models && plan.count > 1;
    split_cores(a, pm_sequence ? 1 : plan.last - plan.first + 1);
    if (pm_sequence) a.jobs = 1;
    a.tone_options.threads = a.threads;
    const Format format = [&] {  // refuse a bad format before any work (a usage error)
        try {
            return output_format(plan.outputs[0], a.format);
        } catch (const Error& e) {
            throw BadValue(e.what());
        }
    }();
    RenderSetup setup;
    std::optional<Style>& style = setup.style;  // read before any work: a bad style file fails fast
    if (!a.style.empty()) {
        if (format == Format::Json) throw BadValue("--style: a style draws svg, pdf or png; JSON keeps the exact pieces");
        style = load_style(a.style);
        if (a.keep_specks) style->keep_specks = true;
        if (!a.lines_given && !style->kinds.empty()) set_line_kinds(style->kinds, a.features, a.surface, &a.tone);
    }
    a.tone_options.lights = a.lights;
    a.freeform.lights = a.lights;
    if (a.tone.any() || a.toon_base) check_tone(a.tone_options, a.camera);
    a.detail.check("render");
    if (a.detail.target_px > 0.0 && plan.models)
        throw BadValue("--detail: one model a run (its smoothed levels are built once for all its frames)");
    if (a.frame_rate_given && !pm_sequence)
        throw BadValue("--frame-rate: paces a --detail-method=pm sequence (--frames=N --orbit); other frames do not depend on time");
    for (const std::string& m : a.models) {
        if (is_freeform_model(m) && a.detail.target_px > 0.0) throw BadValue("--detail: not for surface models");
        if (!is_freeform_model(m) && a.freeform.any())
            throw Usage("line-art flags (--strokes, ...) need a .bpt or .json surface model", "render");
        if (is_freeform_model(m) && a.subdivide > 0)
            throw BadValue("--subdivide: not for surface models (use --tessellation=N)");
    }
    ViewOptions& opt = setup.view;
    opt.features = a.features;
    opt.surface = a.surface;
    opt.visibility = a.visibility;
    opt.walk = a.walk;
    opt.exact_hidden = a.hidden;  // hidden pieces are written only with --hidden
    if (style && style->draw_hidden) opt.exact_hidden = true;
    check_fast_visibility(a.visibility, a.hidden, "--hidden");
    check_fast_visibility(a.visibility, style && style->draw_hidden, "the style's hidden lines");
    opt.fast.buffer_px = fast_buffer_px(a.fast_buffer, a.visibility);
    opt.finder = a.finder;
    opt.threads = a.threads;
    setup.output.hidden = a.hidden;
    setup.output.keep_specks = a.keep_specks;
    if (plan.models) {
        render_items(a, setup, plan, nullptr, Camera(), format);
        print_summary(a, plan, seconds_since(t0), "");
        return 0;
    }
    const std::string& path = a.models[0];
    std::unique_ptr<FreeformRender> freeform;
    if (is_freeform_model(path)) freeform = std::make_unique<FreeformRender>(path, a.freeform);
    const Model model = freeform ? Model(freeform->mesh(), a.crease)
                                 : load_model_file(path, a.strict, a.crease, a.subdivide, true, a.threads);
    const Camera home = make_camera(a.camera, model);
    // --detail (multiscale): the smoothed levels, built (or read from --cache) once for every frame.
    std::optional<MultiscaleLevels> levels;
    if (a.detail.target_px > 0.0 && a.detail.method != "pm") {
        if (const std::string unknown = unknown_detail_objects(
                model.topology(), {.object_target_px = a.detail.object_target_px}); !unknown.empty())
            throw BadValue("--detail-object: " + path + " has no object named " + unknown);
        levels = detail_levels(a, model, path, setup.detail_source);
        setup.detail = &*levels;
    }
    // --detail-method=pm: the hierarchy (built, or read from --cache) for the frame or the sequence.
    std::unique_ptr<ProgressiveMesh> pm;
    std::string pm_source;
    if (a.detail.target_px > 0.0 && a.detail.method == "pm") pm = pm_hierarchy(a, model, path, pm_source);
    if (plan.count == 1) {
        if (pm) {
            std::string detail_report;
            const Model adapted = detail_model(model, *pm, pm_source, home, a, detail_report);
            const std::string report = render_drawing(a, setup, adapted, nullptr, home, plan.outputs[0], format, t0);
            if (!a.quiet) std::fputs((report + detail_report).c_str(), stdout);
            return 0;
        }
        const std::string report = render_drawing(a, setup, model, freeform.get(), home, plan.outputs[0], format, t0);
        if (!a.quiet) std::fputs(report.c_str(), stdout);
        return 0;
    }
    if (pm_sequence) {
        render_pm_sequence(a, setup, plan, model, *pm, home, format);
        print_summary(a, plan, seconds_since(t0), camera_flags(home));
        return 0;
    }
    // The model's lazy parts, built before the jobs start (each frame needs the self-intersections,
    // nearly every one a ray test, all of them the curvature when its lines are drawn): the jobs
    // then only read the model. (Built on first use they would be safe too, behind call_once.)
    model.self_intersections(a.threads);
    model.rays();
    if (setup.view.wants_surface_lines()) model.curvature();
    if (view_options(a, setup, model).features.intersection) model.intersection_curves();
    render_items(a, setup, plan, &model, home, format);
    print_summary(a, plan, seconds_since(t0), camera_flags(home));
    return 0;
}

int run_cli(int argc, char** argv) {
    try {
        if (argc < 2) throw Usage("no command given");
        const std::string cmd = argv[1];
        if (cmd == "-h" || cmd == "--help" || (cmd == "help" && argc == 2)) {
            std::fputs(kOverview, stdout);
            return 0;
        }
        if (cmd == "--version" || cmd == "-V") {
            std::printf("inkline %s\n", version_text());
            return 0;
        }
        if (cmd == "help") {  // `inkline help render`: as `inkline render --help`
            char help[] = "--help";
            char* args[] = {argv[0], argv[2], help};
            return run_cli(3, args);
        }
        if (cmd == "render") return run_render(argc, argv);
        if (cmd == "bench") return run_bench(argc, argv);
        if (cmd == "view") return run_view(argc, argv);
        throw Usage("unknown command '" + cmd + "'");
    } catch (const BadValue& e) {
        std::fprintf(stderr, "inkline: %s\n", e.what());
        return 2;
    } catch (const Usage& e) {
        std::fprintf(stderr, "inkline: %s\n%s\n", e.what(), usage_line(e.command).c_str());
        return 2;
    } catch (const Error& e) {
        std::fprintf(stderr, "inkline: %s\n", e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "inkline: out of memory\n");
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "inkline: internal error: %s\n", e.what());
        return 1;
    }
}

}  // namespace inkline
