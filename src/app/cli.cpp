#include "app/cli.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/freeform_cli.hpp"
#include "core/error.hpp"
#include "output/styled.hpp"
#include "output/writers.hpp"
#include "pipeline.hpp"
#include "style/style.hpp"
#include "style/styled_view.hpp"
#include "style/stylize.hpp"

namespace inkline {

double parse_number(const std::string& flag, const std::string& s) {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0' || !std::isfinite(v)) throw Error(flag, "expected a number, got '" + s + "'");
    return v;
}

bool split_option(const std::string& arg, std::string& model, std::string& key, std::string& value) {
    if (arg.rfind("--", 0) != 0) {
        if (!model.empty()) throw Usage("more than one model given ('" + model + "', '" + arg + "')");
        model = arg;
        return false;
    }
    const auto eq = arg.find('=');
    if (eq == std::string::npos) throw Usage("unknown option '" + arg + "'");
    key = arg.substr(0, eq);
    value = arg.substr(eq + 1);
    return true;
}

namespace {

const char* kUsage =
    "usage: inkline render MODEL [-o OUT.{svg,pdf,png,json}] [--format=svg|pdf|png|json]\n"
    "                      [--eye=x,y,z] [--target=x,y,z] [--up=x,y,z] [--fov=DEG] [--size=WxH]\n"
    "                      [--ortho=H] [--near=D] [--crease=DEG] [--hidden]\n"
    "                      [--lines=silhouette,crease,border] [--visibility=appel|rays]\n"
    "                      [--no-walk] [--subdivide=N] [--quiet]\n"
    "                      [--finder=exhaustive|randomized] [--fraction=F] [--seed=S] [--recall]\n"
    "                      [--style=NAME|FILE.json]\n"
    "       inkline bench MODEL [--path=orbit|dolly|walk] [--frames=N] [--arc=DEG] [--seed=S] [--subdivide=N]\n"
    "                      [--csv=FILE] [--markdown=FILE] [--plot=FILE.svg] [--fractions=F,F,...]\n"
    "                      [--visibility=appel|rays] [--size=WxH] [--crease=DEG] [--threads=N]\n"
    "                      [--first-view=random|exhaustive]\n"
    "       inkline view MODEL [camera, line, finder and visibility flags as render] [--hidden] [--shading] [--style=NAME|FILE]\n"
    "                      [--no-coherence] [--first-view=exhaustive|random] [--no-panel] [--recall]\n"
    "                      [--frames=N [--orbit] [--arc=DEG] [--screenshot=F.png [--screenshot-ui]]\n"
    "                      [--export=F.{svg,pdf,png,json}] [--fps]] [--threads=N] [--in-flight=1|2]\n"
    "view: the randomized finder with frame coherence by default, from an exhaustive first view (exact),\n"
    "and two threads where there are two cores: two views at once, one on each, while the camera moves\n"
    "less than about a degree a view, else one at a time on both (--in-flight=1|2 fixes it);\n"
    "--finder=exhaustive scans every view.\n"
    "MODEL: .obj .off .ply .stl (a 2-manifold triangle or polygon mesh), or SURFACES (below).\n"
    "Without a camera the model is framed as in DESIGN.md (fov 30, up +Y).\n"
    "--finder=randomized: seed-and-seek silhouettes from a --fraction of the edges (default 0.05);\n"
    "--recall also runs the exhaustive finder and reports the recall of silhouette length.\n"
    "bench MODEL: a name like 'tori:64' builds two linked tori with 64 x 32 segments each.\n"
    "--style: a preset in the styles directory ($INKLINE_STYLES, else the source tree's styles/: clean,\n"
    "technical, sketchy, charcoal, ink-brush, hatched) or a style file; see styles/README.md.\n";


glm::dvec3 parse_vec3(const std::string& flag, const std::string& s) {
    std::vector<std::string> parts;
    std::stringstream ss(s);
    for (std::string p; std::getline(ss, p, ',');) parts.push_back(p);
    if (parts.size() != 3) throw Error(flag, "expected x,y,z, got '" + s + "'");
    return {parse_number(flag, parts[0]), parse_number(flag, parts[1]), parse_number(flag, parts[2])};
}

struct RenderArgs {
    std::string model, output, format;
    std::map<std::string, std::string> camera;  // flag -> value
    double crease = 40.0;
    int subdivide = 0;
    bool walk = true;
    bool hidden = false, quiet = false, recall = false;
    FeatureOptions features;
    FinderOptions finder;
    VisibilityMethod visibility = VisibilityMethod::Appel;
    FreeformArgs freeform;  // line art of freeform surfaces (app/freeform_cli.hpp)
    std::string style;  // --style: NAME or FILE; empty: the default drawing (unchanged)
};

RenderArgs parse_render(int argc, char** argv) {
    RenderArgs a;
    for (int i = 2; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "-o" || arg == "--output") {
            if (i + 1 >= argc) throw Usage(arg + " needs a file name");
            a.output = argv[++i];
            continue;
        }
        if (arg == "--hidden") { a.hidden = true; continue; }
        if (arg == "--quiet") { a.quiet = true; continue; }
        if (arg == "--no-walk") { a.walk = false; continue; }
        if (arg == "--recall") { a.recall = true; continue; }
        if (take_freeform_switch(arg, a.freeform)) continue;
        std::string key, value;
        if (!split_option(arg, a.model, key, value)) continue;
        if (key == "--output") a.output = value;
        else if (key == "--style") a.style = value;
        else if (key == "--format") a.format = value;
        else if (key == "--eye" || key == "--target" || key == "--up" || key == "--fov" || key == "--size" ||
                 key == "--ortho" || key == "--near")
            a.camera[key] = value;
        else if (key == "--subdivide") {
            const double n = parse_number(key, value);
            if (n < 0 || n > 6 || n != std::floor(n)) throw Error(key, "expected a number of levels from 0 to 6");
            a.subdivide = int(n);
        } else if (key == "--visibility") {
            if (value == "appel") a.visibility = VisibilityMethod::Appel;
            else if (value == "rays") a.visibility = VisibilityMethod::Rays;
            else throw Error(key, "unknown method '" + value + "' (expected appel or rays)");
        } else if (key == "--finder") {
            if (value == "exhaustive") a.finder.kind = FinderKind::Exhaustive;
            else if (value == "randomized") a.finder.kind = FinderKind::Randomized;
            else throw Error(key, "unknown finder '" + value + "' (expected exhaustive or randomized)");
        } else if (key == "--fraction") {
            a.finder.fraction = parse_number(key, value);
            if (!(a.finder.fraction > 0.0 && a.finder.fraction <= 1.0)) throw Error(key, "expected a share in (0, 1]");
        } else if (key == "--seed") {
            const double n = parse_number(key, value);
            if (n < 0 || n != std::floor(n) || n > 9007199254740992.0) throw Error(key, "expected a non-negative integer");
            a.finder.seed = std::uint64_t(n);
        } else if (key == "--crease") {
            a.crease = parse_number(key, value);
            if (a.crease < 0.0 || a.crease > 180.0) throw Error(key, "expected an angle in [0, 180] degrees");
        } else if (key == "--lines") {
            for (auto& k : a.features.kinds) k = false;
            std::stringstream ss(value);
            for (std::string name; std::getline(ss, name, ',');) {
                LineKind kind;
                if (!parse_line_kind(name, kind))
                    throw Error(key, "unknown line kind '" + name + "' (expected silhouette, crease, border)");
                a.features.kinds[int(kind)] = true;
            }
        } else if (!take_freeform_flag(key, value, a.freeform))
            throw Usage("unknown option '" + key + "'");
    }
    if (a.model.empty()) throw Usage("no model given");
    return a;
}

Camera make_camera(const RenderArgs& a, const MeshTopology& mesh) {
    int w = 1024, h = 1024;
    if (auto it = a.camera.find("--size"); it != a.camera.end()) {
        const auto x = it->second.find('x');
        if (x == std::string::npos) throw Error("--size", "expected WxH, got '" + it->second + "'");
        const double ww = parse_number("--size", it->second.substr(0, x));
        const double hh = parse_number("--size", it->second.substr(x + 1));
        if (ww < 1 || hh < 1 || ww > 32768 || hh > 32768 || ww != std::floor(ww) || hh != std::floor(hh))
            throw Error("--size", "expected integer sizes between 1 and 32768, got '" + it->second + "'");
        w = int(ww);
        h = int(hh);
    }
    const double fov = a.camera.count("--fov") ? parse_number("--fov", a.camera.at("--fov")) : 30.0;
    if (!(fov > 0.0 && fov < 180.0)) throw Error("--fov", "expected an angle in (0, 180) degrees");
    const Camera framed = Camera::framing(mesh.bounds, w, h, fov);
    const glm::dvec3 target = a.camera.count("--target") ? parse_vec3("--target", a.camera.at("--target")) : framed.target();
    const glm::dvec3 eye = a.camera.count("--eye") ? parse_vec3("--eye", a.camera.at("--eye")) : framed.eye();
    const glm::dvec3 up = a.camera.count("--up") ? parse_vec3("--up", a.camera.at("--up")) : glm::dvec3(0, 1, 0);
    Camera cam;
    try {
        if (a.camera.count("--ortho"))
            cam = Camera::orthographic(eye, target, up, parse_number("--ortho", a.camera.at("--ortho")), w, h);
        else
            cam = Camera::perspective(eye, target, up, fov, w, h);
    } catch (const std::invalid_argument& e) {
        throw Error("camera", e.what());
    }
    if (a.camera.count("--near")) {
        const double n = parse_number("--near", a.camera.at("--near"));
        if (!(n > 0.0)) throw Error("--near", "expected a positive distance");
        cam.set_near(n);
    }
    return cam;
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

int render(int argc, char** argv) {
    const auto t0 = std::chrono::steady_clock::now();
    RenderArgs a = parse_render(argc, argv);
    const std::string out = a.output.empty() ? default_output(a.model) : a.output;
    const Format format = output_format(out, a.format);  // refuse a bad format before any work
    std::optional<Style> style;  // read before any work: a bad style file fails fast
    if (!a.style.empty()) {
        if (format == Format::Json) throw Error("--style", "a style draws svg, pdf or png; JSON keeps the exact pieces");
        style = load_style(a.style);
    }
    std::unique_ptr<FreeformRender> freeform;
    if (is_freeform_model(a.model)) freeform = std::make_unique<FreeformRender>(a.model, a.freeform);
    else if (a.freeform.any()) throw Usage("line-art flags (--strokes, ...) need a .bpt or .json surface model");
    if (freeform && a.subdivide > 0) throw Error("--subdivide", "not for surface models (use --tessellation=N)");
    Model model = freeform ? Model(freeform->mesh(), a.crease) : Model::load(a.model, a.crease, a.subdivide);
    const Camera cam = make_camera(a, model.topology());
    ViewOptions opt;
    opt.features = a.features;
    opt.visibility = a.visibility;
    opt.walk = a.walk;
    opt.exact_hidden = a.hidden;  // hidden pieces are written only with --hidden
    if (style && style->draw_hidden) opt.exact_hidden = true;
    opt.finder = a.finder;
    View view = render_view(model, cam, opt);
    if (a.recall) {
        const Features reference = extract_features(model.topology(), cam);
        const double total = edges_length(model.topology(), reference.silhouette_edges);
        view.drawing.stats.recall =
            total > 0.0 ? edges_length(model.topology(), view.features.silhouette_edges) / total : 1.0;
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
        const StyledDrawing sd = stylize_view(model, cam, view, *style, a.hidden, &sv);
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

}  // namespace

Camera camera_from_flags(const std::map<std::string, std::string>& flags, const MeshTopology& mesh) {
    RenderArgs a;
    a.camera = flags;
    return make_camera(a, mesh);
}

int run_cli(int argc, char** argv) {
    try {
        if (argc < 2) throw Usage("no command given");
        const std::string cmd = argv[1];
        if (cmd == "-h" || cmd == "--help" || cmd == "help") {
            std::fputs(kUsage, stdout);
            std::fputs(kFreeformUsage, stdout);
            return 0;
        }
        if (cmd == "render") return render(argc, argv);
        if (cmd == "bench") return run_bench(argc, argv);
        if (cmd == "view") return run_view(argc, argv);
        throw Usage("unknown command '" + cmd + "'");
    } catch (const Usage& e) {
        std::fprintf(stderr, "inkline: %s\n%s", e.what(), kUsage);
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
