// SVG for editing (output/writers.cpp, issue 41 part 3): the SVG's paths read back and compared
// with the JSON's pieces of the same view. Chaining must not move the drawing: >= 99.5 % of the
// visible length of each side within 0.5 px of the other's lines of the same kind and QI (specks,
// pieces shorter than a pixel, apart), every path at least a pixel long, and fewer paths than
// pieces (at most half on the armadillo of the issue).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "output/writers.hpp"
#include "pipeline.hpp"
#include "test_data.hpp"

namespace {

using Polyline = std::vector<glm::dvec2>;
// Lines by "kind/qi".
using Lines = std::map<std::string, std::vector<Polyline>>;

double length(const Polyline& p) {
    double l = 0.0;
    for (std::size_t i = 1; i < p.size(); ++i) l += glm::distance(p[i - 1], p[i]);
    return l;
}

// Every <path> of the SVG with its data-kind and data-qi; d is "Mx,y Lx,y x,y ... [Z]".
Lines svg_paths(const std::string& svg) {
    Lines out;
    static const std::regex path_re(R"re(<path [^>]*data-kind="([^"]+)" data-qi="(\d+)"[^>]* d="([^"]+)"/>)re");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), path_re); it != std::sregex_iterator(); ++it) {
        const std::string key = (*it)[1].str() + "/" + (*it)[2].str();
        std::string d = (*it)[3].str();
        Polyline p;
        const bool closed = d.back() == 'Z';
        for (char& c : d)
            if (c == 'M' || c == 'L' || c == 'Z' || c == ',') c = ' ';
        std::istringstream in(d);
        for (double x, y; in >> x >> y;) p.emplace_back(x, y);
        if (closed && !p.empty()) p.push_back(p.front());
        out[key].push_back(std::move(p));
    }
    return out;
}

Lines json_pieces(const std::string& text) {
    Lines out;
    const nlohmann::json j = nlohmann::json::parse(text);
    for (const auto& p : j["polylines"]) {
        Polyline q;
        for (const auto& xy : p["points"]) q.emplace_back(xy[0].get<double>(), xy[1].get<double>());
        out[p["kind"].get<std::string>() + "/" + std::to_string(p["qi"].get<int>())].push_back(std::move(q));
    }
    return out;
}

// Segments binned in a grid of 2 px cells: distance from a point to the nearest, up to a limit.
class NearestSegment {
public:
    explicit NearestSegment(const std::vector<Polyline>& lines) {
        for (const Polyline& p : lines)
            for (std::size_t i = 1; i < p.size(); ++i) {
                const glm::dvec2 a = p[i - 1], b = p[i];
                const std::size_t id = segments_.size();
                segments_.push_back({a, b});
                for (long cx = cell(std::min(a.x, b.x)); cx <= cell(std::max(a.x, b.x)); ++cx)
                    for (long cy = cell(std::min(a.y, b.y)); cy <= cell(std::max(a.y, b.y)); ++cy)
                        grid_[{cx, cy}].push_back(id);
            }
    }
    bool within(const glm::dvec2& q, double limit) const {
        for (long cx = cell(q.x - limit); cx <= cell(q.x + limit); ++cx)
            for (long cy = cell(q.y - limit); cy <= cell(q.y + limit); ++cy) {
                const auto it = grid_.find({cx, cy});
                if (it == grid_.end()) continue;
                for (std::size_t id : it->second) {
                    const auto& [a, b] = segments_[id];
                    const glm::dvec2 ab = b - a;
                    const double t = glm::dot(ab, ab) > 0 ? std::clamp(glm::dot(q - a, ab) / glm::dot(ab, ab), 0.0, 1.0) : 0.0;
                    if (glm::distance(q, a + t * ab) <= limit) return true;
                }
            }
        return false;
    }

private:
    static long cell(double v) { return long(std::floor(v / 2.0)); }
    std::vector<std::pair<glm::dvec2, glm::dvec2>> segments_;
    std::map<std::pair<long, long>, std::vector<std::size_t>> grid_;
};

struct Coverage {
    double total = 0.0, near = 0.0;
    double share() const { return total > 0 ? near / total : 1.0; }
};

// Length of `from` (lines at least `min_length` long) within `limit` px of `to`, by key.
Coverage coverage(const Lines& from, const Lines& to, double limit, double min_length) {
    Coverage c;
    for (const auto& [key, lines] : from) {
        const auto it = to.find(key);
        const NearestSegment index(it == to.end() ? std::vector<Polyline>{} : it->second);
        for (const Polyline& p : lines) {
            if (length(p) < min_length) continue;
            for (std::size_t i = 1; i < p.size(); ++i) {
                const double len = glm::distance(p[i - 1], p[i]);
                const int n = std::max(1, int(std::ceil(len / 0.25)));
                for (int k = 0; k < n; ++k) {
                    const glm::dvec2 q = p[i - 1] + (k + 0.5) / n * (p[i] - p[i - 1]);
                    c.total += len / n;
                    if (index.within(q, limit)) c.near += len / n;
                }
            }
        }
    }
    return c;
}

std::size_t count(const Lines& lines) {
    std::size_t n = 0;
    for (const auto& [key, l] : lines) n += l.size();
    return n;
}

struct Case {
    const char* mesh;
    int camera;  // 0: framed (the command's default); k > 0: random camera k of the series
};

}  // namespace

TEST(SvgPaths, SameDrawingAsTheJsonPiecesFewerPathsNoSpecks) {
    const Case cases[] = {{"fandisk", 0}, {"bunny00", 0}, {"knot1", 0},     {"armadillo", 0},
                          {"elephant", 0}, {"fandisk", 1}, {"armadillo", 2}, {"bunny00", 3}};
    for (const bool hidden : {false, true}) {
        for (const Case& c : cases) {
            const inkline::Model model = inkline::Model::load(inkline::test::mesh_path(c.mesh));
            std::mt19937 rng(41);
            inkline::Camera cam = inkline::test::framed_camera(model.topology().bounds);
            for (int k = 1; k <= c.camera; ++k) cam = inkline::random_camera(rng, model.topology().bounds);
            inkline::ViewOptions vo;
            vo.exact_hidden = hidden;
            const inkline::View view = inkline::render_view(model, cam, vo);
            inkline::OutputOptions o;
            o.hidden = hidden;
            const Lines svg = svg_paths(inkline::drawing_to_svg(view.drawing, o));
            const Lines pieces = json_pieces(inkline::drawing_to_json(view.drawing, o));
            const std::string what = std::string(c.mesh) + " camera " + std::to_string(c.camera) +
                                     (hidden ? " --hidden" : "");
            // The SVG's lines lie on the pieces (coordinates are rounded to 0.001 px) ...
            EXPECT_GE(coverage(svg, pieces, 0.5, 0.0).share(), 0.995) << what;
            // ... and the pieces, specks apart, are in the SVG.
            EXPECT_GE(coverage(pieces, svg, 0.5, 1.0).share(), 0.995) << what;
            for (const auto& [key, lines] : svg)
                for (const Polyline& p : lines) EXPECT_GE(length(p), 1.0 - 1e-3) << what << " " << key;
            EXPECT_LT(count(svg), count(pieces)) << what;
        }
    }
}

// The issue's numbers: armadillo from the default camera drew 1541 paths (492 shorter than a
// pixel); at most half of that now, none short.
TEST(SvgPaths, ArmadilloAtMostHalfTheFormerPaths) {
    const inkline::Model model = inkline::Model::load(inkline::test::mesh_path("armadillo"));
    const inkline::View view = inkline::render_view(model, inkline::test::framed_camera(model.topology().bounds));
    const Lines svg = svg_paths(inkline::drawing_to_svg(view.drawing, {}));
    const Lines pieces = json_pieces(inkline::drawing_to_json(view.drawing, {}));
    EXPECT_EQ(count(pieces), 1541u);  // the drawing itself is unchanged
    EXPECT_LE(count(svg), 1541u / 2);
    for (const auto& [key, lines] : svg)
        for (const Polyline& p : lines) EXPECT_GE(length(p), 1.0 - 1e-3) << key;
}
