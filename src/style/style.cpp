#include "style/style.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/files.hpp"

// The styles' directory relative to the running program's (src/CMakeLists.txt: the install layout,
// which the build tree mirrors with a link to the source's styles/).
#ifndef INKLINE_STYLES_RELATIVE
#define INKLINE_STYLES_RELATIVE "../share/inkline/styles"
#endif

namespace inkline {

namespace fs = std::filesystem;
using json = nlohmann::json;

Style Style::clean() {
    Style s;
    s.name = "clean";
    for (auto& l : s.lines) l = LineStyle{};
    // Lines from curvature suggest shape inside the outline: lighter than it (as the plain
    // writers draw them, output/writers.cpp).
    for (LineKind k : {LineKind::Suggestive, LineKind::Ridge, LineKind::Valley}) s.lines[std::size_t(k)].width = 0.7;
    s.lines[std::size_t(LineKind::ToneHighlight)].rgb = kind_rgb(LineKind::ToneHighlight);  // light lines
    const auto hidden = [](std::uint32_t rgb, double on, double off, double w) {
        LineStyle l;
        l.rgb = rgb;
        l.dash_on = on;
        l.dash_off = off;
        l.width = w;
        return l;
    };
    s.hidden = {hidden(0x7f7f7f, 6, 4, 0.6), hidden(0xa8a8a8, 2, 3, 0.5), hidden(0xcccccc, 1, 4, 0.4)};
    s.hatching.line.width = 0.5;
    s.hatching.line.rgb = 0x333333;
    return s;
}

bool Style::uses_attributes() const {
    for (const auto& l : lines)
        if (l.uses_attributes()) return true;
    for (const auto& l : hidden)
        if (l.uses_attributes()) return true;
    return hatching.line.uses_attributes();
}

const LineStyle& Style::for_qi(LineKind kind, int qi) const {
    static const LineStyle omitted = [] {
        LineStyle l;
        l.omit = true;
        return l;
    }();
    if (qi <= 0) return lines[std::size_t(kind)];
    if (hidden.empty()) return omitted;
    return hidden[std::size_t(std::min<int>(qi, int(hidden.size())) - 1)];
}

const LineStyle& Style::for_line(LineKind kind, int qi, const std::string* object) const {
    if (qi <= 0 && object) {
        const auto it = objects.find(*object);
        if (it != objects.end()) return it->second[std::size_t(kind)];
    }
    return for_qi(kind, qi);
}

namespace {

struct Parser {
    std::string file;
    fs::path dir;

    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw Error(file, "key '" + key + "': " + what);
    }
    void check_keys(const json& j, const std::string& path, const std::set<std::string>& allowed) const {
        if (!j.is_object()) fail(path.empty() ? "(top level)" : path, "expected an object");
        for (const auto& [k, v] : j.items()) {
            if (allowed.count(k)) continue;
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            throw Error(file, "unknown key '" + (path.empty() ? k : path + "." + k) + "' (expected one of " + list + ")");
        }
    }
    double number(const json& v, const std::string& key, double lo, double hi) const {
        if (!v.is_number()) fail(key, "expected a number in [" + fmt(lo) + ", " + fmt(hi) + "], got " + v.dump());
        const double x = v.get<double>();
        if (!(x >= lo && x <= hi)) fail(key, "expected a number in [" + fmt(lo) + ", " + fmt(hi) + "], got " + v.dump());
        return x;
    }
    bool boolean(const json& v, const std::string& key) const {
        if (!v.is_boolean()) fail(key, "expected true or false, got " + v.dump());
        return v.get<bool>();
    }
    std::string string(const json& v, const std::string& key) const {
        if (!v.is_string()) fail(key, "expected a string, got " + v.dump());
        return v.get<std::string>();
    }
    static std::string fmt(double x) {
        std::ostringstream o;
        o << x;
        return o.str();
    }
    std::uint32_t colour(const json& v, const std::string& key) const {
        const std::string s = v.is_string() ? v.get<std::string>() : "";
        bool ok = s.size() == 7 && s[0] == '#';
        for (std::size_t i = 1; ok && i < 7; ++i) ok = std::isxdigit(static_cast<unsigned char>(s[i])) != 0;
        if (!ok) fail(key, "expected a colour \"#rrggbb\", got " + v.dump());
        return std::uint32_t(std::strtoul(s.c_str() + 1, nullptr, 16));
    }
    // A file named by the style: a bare NAME is <dir>/<sub>/NAME<ext>, anything else is a path
    // relative to the style file.
    std::string resolve(const std::string& name, const char* sub, const char* ext, const std::string& key) const {
        fs::path p = name.find('/') == std::string::npos && fs::path(name).extension() != ext
                         ? dir / sub / (name + ext)
                         : dir / name;
        std::error_code ec;  // a name too long for the file system is "no such file" too, not an exception
        if (!fs::exists(p, ec)) fail(key, "no such file '" + p.string() + "'");
        return p.string();
    }

    // "camera" or a direction [x, y, z] towards the light.
    void light(const json& v, const std::string& key, bool& at_camera, glm::dvec3& dir) const {
        const char* expected = "expected \"camera\" or a direction [x, y, z] towards the light";
        if (v.is_string() && v.get<std::string>() == "camera") {
            at_camera = true;
            return;
        }
        if (v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number()) {
            const glm::dvec3 d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
            const double n = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
            if (n > 0 && std::isfinite(n)) {
                at_camera = false;
                dir = d / n;
                return;
            }
        }
        fail(key, std::string(expected) + ", got " + v.dump());
    }

    // Width / height of a PNG, from its IHDR chunk.
    double png_aspect(const std::string& png, const std::string& key) const {
        std::ifstream in(png, std::ios::binary);
        unsigned char h[24] = {};
        in.read(reinterpret_cast<char*>(h), sizeof h);
        const auto be32 = [&](int o) { return (std::uint32_t(h[o]) << 24) | (h[o + 1] << 16) | (h[o + 2] << 8) | h[o + 3]; };
        static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
        if (!in || !std::equal(sig, sig + 8, h) || be32(12) != 0x49484452u || be32(16) == 0 || be32(20) == 0)
            fail(key, "'" + png + "' is not a PNG image");
        return double(be32(16)) / double(be32(20));
    }

    // The line kinds a style turns on: names of mesh and surface line kinds.
    std::vector<LineKind> kinds(const json& j, const std::string& path) const {
        std::string names;
        for (int i = 0; i < kPieceKindCount; ++i)
            if (LineKind(i) != LineKind::Freeform) names += std::string(names.empty() ? "" : ", ") + to_string(LineKind(i));
        if (!j.is_array() || j.empty()) fail(path, "expected a non-empty array of line kinds (" + names + ")");
        std::vector<LineKind> out;
        for (const json& n : j) {
            int found = -1;
            for (int i = 0; i < kPieceKindCount && found < 0; ++i)
                if (n.is_string() && LineKind(i) != LineKind::Freeform && n.get<std::string>() == to_string(LineKind(i)))
                    found = i;
            if (found < 0) fail(path, "unknown line kind " + n.dump() + " (expected one of " + names + ")");
            out.push_back(LineKind(found));
        }
        return out;
    }

    LineStyle line(const json& j, const std::string& path, LineStyle l) const {
        check_keys(j, path,
                   {"colour", "opacity", "width", "width_rule", "taper_length", "taper_min", "width_by_depth",
                    "width_by_light", "dash", "spacing",
                    "offsets", "noise", "brush", "brush_aspect", "omit"});
        for (const auto& [k, v] : j.items()) {
            const std::string key = path + "." + k;
            if (k == "colour") l.rgb = colour(v, key);
            else if (k == "opacity") l.opacity = number(v, key, 0, 1);
            else if (k == "width") l.width = number(v, key, 0, 100);
            else if (k == "width_rule") {
                const std::string r = string(v, key);
                if (r == "constant") l.width_rule = WidthRule::Constant;
                else if (r == "taper") l.width_rule = WidthRule::Taper;
                else fail(key, "expected one of constant, taper, got \"" + r + "\"");
            } else if (k == "taper_length") l.taper_length = number(v, key, 0, 1e4);
            else if (k == "taper_min") l.taper_min = number(v, key, 0, 1);
            else if (k == "width_by_depth" || k == "width_by_light") {
                if (!v.is_array() || v.size() != 2)
                    fail(key, std::string("expected [") + (k == "width_by_depth" ? "near, far" : "lit, dark") +
                                  "] width factors, got " + v.dump());
                const double a = number(v[0], key, 0, 100), b = number(v[1], key, 0, 100);
                if (k == "width_by_depth") l.depth_near = a, l.depth_far = b;
                else l.light_lit = a, l.light_dark = b;
            }
            else if (k == "dash") {
                if (!v.is_array() || v.size() != 2) fail(key, "expected [on, off] in px, got " + v.dump());
                l.dash_on = number(v[0], key, 0, 1e4);
                l.dash_off = number(v[1], key, 0, 1e4);
                if (l.dash_on == 0 && l.dash_off > 0) l.dash_on = 1e-3;  // dots with round caps
            } else if (k == "spacing") l.spacing = number(v, key, 0.05, 100);
            else if (k == "offsets") {
                check_keys(v, key, {"table", "scale", "period"});
                if (!v.contains("table")) fail(key + ".table", "missing (expected an offset table name or file)");
                for (const auto& [k2, v2] : v.items()) {
                    const std::string key2 = key + "." + k2;
                    if (k2 == "table") l.offsets = load_offset_table(resolve(string(v2, key2), "offsets", ".txt", key2));
                    else if (k2 == "scale") l.offset_scale = number(v2, key2, -100, 100);
                    else {
                        l.offset_period = number(v2, key2, 0, 1e4);
                        if (l.offset_period > 0 && l.offset_period < 0.1)
                            fail(key2, "expected 0 (the table's period) or at least 0.1 px, got " + v2.dump());
                    }
                }
            } else if (k == "noise") {
                check_keys(v, key, {"normal", "tangent", "wavelength"});
                for (const auto& [k2, v2] : v.items()) {
                    const std::string key2 = key + "." + k2;
                    if (k2 == "normal") l.noise.normal = number(v2, key2, -1000, 1000);
                    else if (k2 == "tangent") l.noise.tangent = number(v2, key2, -1000, 1000);
                    else l.noise.wavelength = number(v2, key2, 0.01, 1e6);
                }
            } else if (k == "brush") {
                const std::string b = string(v, key);
                l.brush = b.empty() ? "" : resolve(b, "brushes", ".png", key);
            } else if (k == "brush_aspect") l.brush_aspect = number(v, key, 0, 1000);
            else l.omit = boolean(v, key);
        }
        if (l.offsets && l.offset_period > 0 &&
            double(l.offsets->vertices.size()) > kMaxOffsetVerticesPerPx * l.offset_period)
            fail(path + ".offsets.period", "table '" + l.offsets->name + "' has " +
                                               std::to_string(l.offsets->vertices.size()) + " vertices, more than 100 per px of a " +
                                               fmt(l.offset_period) + " px period");
        if (j.contains("brush") && !j.contains("brush_aspect") && !l.brush.empty())
            l.brush_aspect = png_aspect(l.brush, path + ".brush");
        return l;
    }

    Style style(const json& root) const {
        Style s = Style::clean();
        s.file = file;
        s.name = fs::path(file).stem().string();
        check_keys(root, "", {"name", "description", "background", "base_width", "draw_hidden", "light", "chain",
                              "kinds", "lines", "hidden", "hatching", "objects"});
        for (const auto& [k, v] : root.items()) {
            if (k == "name") s.name = string(v, k);
            else if (k == "description") string(v, k);
            else if (k == "background") s.background = colour(v, k);
            else if (k == "base_width") s.base_width = number(v, k, 0, 1000);
            else if (k == "draw_hidden") s.draw_hidden = boolean(v, k);
            else if (k == "kinds") s.kinds = kinds(v, k);
            else if (k == "light") light(v, k, s.light_at_camera, s.light);
            else if (k == "chain") {
                check_keys(v, k, {"join", "max_turn_degrees", "join_distance", "keep_specks"});
                for (const auto& [k2, v2] : v.items()) {
                    const std::string key = k + "." + k2;
                    if (k2 == "join") s.chain = boolean(v2, key);
                    else if (k2 == "keep_specks") s.keep_specks = boolean(v2, key);
                    else if (k2 == "max_turn_degrees") s.max_turn_degrees = number(v2, key, 0, 180);
                    else s.join_distance = number(v2, key, 0, 1);
                }
            } else if (k == "lines") {
                std::set<std::string> kinds{"default"};
                for (int i = 0; i < kPieceKindCount; ++i) kinds.insert(to_string(LineKind(i)));
                check_keys(v, k, kinds);
                LineStyle base = s.lines[0];
                if (v.contains("default")) base = line(v["default"], "lines.default", base);
                for (int i = 0; i < kPieceKindCount; ++i) {
                    const std::string kind = to_string(LineKind(i));
                    // Highlight lines are light whatever colour the other lines take, unless named.
                    LineStyle own = base;
                    if (LineKind(i) == LineKind::ToneHighlight) own.rgb = kind_rgb(LineKind::ToneHighlight);
                    s.lines[std::size_t(i)] = v.contains(kind) ? line(v[kind], "lines." + kind, own) : own;
                }
            } else if (k == "objects") {
                if (!v.is_object()) fail(k, "expected an object of object names, got " + v.dump());
            } else if (k == "hidden") {
                if (!v.is_array()) fail(k, "expected an array of line styles, one per QI level from 1, got " + v.dump());
                const std::vector<LineStyle> clean = s.hidden;
                s.hidden.clear();
                for (std::size_t i = 0; i < v.size(); ++i)
                    s.hidden.push_back(line(v[i], "hidden[" + std::to_string(i) + "]", clean[std::min(i, clean.size() - 1)]));
            } else {
                check_keys(v, k, {"enabled", "threshold", "light", "length", "segments", "min_pixels", "by_area",
                                  "spacing", "seed", "line"});
                HatchStyle& h = s.hatching;
                for (const auto& [k2, v2] : v.items()) {
                    const std::string key = k + "." + k2;
                    if (k2 == "enabled") h.enabled = boolean(v2, key);
                    else if (k2 == "threshold") h.threshold = number(v2, key, 0, 1);
                    else if (k2 == "light") light(v2, key, h.light_at_camera, h.light);
                    else if (k2 == "length") h.length = number(v2, key, 1e-6, 10);
                    else if (k2 == "segments") h.segments = int(number(v2, key, 1, 64));
                    else if (k2 == "min_pixels") h.min_pixels = number(v2, key, 0, 1e4);
                    else if (k2 == "by_area") h.by_area = boolean(v2, key);
                    else if (k2 == "spacing") h.spacing = number(v2, key, 0.002, 10);  // bounds the particle count
                    else if (k2 == "seed") h.seed = std::uint32_t(number(v2, key, 0, 4294967295.0));
                    else h.line = line(v2, key + ".line", h.line);
                }
            }
        }
        if (root.contains("objects")) objects(root["objects"], s);  // over the final `lines`
        return s;
    }

    // "objects": {"NAME": {"default": LINE, "silhouette": LINE, ...}}: per kind, the style's line
    // with the object's "default" over it, then the object's entry for the kind.
    void objects(const json& v, Style& s) const {
        std::set<std::string> kinds{"default"};
        for (int i = 0; i < kPieceKindCount; ++i) kinds.insert(to_string(LineKind(i)));
        for (const auto& [name, o] : v.items()) {
            const std::string path = "objects." + name;
            check_keys(o, path, kinds);
            auto& lines = s.objects[name];
            for (int i = 0; i < kPieceKindCount; ++i) {
                const std::string kind = to_string(LineKind(i));
                LineStyle l = s.lines[std::size_t(i)];
                if (o.contains("default")) l = line(o["default"], path + ".default", l);
                lines[std::size_t(i)] = o.contains(kind) ? line(o[kind], path + "." + kind, l) : l;
            }
        }
    }
};

}  // namespace

Style parse_style(const std::string& text, const std::string& file) {
    json root;
    try {
        root = json::parse(text);
    } catch (const json::exception& e) {  // parse_error, and out_of_range for a number like 1e999
        std::string what = e.what();
        if (const auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);  // "[json.exception.x.n] "
        throw Error(file, "not valid JSON: " + what);
    }
    Parser p{file, fs::path(file).parent_path()};
    return p.style(root);
}

Style load_style_file(const std::string& path) {
    return parse_style(read_whole_file(path, "style file"), path);
}

std::string styles_dir() {
    if (const char* env = std::getenv("INKLINE_STYLES"); env && *env) return env;
    // Found from the program, not from a path compiled in: an installed tree can be moved, and a
    // program built against the installed library passes its directory to load_style instead.
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return INKLINE_STYLES_RELATIVE;
    return (exe.parent_path() / INKLINE_STYLES_RELATIVE).lexically_normal().string();
}

Style load_style(const std::string& name) { return load_style(name, styles_dir()); }

Style load_style(const std::string& name, const std::string& dir) {
    if (name.find('/') != std::string::npos || fs::path(name).extension() == ".json") return load_style_file(name);
    const fs::path p = fs::path(dir) / (name + ".json");
    if (std::error_code missing; !fs::exists(p, missing)) {
        std::error_code ec;
        if (!fs::is_directory(dir, ec))
            throw Error("--style", "no style '" + name + "': the styles directory " + dir +
                                       " does not exist (set INKLINE_STYLES to the directory of the style files)");
        std::string known;
        for (const auto& e : fs::directory_iterator(dir, ec))
            if (e.path().extension() == ".json") known += (known.empty() ? "" : ", ") + e.path().stem().string();
        throw Error("--style", "no style '" + name + "' in " + dir + " (expected one of " + known +
                                   ", or a .json file)");
    }
    return load_style_file(p.string());
}

}  // namespace inkline
