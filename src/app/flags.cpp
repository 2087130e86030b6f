#include "app/flags.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <thread>

#include <glm/geometric.hpp>

#include "app/batch.hpp"
#include "app/load_progress_line.hpp"
#include "app/progress.hpp"
#include "core/error.hpp"

namespace inkline {

// ---- value parsers ----

double parse_number(const std::string& flag, const std::string& s) {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || *end != '\0' || !std::isfinite(v)) throw Error(flag, "expected a number, got '" + s + "'");
    return v;
}

int parse_integer(const std::string& flag, const std::string& s, int lo, int hi) {
    const double n = parse_number(flag, s);
    if (n < lo || n > hi || n != std::floor(n))
        throw Error(flag, "expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    return int(n);
}

glm::dvec3 parse_vec3(const std::string& flag, const std::string& s) {
    std::vector<std::string> parts;
    std::stringstream ss(s);
    for (std::string p; std::getline(ss, p, ',');) parts.push_back(p);
    if (parts.size() != 3) throw Error(flag, "expected x,y,z, got '" + s + "'");
    return {parse_number(flag, parts[0]), parse_number(flag, parts[1]), parse_number(flag, parts[2])};
}

// ---- the table ----

FlagTable::FlagTable(std::string command, std::string synopsis, std::string about)
    : command_(std::move(command)), synopsis_(std::move(synopsis)), about_(std::move(about)) {}

FlagTable& FlagTable::group(const std::string& title) {
    groups_.push_back({title, {}});
    return *this;
}

FlagTable& FlagTable::add(Flag flag) {
    if (groups_.empty()) group("Flags");
    groups_.back().second.push_back(std::move(flag));
    return *this;
}

FlagTable& FlagTable::add(std::vector<Flag> flags) {
    for (Flag& f : flags) add(std::move(f));
    return *this;
}

FlagTable& FlagTable::note(const std::string& text) {
    notes_ += text;
    return *this;
}

const Flag* FlagTable::find(const std::string& name) const {
    for (const auto& [title, flags] : groups_)
        for (const Flag& f : flags)
            if (f.name == name || (!f.short_name.empty() && f.short_name == name)) return &f;
    return nullptr;
}

bool FlagTable::parse(int argc, char** argv, int first, std::string& model) const {
    std::vector<std::string> models;
    if (!parse(argc, argv, first, models)) return false;
    if (models.size() > 1) throw Usage("more than one model given ('" + models[0] + "', '" + models[1] + "')", command_);
    model = models[0];
    return true;
}

bool FlagTable::parse(int argc, char** argv, int first, std::vector<std::string>& models) const {
    for (int i = first; i < argc; ++i)
        if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
            std::fputs(help().c_str(), stdout);
            return false;
        }
    for (int i = first; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg.rfind("--", 0) != 0 && !find(arg)) {  // (as before: "-x" is a file name, not a flag)
            models.push_back(arg);
            continue;
        }
        const auto eq = arg.find('=');
        const std::string key = arg.substr(0, eq);
        const Flag* f = find(key);
        if (!f) throw Usage("unknown option '" + key + "'", command_);
        // A value the flag refuses is a usage error too (exit 2), in the flag's own one line.
        auto set = [f](const std::string& value) {
            try {
                f->set(value);
            } catch (const Error& e) {
                throw BadValue(e.what());
            }
        };
        if (f->value.empty()) {
            if (eq != std::string::npos) throw Usage(key + " takes no value", command_);
            set("");
        } else if (eq != std::string::npos) {
            set(arg.substr(eq + 1));
        } else if (!f->short_name.empty()) {  // `-o FILE`, `--output FILE`
            if (i + 1 >= argc) throw Usage(arg + " needs a file name", command_);
            set(argv[++i]);
        } else {
            throw Usage(key + " needs a value (" + key + "=" + f->value + ")", command_);
        }
    }
    if (models.empty()) throw Usage("no model given", command_);
    return true;
}

namespace {

constexpr std::size_t kColumns = 100;  // the help fits a terminal this wide
constexpr std::size_t kFlagColumn = 28;  // where the descriptions start

// Appends `text` word by word, lines no wider than kColumns, continuation lines indented by
// `indent` (the first line continues from `column`).
void wrap(std::string& out, const std::string& text, std::size_t column, std::size_t indent) {
    std::stringstream ss(text);
    bool first = true;
    for (std::string word; ss >> word; first = false) {
        if (!first && column + 1 + word.size() > kColumns) {
            out += '\n';
            out.append(indent, ' ');
            column = indent;
        } else if (!first) {
            out += ' ';
            ++column;
        }
        out += word;
        column += word.size();
    }
    out += '\n';
}

}  // namespace

std::string FlagTable::help() const {
    std::string out = "usage: inkline " + synopsis_ + "\n";
    wrap(out, about_, 0, 0);
    for (const auto& [title, flags] : groups_) {
        out += "\n" + title + ":\n";
        for (const Flag& f : flags) {
            std::string left = "  ";
            if (!f.short_name.empty()) left += f.short_name + " " + f.value + ", ";
            left += f.name + (f.value.empty() ? "" : "=" + f.value);
            out += left;
            std::size_t column = left.size();
            if (column + 2 > kFlagColumn) {  // long flag: its description on the next line
                out += "\n";
                column = 0;
            }
            out += std::string(kFlagColumn - column, ' ');
            wrap(out, f.help, kFlagColumn, kFlagColumn);
        }
    }
    if (!notes_.empty()) {
        out += "\n";
        std::stringstream ss(notes_);
        for (std::string paragraph; std::getline(ss, paragraph);) wrap(out, paragraph, 0, 0);
    }
    return out;
}

std::string usage_line(const std::string& command) {
    if (command.empty()) return "usage: inkline COMMAND MODEL [FLAGS]; see 'inkline --help'";
    return "usage: inkline " + command + " MODEL [FLAGS]; see 'inkline " + command + " --help'";
}

// ---- the camera ----

Flag size_flag(std::optional<int>& width, std::optional<int>& height) {
    const std::string unset = width ? " (default " + std::to_string(*width) + "x" + std::to_string(*height) + ")" : "";
    return {"--size", "WxH", "image size in pixels, 1 to 32768 each" + unset, [&width, &height](const std::string& v) {
                const auto x = v.find('x');
                if (x == std::string::npos) throw Error("--size", "expected WxH, got '" + v + "'");
                const double w = parse_number("--size", v.substr(0, x));
                const double h = parse_number("--size", v.substr(x + 1));
                if (w < 1 || h < 1 || w > 32768 || h > 32768 || w != std::floor(w) || h != std::floor(h))
                    throw Error("--size", "expected integer sizes between 1 and 32768, got '" + v + "'");
                width = int(w);
                height = int(h);
            }};
}

std::vector<Flag> camera_flags(CameraFlags& c) {
    const auto vec3 = [](const char* name, const char* help, std::optional<glm::dvec3>& to) {
        return Flag{name, "X,Y,Z", help, [name, &to](const std::string& v) { to = parse_vec3(name, v); }};
    };
    return {
        vec3("--eye", "camera position (default: framed)", c.eye),
        vec3("--target", "point looked at (default: the bounding box's centre)", c.target),
        vec3("--up", "up direction (default 0,1,0)", c.up),
        {"--fov", "DEG", "vertical field of view, in (0, 180) (default 30)",
         [&c](const std::string& v) {
             const double fov = parse_number("--fov", v);
             if (!(fov > 0.0 && fov < 180.0)) throw Error("--fov", "expected an angle in (0, 180) degrees");
             c.fov = fov;
         }},
        size_flag(c.width, c.height),
        {"--ortho", "H", "orthographic, H world units high (default: perspective)",
         [&c](const std::string& v) { c.ortho = parse_number("--ortho", v); }},
        {"--near", "D", "near plane distance (default: a small share of the model's size)",
         [&c](const std::string& v) {
             const double n = parse_number("--near", v);
             if (!(n > 0.0)) throw Error("--near", "expected a positive distance");
             c.near = n;
         }},
        {"--camera", "NAME|frame",
         "a camera of the model's file by name, or frame the model (default: the file's first perspective "
         "camera when no other camera flag is given, else framed)",
         [&c](const std::string& v) {
             if (v.empty()) throw Error("--camera", "expected a camera's name or 'frame'");
             c.file_camera = v;
         }},
    };
}

Camera make_camera(const CameraFlags& c, const Model& model) {
    const std::vector<SceneCamera>& cams = model.cameras();
    const SceneCamera* file = nullptr;
    if (c.file_camera == "frame") {
    } else if (!c.file_camera.empty()) {
        std::string names;
        for (const SceneCamera& s : cams) {
            if (s.name == c.file_camera && !file) file = &s;
            names += (names.empty() ? "'" : ", '") + s.name + "'";
        }
        if (!file)
            throw BadValue("--camera: the model's file has no camera '" + c.file_camera + "' (" +
                           (names.empty() ? std::string("it has none") : "its cameras: " + names) +
                           "; 'frame' frames the model)");
    } else if (!c.eye && !c.target && !c.up && !c.fov && !c.ortho) {
        for (const SceneCamera& s : cams)
            if (!s.orthographic && !file) file = &s;
    }
    if (!file) return make_camera(c, model.topology());
    CameraFlags from_file = c;  // the file's camera, where no flag says otherwise
    from_file.eye = c.eye.value_or(file->eye);
    from_file.target = c.target.value_or(file->target);
    from_file.up = c.up.value_or(file->up);
    if (file->orthographic && !c.fov) from_file.ortho = c.ortho.value_or(file->ortho_height);
    else from_file.fov = c.fov.value_or(file->fov_deg);
    return make_camera(from_file, model.topology());
}

Model load_model_file(const std::string& path, bool strict, double crease_degrees, int subdivide, bool progress,
                      int threads) {
    std::unique_ptr<ProgressLine> line;  // from the subdivision's start (the file's reading apart)
    SubdivideProgress on_level = [&line](std::size_t done, std::size_t total) {
        if (!line) line = ProgressLine::on_stderr("subdivide", total, "triangles");
        line->set_done(done);
        if (done == total) line->finish();  // (the ordering and topology that follow are not counted)
    };
    Model model = Model::load(path, LoadOptions{.strict = strict, .progress = progress ? load_progress_line(path) : LoadProgressCallback(), .threads = threads}, crease_degrees, subdivide,
                              progress ? on_level : SubdivideProgress());
    line.reset();
    for (const std::string& w : model.repairs().warnings(path)) std::fprintf(stderr, "inkline: warning: %s\n", w.c_str());
    return model;
}

Camera make_camera(const CameraFlags& c, const MeshTopology& mesh) {
    const int w = c.width.value_or(1024), h = c.height.value_or(1024);
    const double fov = c.fov.value_or(30.0);
    const Camera framed = Camera::framing(mesh.bounds, w, h, fov);
    const glm::dvec3 target = c.target.value_or(framed.target());
    const glm::dvec3 eye = c.eye.value_or(framed.eye());
    const glm::dvec3 up = c.up.value_or(glm::dvec3(0, 1, 0));
    Camera cam;
    try {
        cam = c.ortho ? Camera::orthographic(eye, target, up, *c.ortho, w, h)
                      : Camera::perspective(eye, target, up, fov, w, h);
    } catch (const std::invalid_argument& e) {
        throw BadValue(std::string("camera: ") + e.what());
    }
    if (c.near) cam.set_near(*c.near);
    return cam;
}

// ---- the other shared flags ----

namespace {
std::string fmt_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}
}  // namespace

Flag seed_flag(std::uint64_t& seed) {
    return {"--seed", "S", "random seed, an integer from 0 to 2^53 (default 1; runs are deterministic)",
            [&seed](const std::string& v) {
                const double n = parse_number("--seed", v);
                if (n < 0 || n != std::floor(n) || n > 9007199254740992.0)
                    throw Error("--seed", "expected an integer from 0 to 2^53");
                seed = std::uint64_t(n);
            }};
}

Flag crease_flag(double& degrees) {
    return {"--crease", "DEG", "an edge whose face normals differ by more is a crease, in [0, 180] (default 40)",
            [&degrees](const std::string& v) {
                const double d = parse_number("--crease", v);
                if (d < 0.0 || d > 180.0) throw Error("--crease", "expected an angle in [0, 180] degrees");
                degrees = d;
            }};
}

namespace {
const char* const kLineKindNames =
    "silhouette, crease, border, suggestive, smooth-contour, ridge, valley, intersection, tone-dark, tone-highlight";
// The switch of a surface line kind (curvature/curvature.hpp); null for the mesh edge kinds.
bool* surface_switch(SurfaceLineOptions& surface, LineKind k) {
    switch (k) {
        case LineKind::Suggestive: return &surface.suggestive;
        case LineKind::SmoothContour: return &surface.smooth_contour;
        case LineKind::Ridge: return &surface.ridge;
        case LineKind::Valley: return &surface.valley;
        default: return nullptr;
    }
}
// A kind the drawing of a mesh can hold (not the freeform line art, which has flags of its own).
bool parse_drawn_kind(const std::string& name, LineKind& out) {
    for (int i = 0; i < kPieceKindCount; ++i)
        if (LineKind(i) != LineKind::Freeform && name == to_string(LineKind(i))) {
            out = LineKind(i);
            return true;
        }
    return false;
}
}  // namespace

void set_line_kinds(const std::vector<LineKind>& kinds, FeatureOptions& features, SurfaceLineOptions& surface,
                    ToneKinds* tone) {
    for (auto& k : features.kinds) k = false;
    surface.suggestive = surface.smooth_contour = surface.ridge = surface.valley = false;
    features.intersection = false;
    if (tone) *tone = {};
    for (LineKind k : kinds) {
        if (bool* on = surface_switch(surface, k)) *on = true;
        else if (k == LineKind::Intersection) features.intersection = true;
        else if (k == LineKind::ToneDark && tone) tone->dark = true;
        else if (k == LineKind::ToneHighlight && tone) tone->highlight = true;
        else if (int(k) < kLineKindCount) features.kinds[int(k)] = true;
    }
}

void default_intersection_lines(FeatureOptions& features, const Model& model, bool kinds_chosen) {
    if (!kinds_chosen && model.topology().object_names.size() > 1) features.intersection = true;
}

Flag lines_flag(FeatureOptions& features, SurfaceLineOptions& surface, bool* given, ToneKinds* tone) {
    return {"--lines", "KIND,...", std::string("line kinds drawn: ") + kLineKindNames +
                " (default the first three, and intersection for a scene of several objects)",
            [&features, &surface, given, tone](const std::string& v) {
                std::vector<LineKind> kinds;
                std::stringstream ss(v);
                for (std::string name; std::getline(ss, name, ',');) {
                    LineKind kind;
                    if (!parse_drawn_kind(name, kind))
                        throw Error("--lines", "unknown line kind '" + name + "' (expected " + kLineKindNames + ")");
                    if (!tone && (kind == LineKind::ToneDark || kind == LineKind::ToneHighlight))
                        throw Error("--lines", name + " lines are drawn by 'inkline render' and 'inkline view' only");
                    kinds.push_back(kind);
                }
                set_line_kinds(kinds, features, surface, tone);
                if (given) *given = true;
            }};
}

namespace {
// A threshold of the lines from curvature: a number in [0, 1000], relative to the model's size.
Flag threshold_flag(const std::string& name, const std::string& help, double& target) {
    return {name, "T", help, [name, &target](const std::string& v) {
                const double t = parse_number(name, v);
                if (!(t >= 0.0 && t <= 1000.0)) throw Error(name, "expected a number in [0, 1000]");
                target = t;
            }};
}
}  // namespace

Flag suggestive_threshold_flag(SurfaceLineOptions& surface) {
    return threshold_flag("--suggestive-threshold",
                          "suggestive contours: how steeply the radial curvature must rise across them, relative "
                          "to the model's feature size (default 0.01; 0 draws every zero of it, larger draws fewer)",
                          surface.suggestive_threshold);
}

Flag ridge_threshold_flag(SurfaceLineOptions& surface) {
    return threshold_flag("--ridge-threshold",
                          "ridges and valleys: the least principal curvature drawn, relative to the model's "
                          "feature size (default 0.1)",
                          surface.ridge_threshold);
}

Flag light_flag(std::vector<glm::dvec3>& lights) {
    return {"--light", "X,Y,Z",
            "a light: world direction towards it; repeat for more (default: a headlight from the upper left)",
            [&lights](const std::string& v) {
                const glm::dvec3 l = parse_vec3("--light", v);
                if (!(glm::length(l) > 0.0)) throw Error("--light", "expected a non-zero direction, got '" + v + "'");
                lights.push_back(glm::normalize(l));
            }};
}

std::vector<Flag> tone_flags(tone::ToneOptions& o, bool& toon_base) {
    const auto pair = [](const char* name, double& lo, double& hi) {
        return [name, &lo, &hi](const std::string& v) {
            const auto comma = v.find(',');
            if (comma == std::string::npos) throw Error(name, "expected CL,CU, got '" + v + "'");
            const double a = parse_number(name, v.substr(0, comma)), b = parse_number(name, v.substr(comma + 1));
            if (a < 0 || b < 0) throw Error(name, "expected thresholds CL,CU >= 0, got '" + v + "'");
            if (a > b) throw Error(name, "the lower threshold is above the upper one in '" + v + "' (expected CL <= CU)");
            lo = a, hi = b;
        };
    };
    const auto number = [](const char* name, double lo, double hi, const char* what, double& to) {
        return [=, &to](const std::string& v) {
            const double x = parse_number(name, v);
            if (!(x >= lo && x <= hi)) throw Error(name, std::string("expected ") + what + ", got '" + v + "'");
            to = x;
        };
    };
    return {
        {"--tone-width", "PX", "tone lines: line width w in px, (0, 256]: blur size and fit spacing w/2 (default 6)",
         [&o](const std::string& v) {
             const double w = parse_number("--tone-width", v);
             if (!(w > 0.0 && w <= 256.0)) throw Error("--tone-width", "expected a width in (0, 256] px, got '" + v + "'");
             o.width = w;
         }},
        {"--tone-beta", "B",
         "tone lines: share of the way moved toward the ridge per step, [0, 1]; 0 keeps tone edges, 1 only ridges "
         "(default 0.2)",
         number("--tone-beta", 0.0, 1.0, "a share in [0, 1]", o.beta)},
        {"--tone-dark", "CL,CU", "dark lines' soft curvature thresholds, per (w/2)^2 (default 0.015,0.05)",
         pair("--tone-dark", o.dark_lower, o.dark_upper)},
        {"--tone-highlight", "CL,CU", "highlight lines' soft curvature thresholds (default 0.05,0.12)",
         pair("--tone-highlight", o.highlight_lower, o.highlight_upper)},
        {"--specular", "E", "Blinn-Phong exponent of the specular channel, [1, 10000] (default 40)",
         number("--specular", 1.0, 10000.0, "an exponent in [1, 10000]", o.specular_exponent)},
        {"--base", "none|toon", "under the lines: nothing (default) or a toon-shaded base coat of the tone image",
         [&toon_base](const std::string& v) {
             if (v != "none" && v != "toon") throw Error("--base", "unknown base '" + v + "' (expected none or toon)");
             toon_base = v == "toon";
         }},
        {"--toon-bands", "N", "tone bands of the toon base coat, 2 to 4 (default 3)",
         [&o](const std::string& v) { o.toon_bands = parse_integer("--toon-bands", v, 2, 4); }},
        {"--tone-line-width", "constant|depth|edge-length",
         "tone lines: w everywhere (default), or thinner on distant surfaces, or on finely tessellated ones (down to w/4)",
         [&o](const std::string& v) {
             if (v == "constant") o.width_by = tone::ToneWidthBy::Constant;
             else if (v == "depth") o.width_by = tone::ToneWidthBy::Depth;
             else if (v == "edge-length") o.width_by = tone::ToneWidthBy::EdgeLength;
             else throw Error("--tone-line-width", "unknown mode '" + v + "' (expected constant, depth or edge-length)");
         }},
    };
}

Flag finder_flag(FinderKind& kind) {
    return {"--finder", "exhaustive|randomized",
            "silhouette search: every edge (exact), or seed-and-seek from a --fraction of the edges",
            [&kind](const std::string& v) {
                if (v == "exhaustive") kind = FinderKind::Exhaustive;
                else if (v == "randomized") kind = FinderKind::Randomized;
                else throw Error("--finder", "unknown finder '" + v + "' (expected exhaustive or randomized)");
            }};
}

Flag fraction_flag(double& share) {
    return {"--fraction", "F", "randomized finder: share of the edges sampled, in (0, 1] (default 0.05)",
            [&share](const std::string& v) {
                const double f = parse_number("--fraction", v);
                if (!(f > 0.0 && f <= 1.0)) throw Error("--fraction", "expected a share in (0, 1]");
                share = f;
            }};
}

Flag first_view_flag(bool& first_full) {
    return {"--first-view", "exhaustive|random",
            "frame coherence: the first view by an exhaustive scan (exact) or by random draws",
            [&first_full](const std::string& v) {
                if (v != "exhaustive" && v != "random")
                    throw Error("--first-view", "unknown value '" + v + "' (expected exhaustive or random)");
                first_full = v == "exhaustive";
            }};
}

Flag visibility_flag(VisibilityMethod& method) {
    return {"--visibility", "appel|rays|fast",
            "QI by Appel/Markosian propagation (default, exact), a ray test at every piece (the reference), "
            "or fast: a depth buffer settles what is clear and the exact method the rest (visible lines only; "
            "experimental: within 0.5 % of the exact drawing but not yet faster than appel, docs/fast_visibility.md)",
            [&method](const std::string& v) {
                if (v == "appel") method = VisibilityMethod::Appel;
                else if (v == "rays") method = VisibilityMethod::Rays;
                else if (v == "fast") method = VisibilityMethod::Fast;
                else throw Error("--visibility", "unknown method '" + v + "' (expected appel, rays or fast)");
            }};
}

Flag fast_buffer_flag(int& px) {
    return {"--fast-buffer", "PX",
            "fast visibility: the depth buffer's long side, 64-8192 pixels (default 768; more: slower, closer "
            "to the exact drawing)",
            [&px](const std::string& v) { px = parse_integer("--fast-buffer", v, 64, 8192); }};
}

void check_fast_visibility(VisibilityMethod method, bool hidden, const std::string& what) {
    if (method == VisibilityMethod::Fast && hidden)
        throw BadValue("--visibility=fast draws visible lines only; " + what +
                       " needs the exact QI of hidden lines (use --visibility=appel)");
}

int fast_buffer_px(int given_px, VisibilityMethod method) {
    if (given_px == 0) return FastVisibilityOptions{}.buffer_px;
    if (method != VisibilityMethod::Fast)
        throw BadValue("--fast-buffer sizes the fast visibility's depth buffer: it needs --visibility=fast");
    return given_px;
}

std::vector<Flag> detail_flags(DetailFlags& d) {
    return {
        {"--detail", "PX",
         "draw shape features of about PX pixels: finer ones near the eye, coarser far away (as "
         "--detail-method says; docs/detail.md). Default: off, every feature of the mesh",
         [&d](const std::string& v) {
             const double px = parse_number("--detail", v);
             if (!(px > 0.0 && px <= 10000.0)) throw Error("--detail", "expected a target size in pixels in (0, 10000]");
             d.target_px = px;
         }},
        {"--levels", "N", "--detail: smoothed levels of the model, the input included, 2 to 8 (default 4)",
         [&d](const std::string& v) { d.levels = parse_integer("--levels", v, 2, 8); }},
        {"--detail-method", "multiscale|pm",
         "--detail: how detail is removed: multiscale, smoothed copies of the shape blended per vertex (the default), "
         "or pm, a view-dependent progressive mesh (docs/progressive_mesh.md)",
         [&d](const std::string& v) {
             if (v != "multiscale" && v != "pm")
                 throw Error("--detail-method", "unknown method '" + v + "' (expected multiscale or pm)");
             d.method = v;
             d.method_given = true;
         }},
        {"--detail-ratio", "R",
         "--detail: level k keeps the detail of the first R^k of the vertex splits, in (0, 1) (default 0.5; "
         "the seed's 0.75 smooths less)",
         [&d](const std::string& v) {
             const double r = parse_number("--detail-ratio", v);
             if (!(r > 0.0 && r < 1.0)) throw Error("--detail-ratio", "expected a ratio in (0, 1)");
             d.ratio = r;
         }},
        {"--detail-fairing", "umbrella|second-order",
         "--detail: the fairing functional that predicts the smoothed levels: umbrella (the default) or "
         "second-order (keeps volume, folds fewer faces, smooths less; best with --detail-ratio=0.75; docs/detail.md)",
         [&d](const std::string& v) {
             if (v == "umbrella") d.fairing = MultiscaleFairing::Umbrella;
             else if (v == "second-order") d.fairing = MultiscaleFairing::SecondOrder;
             else throw Error("--detail-fairing", "unknown functional '" + v + "' (expected umbrella or second-order)");
         }},
        {"--detail-smoothing", "none|thin-guarded",
         "--detail: thin-guarded adds an implicit smoothing pass per level that spares thin parts (limbs, "
         "ears): M3's bumps go and thin parts keep their shape, for a slower pre-process (armadillo about "
         "1 s; implies --detail-fairing=second-order and --detail-ratio=0.75 unless given; docs/detail.md)",
         [&d](const std::string& v) {
             if (v == "none") d.smoothing_thin_guarded = false;
             else if (v == "thin-guarded") d.smoothing_thin_guarded = true;
             else throw Error("--detail-smoothing", "unknown smoothing '" + v + "' (expected none or thin-guarded)");
             d.smoothing_given = true;
         }},
        {"--cache", "DIR",
         "--detail: keep the pre-process in DIR (the smoothed levels, or pm's hierarchy), keyed by the model "
         "file's content and the options that change it; reused when they match, rebuilt (one warning) when a "
         "file there is corrupt or stale",
         [&d](const std::string& v) {
             if (v.empty()) throw Error("--cache", "expected a folder");
             d.cache_dir = v;
         }},
        {"--detail-object", "NAME=PX",
         "--detail: object NAME of a scene gets its own target size PX (repeat for more objects; the others take --detail)",
         [&d](const std::string& v) {
             const std::size_t eq = v.rfind('=');
             if (eq == std::string::npos || eq == 0)
                 throw Error("--detail-object", "expected NAME=PX (an object of the scene and its target size), got '" + v + "'");
             const double px = parse_number("--detail-object", v.substr(eq + 1));
             if (!(px > 0.0 && px <= 10000.0)) throw Error("--detail-object", "expected a target size in pixels in (0, 10000]");
             d.object_target_px.emplace_back(v.substr(0, eq), px);
         }},
        {"--detail-depth", "E",
         "--detail: the target grows with depth as (d / d_centre)^E, -1 to 4 (default 0: the same everywhere; "
         "-1: one level for the whole model, the centre's)",
         [&d](const std::string& v) {
             const double e = parse_number("--detail-depth", v);
             if (!(e >= -1.0 && e <= 4.0)) throw Error("--detail-depth", "expected an exponent in [-1, 4]");
             d.depth_exponent = e;
         }},
    };
}

MultiscaleOptions DetailFlags::levels_options() const {
    MultiscaleOptions o;
    o.levels = levels.value_or(o.levels);
    o.ratio = ratio.value_or(o.ratio);
    o.fairing = fairing.value_or(o.fairing);
    // The second-order functional's splits leave folds, spikes at thin tips and slivers; sweeps over
    // each level take most (bench/results/multiscale.md: armadillo's M3 at r = 3/4, mean |k1| 0.193
    // -> 0.151 against M0's 0.187).
    if (o.fairing == MultiscaleFairing::SecondOrder) o.sweeps = 8, o.tangential_sweeps = 32;
    return smoothing_thin_guarded ? thin_guarded(o, ratio.has_value(), fairing.has_value()) : o;
}

void DetailFlags::check(const std::string& command) const {
    if (target_px > 0.0) {
        if (method == "pm" && (fairing || smoothing_given || !object_target_px.empty()))
            throw BadValue("--detail-fairing, --detail-smoothing and --detail-object are for --detail-method=multiscale");
        return;
    }
    if (ratio) throw Usage("--detail-ratio needs --detail=PX", command);
    if (levels) throw Usage("--levels needs --detail=PX", command);
    if (depth_exponent) throw Usage("--detail-depth needs --detail=PX", command);
    if (method_given) throw Usage("--detail-method needs --detail=PX", command);
    if (fairing) throw Usage("--detail-fairing needs --detail=PX", command);
    if (smoothing_given) throw Usage("--detail-smoothing needs --detail=PX", command);
    if (!cache_dir.empty()) throw Usage("--cache needs --detail=PX", command);
    if (!object_target_px.empty()) throw Usage("--detail-object needs --detail=PX", command);
}

Flag subdivide_flag(int& levels) {
    return {"--subdivide", "N", "Loop subdivision levels, 0 to 6, before drawing (default 0)",
            [&levels](const std::string& v) {
                const double n = parse_number("--subdivide", v);
                if (n < 0 || n > 6 || n != std::floor(n))
                    throw Error("--subdivide", "expected a number of levels from 0 to 6");
                levels = int(n);
            }};
}

Flag strict_flag(bool& strict) {
    return switch_flag("--strict", strict, true,
                       "refuse a model that needs repairs (degenerate or duplicate faces, non-manifold edges) "
                       "instead of repairing it; vertices at one position are then not welded");
}

int hardware_threads() {
    return std::clamp(int(std::thread::hardware_concurrency()), 1, kMaxThreads);
}

Flag threads_flag(int& threads, const std::string& unset, bool* given) {
    return {"--threads", "N",
            "threads for each frame (silhouette search, visibility, tone lines), 1 to " + std::to_string(kMaxThreads) +
                " (default " + unset + "; the drawing is the same whatever N)",
            [&threads, given](const std::string& v) {
                threads = parse_integer("--threads", v, 1, kMaxThreads);
                if (given) *given = true;
            }};
}

Flag frames_flag(int& frames, const std::string& what, bool* given) {
    return {"--frames", "N", what + " (1 to 1000000)", [&frames, given](const std::string& v) {
                frames = parse_integer("--frames", v, 1, 1000000);
                if (given) *given = true;
            }};
}

Flag orbit_flag(bool& orbit, const std::string& help) { return switch_flag("--orbit", orbit, true, help); }

Flag jobs_flag(int& jobs, bool* given) {
    return {"--jobs", "N", "frames rendered at once, 1 to 1024 (default: the machine's hardware threads, divided by "
                           "--threads when given; the frames are the same whatever N)",
            [&jobs, given](const std::string& v) {
                jobs = parse_integer("--jobs", v, 1, 1024);
                if (given) *given = true;
            }};
}

Flag frame_rate_flag(double& fps, bool* given) {
    return {"--frame-rate", "FPS",
            "with --detail-method=pm: the sequence's frames a second, the pace of its geomorphs (0.5 s) and of "
            "its temporal smoothing (0.8 s), 1 to 1000 (default " + fmt_number(fps) + ")",
            [&fps, given](const std::string& v) {
                const double f = parse_number("--frame-rate", v);
                if (!(f >= 1.0 && f <= 1000.0)) throw Error("--frame-rate", "expected frames a second in [1, 1000]");
                fps = f;
                *given = true;
            }};
}

Flag frame_range_flag(FrameRange& range) {
    return {"--frame-range", "A:B",
            "render frames A to B only (both included, numbered from 0 as in the whole run, each frame the "
            "same file), to split a sequence between machines",
            [&range](const std::string& v) { range = parse_frame_range(v); }};
}

Flag arc_flag(double& degrees, const std::string& what) {
    return {"--arc", "DEG", what + ", in (0, 3600] (default " + fmt_number(degrees) + ")", [&degrees](const std::string& v) {
                const double a = parse_number("--arc", v);
                if (!(a > 0.0 && a <= 3600.0)) throw Error("--arc", "expected degrees in (0, 3600]");
                degrees = a;
            }};
}

Flag style_flag(std::string& style) {
    return {"--style", "NAME|FILE.json",
            "a preset (clean, technical, sketchy, charcoal, ink-brush, hatched, illustration; found in "
            "$INKLINE_STYLES, else in the styles installed with inkline) or a style file (the format: README.md "
            "beside the presets)",
            [&style](const std::string& v) { style = v; }};
}

Flag switch_flag(const std::string& name, bool& target, bool value_when_given, const std::string& help) {
    return {name, "", help, [&target, value_when_given](const std::string&) { target = value_when_given; }};
}

Flag text_flag(const std::string& name, const std::string& value, std::string& target, const std::string& help) {
    return {name, value, help, [&target](const std::string& v) { target = v; }};
}

}  // namespace inkline
