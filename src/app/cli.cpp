#include "app/cli.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "app/flags.hpp"
#include "app/freeform_cli.hpp"
#include "core/error.hpp"
#include "detail/multiscale.hpp"
#include "output/styled.hpp"
#include "output/writers.hpp"
#include "pipeline.hpp"
#include "style/style.hpp"
#include "style/styled_view.hpp"
#include "style/stylize.hpp"

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
    std::string model, output, format;
    CameraFlags camera;
    double crease = 40.0;
    int subdivide = 0;
    bool walk = true;
    bool hidden = false, quiet = false, recall = false;
    bool strict = false;  // --strict: refuse what tolerant loading repairs
    FeatureOptions features;
    SurfaceLineOptions surface{.suggestive = false};
    bool lines_given = false;  // --lines (else a style's kinds apply)
    FinderOptions finder;
    VisibilityMethod visibility = VisibilityMethod::Appel;
    FreeformArgs freeform;  // line art of freeform surfaces (app/freeform_cli.hpp)
    std::string style;  // --style: NAME or FILE; empty: the default drawing (unchanged)
    DetailFlags detail;  // --detail: features of a target size in the image (detail/)
};

FlagTable render_flags(RenderArgs& a) {
    FlagTable t("render", "render MODEL [-o OUT] [FLAGS]",
                "Draws MODEL's lines to a file. MODEL: .obj .off .ply .stl (a triangle or polygon mesh), "
                "a scene Assimp reads (.gltf .glb .fbx .dae .3ds .blend ...), or SURFACES: .bpt Bezier patches (e.g. examples/teapot.bpt) or .json "
                "(src/freeform/README.md). Prints what it drew and the camera flags that reproduce it.");
    t.group("Output")
        .add({"--output", "FILE", "the drawing; its extension gives the format (default: MODEL's name .svg)",
              [&a](const std::string& v) { a.output = v; }, "-o"})
        .add(text_flag("--format", "svg|pdf|png|json", a.format, "the format, whatever the extension"))
        .add(switch_flag("--quiet", a.quiet, true, "print nothing"));
    t.group("Camera (default framed: the whole model in view, fov 30, +Y up)")
        .add(camera_flags(a.camera));
    t.group("Lines")
        .add(lines_flag(a.features, a.surface, &a.lines_given))
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
        .add(switch_flag("--no-walk", a.walk, false, "appel: a ray test where a walk on the surface would do"));
    t.group("Style").add(style_flag(a.style));
    t.group("Surfaces (.bpt, .json): silhouettes and borders of the tessellation, and Elber's line art")
        .add(freeform_flags(a.freeform));
    return t;
}

std::string default_output(const std::string& model) {
    const auto slash = model.find_last_of('/');
    std::string stem = slash == std::string::npos ? model : model.substr(slash + 1);
    const auto dot = stem.find_last_of('.');
    if (dot != std::string::npos && dot > 0) stem = stem.substr(0, dot);
    return stem + ".svg";
}

std::string fmt3(const glm::dvec3& v) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g", v.x, v.y, v.z);
    return buf;
}

}  // namespace

int run_render(int argc, char** argv) {
    const auto t0 = std::chrono::steady_clock::now();
    RenderArgs a;
    if (!render_flags(a).parse(argc, argv, 2, a.model)) return 0;  // --help
    const std::string out = a.output.empty() ? default_output(a.model) : a.output;
    const Format format = [&] {  // refuse a bad format before any work (a usage error)
        try {
            return output_format(out, a.format);
        } catch (const Error& e) {
            throw BadValue(e.what());
        }
    }();
    std::optional<Style> style;  // read before any work: a bad style file fails fast
    if (!a.style.empty()) {
        if (format == Format::Json) throw BadValue("--style: a style draws svg, pdf or png; JSON keeps the exact pieces");
        style = load_style(a.style);
        if (!a.lines_given && !style->kinds.empty()) set_line_kinds(style->kinds, a.features, a.surface);
    }
    std::unique_ptr<FreeformRender> freeform;
    if (is_freeform_model(a.model)) freeform = std::make_unique<FreeformRender>(a.model, a.freeform);
    else if (a.freeform.any()) throw Usage("line-art flags (--strokes, ...) need a .bpt or .json surface model", "render");
    if (freeform && a.subdivide > 0) throw BadValue("--subdivide: not for surface models (use --tessellation=N)");
    a.detail.check("render");
    if (freeform && a.detail.target_px > 0.0) throw BadValue("--detail: not for surface models");
    Model model = freeform ? Model(freeform->mesh(), a.crease) : load_model_file(a.model, a.strict, a.crease, a.subdivide);
    const Camera cam = make_camera(a.camera, model);
    ViewOptions opt;
    opt.features = a.features;
    opt.surface = a.surface;
    opt.visibility = a.visibility;
    opt.walk = a.walk;
    opt.exact_hidden = a.hidden;  // hidden pieces are written only with --hidden
    if (style && style->draw_hidden) opt.exact_hidden = true;
    opt.finder = a.finder;
    std::unique_ptr<MultiscaleLevels> levels;  // --detail: the smoothed levels and the session drawing them
    std::unique_ptr<MultiscaleSession> detail;
    if (a.detail.target_px > 0.0) {
        levels = std::make_unique<MultiscaleLevels>(
            build_multiscale_levels(model, a.detail.levels_options()));
        if (!levels->note.empty()) std::fprintf(stderr, "inkline: warning: %s: %s\n", a.model.c_str(), levels->note.c_str());
        detail = std::make_unique<MultiscaleSession>(
            model, *levels, opt,
            MultiscaleViewOptions{.target_px = a.detail.target_px, .depth_exponent = a.detail.depth_exponent.value_or(0.0)});
    }
    View view = detail ? std::move(detail->render(cam)) : render_view(model, cam, opt);
    // (with --detail the lines are those of the blended shape: the recall compares with its own)
    const MeshTopology& drawn = detail ? detail->blended().topology() : model.topology();
    if (a.recall) {
        const Features reference = extract_features(drawn, cam);
        const double total = edges_length(drawn, reference.silhouette_edges);
        view.drawing.stats.recall = total > 0.0 ? edges_length(drawn, view.features.silhouette_edges) / total : 1.0;
    }
    if (freeform) freeform->add_strokes(cam, view.drawing, a.quiet);
    OutputOptions oo;
    oo.hidden = a.hidden;
    const auto t_out = std::chrono::steady_clock::now();
    view.drawing.stats.seconds_output = 0.0;
    view.drawing.stats.seconds_total =
        std::chrono::duration<double>(t_out - t0).count();  // load + features + visibility
    StylizeStats style_stats;
    HatchStats hatch_stats;
    double t_style = 0.0;
    if (style) {
        const auto t_s = std::chrono::steady_clock::now();
        StyledViewStats sv;
        const StyledDrawing sd = stylize_view(detail ? detail->blended() : model, cam, view, *style, a.hidden, &sv);
        style_stats = sv.stylize;
        hatch_stats = sv.hatching;
        t_style = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_s).count();
        write_styled(sd, out, format);
    } else {
        write_drawing(view.drawing, out, format, oo);
    }
    const double t_write = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_out).count();
    if (!a.quiet) {
        const auto& s = view.drawing.stats;
        std::printf("%s: %zu triangles, %zu silhouette edges, %zu crease, %zu border, %zu curves, %zu cusps, "
                    "%zu crossings, %zu pieces, %zu ray tests (%s, %zu clusters)\n",
                    out.c_str(), s.triangles, s.silhouette_edges, s.crease_edges, s.border_edges, s.curves, s.cusps,
                    s.crossings, s.pieces, s.ray_tests, s.visibility.c_str(), s.clusters);
        std::printf("finder: %s (fraction %g)", s.finder.c_str(), s.fraction);
        if (s.recall >= 0.0) std::printf(", recall of silhouette length %.4f", s.recall);
        std::printf("\n");
        std::printf("seconds: load %.4f, features %.4f, visibility %.4f (pieces %.4f, propagation %.4f, walks "
                    "%.4f, ray tests %.4f), output %.4f\n",
                    s.seconds_load, s.seconds_features, s.seconds_visibility, s.seconds_pieces, s.seconds_propagation,
                    s.seconds_walks, s.seconds_ray_tests, t_write);
        if (levels)
            std::printf("detail: multiscale, target %g px, %d levels (%zu of %zu vertices collapsed), pre-process %.4f s, "
                        "%.1f bytes a vertex a level, blend %.4f s\n",
                        a.detail.target_px, levels->levels, levels->collapses, levels->vertices, levels->seconds,
                        levels->levels > 1 ? double(levels->bytes()) / double(levels->vertices * std::size_t(levels->levels - 1)) : 0.0,
                        detail->seconds_blend());
        if (style)
            std::printf("style: %s, %zu strokes, %zu points, %zu hatching strokes (%zu ray tests), %.4f s\n",
                        style->name.c_str(), style_stats.strokes, style_stats.points, style_stats.hatches,
                        hatch_stats.ray_tests, t_style);
        std::printf("camera: --eye=%s --target=%s --up=%s --%s=%.17g --size=%dx%d\n", fmt3(cam.eye()).c_str(),
                    fmt3(cam.target()).c_str(), fmt3(cam.up()).c_str(), cam.is_ortho() ? "ortho" : "fov",
                    cam.is_ortho() ? cam.ortho_height() : cam.fov_deg(), cam.width(), cam.height());
    }
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
            std::printf("inkline %s\n", INKLINE_VERSION);
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
