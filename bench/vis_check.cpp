// Regression check for visibility optimizations: prints, per (mesh, camera, method, options), the
// statistics of the view and a hash of every piece (kind, curve, QI, point bits, spans), and how
// many pieces' QI differ from the reference method (rays; for the variant without creases, rays
// without creases). Two builds that print the same lines gave the same results (for views without
// exact hidden QI: the same visible pieces).
// Usage: vis_check [--session] [--all] [--distance=F] [--threads=N] [--details] [mesh ...]
// (default: the bench meshes without subdivision, and armadillo@1); meshes come from
// INKLINE_DATA_DIR (a name without an extension is the .off file; --all: every mesh file there,
// those that do not load reported and skipped). With --session the views of each variant come from
// one ViewSession per mesh (storage reused from camera to camera) instead of render_view: the same
// lines are expected. --distance: the random cameras F times as far (1: the model about fills the
// image; their orthographic views F times as high). --threads: the visibility stage on N threads
// (in large views; the same lines are expected). --details: after a view's line, each piece whose
// visibility differs. The last lines total each variant over all views (pieces, ray tests, walks,
// pieces whose QI / visibility differ from the reference).
// --geometry=ORDER prints instead, per case, what does not depend on how the mesh is numbered:
// the drawing's visible length and hidden length per QI (px, rounded), and the length that
// differs (missing + extra, within 1e-6 px, each kind and QI against its own) from the drawing of
// the same mesh numbered in ORDER: `input` (the file's order, no Hilbert order), `shuffled` (at
// random), `median` (the Hilbert order before the keys: CGAL's hilbert_sort, median policy).
// With --details, a differing case's classes (kind, QI) that differ. Lines of two builds compare with diff; the last lines count the cases that differ.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <random>
#include <string>
#include <vector>

#include "model/reorder.hpp"
#include "model/subdivide.hpp"
#include "pipeline.hpp"
#include "visibility/line_difference.hpp"

namespace {

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
    h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    return h * 0xff51afd7ed558ccdull;
}
std::uint64_t bits(double d) {
    std::uint64_t u;
    std::memcpy(&u, &d, 8);
    return u;
}

// (scale: the distance, and an orthographic view's height, times scale)
inkline::Camera random_camera(std::mt19937& rng, const inkline::Bounds3& box, bool ortho, double scale) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double z = 2.0 * u(rng) - 1.0, phi = 2.0 * M_PI * u(rng), s = std::sqrt(1.0 - z * z);
    const glm::dvec3 dir(s * std::cos(phi), z, s * std::sin(phi));
    const double fov = 25.0 + 25.0 * u(rng), R = box.half_diagonal();
    const double dist = scale * R / std::sin(fov * M_PI / 360.0) * (0.7 + 0.8 * u(rng));
    const glm::dvec3 target = box.center() + 0.2 * R * glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    const glm::dvec3 up = std::abs(dir.y) > 0.95 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    if (ortho) return inkline::Camera::orthographic(target + dist * dir, target, up, 2.2 * R * scale, 1024, 1024);
    return inkline::Camera::perspective(target + dist * dir, target, up, fov, 1024, 1024);
}

inkline::ViewOptions variant_options(int variant, int threads) {
    inkline::ViewOptions o;
    o.threads = threads;
    o.visibility = variant == 4 ? inkline::VisibilityMethod::Rays : inkline::VisibilityMethod::Appel;
    o.exact_hidden = variant == 0 || variant == 4;
    o.walk = variant != 2;
    if (variant == 3) o.features.kinds[int(inkline::LineKind::Crease)] = false;
    return o;
}

// The mesh of `path` as Model::load makes it (strict), but numbered in `order`.
inkline::Model model_in_order(const std::string& path, int levels, const std::string& order) {
    inkline::LoadOptions strict;
    strict.strict = true;
    inkline::TriangleMesh mesh = inkline::subdivide_loop(inkline::load_mesh(path, strict), levels);
    if (order == "shuffled") mesh = inkline::shuffled_numbering(std::move(mesh), 11u);
    else if (order == "median") mesh = inkline::hilbert_ordered_median(std::move(mesh));
    else if (order != "input") throw std::runtime_error("--geometry: unknown order " + order);
    return inkline::Model(std::move(mesh), 40.0);
}

// Visible length, then hidden length per QI (QI 1 for every hidden piece without exact QI).
std::string length_summary(const inkline::Drawing& d, bool qi_levels) {
    std::vector<double> by_qi;
    for (const auto& p : d.pieces) {
        const std::size_t qi = qi_levels ? std::size_t(p.qi) : std::size_t(p.qi > 0);
        if (by_qi.size() <= qi) by_qi.resize(qi + 1, 0.0);
        for (std::size_t q = 1; q < p.points.size(); ++q) by_qi[qi] += glm::length(p.points[q] - p.points[q - 1]);
    }
    by_qi.resize(std::max<std::size_t>(by_qi.size(), 1), 0.0);
    char b[64];
    std::snprintf(b, sizeof b, "visible %.3f hidden", by_qi[0]);
    std::string out = b;
    for (std::size_t qi = 1; qi < by_qi.size(); ++qi) {
        std::snprintf(b, sizeof b, " %.3f", by_qi[qi]);
        out += b;
    }
    return out;
}

constexpr double kRoundingPx = 1e-6;

struct GeometryTotals {
    std::size_t cases = 0, differing = 0;
    double differ_px = 0.0, max_px = 0.0;
};

void geometry_cases(const std::string& name, const inkline::Model& model, const inkline::Model& other, int threads,
                    double distance, bool details, GeometryTotals (&total)[5]) {
    std::mt19937 rng(7u);
    for (int k = 0; k < 16; ++k) {
        const inkline::Camera cam = k == 0 ? inkline::Camera::framing(model.topology().bounds, 1024, 1024)
                                           : random_camera(rng, model.topology().bounds, k >= 13, distance);
        for (int variant = 0; variant < 5; ++variant) {
            const inkline::ViewOptions o = variant_options(variant, threads);
            const inkline::View a = inkline::render_view(model, cam, o), b = inkline::render_view(other, cam, o);
            const inkline::LineDifference d = inkline::drawing_difference(a.drawing, b.drawing, 1e-6, o.exact_hidden);
            const double px = d.missing_px + d.extra_px;
            GeometryTotals& t = total[variant];
            // (a drawing compared with itself can leave 1e-13 px: its length less its length near)
            ++t.cases, t.differing += px > kRoundingPx, t.differ_px += px, t.max_px = std::max(t.max_px, px);
            std::printf("%s cam %2d var %d: %s differ %.3g px\n", name.c_str(), k, variant,
                        length_summary(a.drawing, o.exact_hidden).c_str(), px);
            if (details && px > kRoundingPx)
                for (const auto& c : inkline::drawing_difference_by_class(a.drawing, b.drawing, 1e-6, o.exact_hidden))
                    if (c.difference.missing_px + c.difference.extra_px > 0.0)
                        std::printf("  kind %d qi %d: %.4f px, missing %.4f extra %.4f\n", int(c.kind), c.qi,
                                    c.difference.reference_px, c.difference.missing_px, c.difference.extra_px);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> meshes;
    bool session = false, details = false;
    double distance = 1.0;
    std::string geometry_order;  // empty: the hashes
    int threads = 1;
    const std::string dir = std::string(INKLINE_DATA_DIR) + "/meshes/";
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--session") == 0) {
            session = true;
        } else if (std::strcmp(argv[i], "--details") == 0) {
            details = true;
        } else if (std::strncmp(argv[i], "--distance=", 11) == 0) {
            distance = std::stod(argv[i] + 11);
        } else if (std::strncmp(argv[i], "--geometry=", 11) == 0) {
            geometry_order = argv[i] + 11;
        } else if (std::strncmp(argv[i], "--threads=", 10) == 0) {
            threads = std::stoi(argv[i] + 10);
        } else if (std::strcmp(argv[i], "--all") == 0) {
            std::vector<std::string> all;
            for (const auto& entry : std::filesystem::directory_iterator(dir))
                if (entry.is_regular_file()) all.push_back(entry.path().filename().string());
            std::sort(all.begin(), all.end());
            meshes.insert(meshes.end(), all.begin(), all.end());
        } else {
            meshes.push_back(argv[i]);
        }
    if (meshes.empty())
        meshes = {"armadillo", "bunny00", "fandisk", "elephant", "knot1", "ChineseDragon-10kv", "armadillo@1"};
    struct Total {
        std::size_t pieces = 0, rays = 0, walks = 0, differ = 0, differ_vis = 0;
    };
    Total total[5];
    GeometryTotals geometry_total[5];
    std::size_t skipped = 0;
    for (const std::string& name : meshes) {
        const auto at = name.find('@');
        const int levels = at == std::string::npos ? 0 : std::stoi(name.substr(at + 1));
        const std::string file = name.substr(0, at);
        const std::string path = dir + file + (std::filesystem::path(file).has_extension() ? "" : ".off");
        std::optional<inkline::Model> loaded;
        try {
            loaded.emplace(inkline::Model::load(path, 40.0, levels));
        } catch (const std::exception& e) {
            std::printf("%s: skipped: %s\n", name.c_str(), e.what());
            ++skipped;
            continue;
        }
        const inkline::Model& model = *loaded;
        if (!geometry_order.empty()) {
            geometry_cases(name, model, model_in_order(path, levels, geometry_order), threads, distance, details,
                           geometry_total);
            continue;
        }
        std::mt19937 rng(7u);
        auto options = [threads](int variant) { return variant_options(variant, threads); };
        std::vector<inkline::ViewSession> sessions;
        for (int variant = 0; variant < 5; ++variant) sessions.emplace_back(model, options(variant));
        for (int k = 0; k < 16; ++k) {
            const inkline::Camera cam = k == 0 ? inkline::Camera::framing(model.topology().bounds, 1024, 1024)
                                               : random_camera(rng, model.topology().bounds, k >= 13, distance);
            const inkline::View ref = session ? sessions[4].render(cam) : inkline::render_view(model, cam, options(4));
            // Variant 3's own reference: rays with creases off (its curves differ from the others').
            inkline::ViewOptions o3 = options(3);
            o3.visibility = inkline::VisibilityMethod::Rays;
            o3.exact_hidden = true;
            const inkline::View ref3 = inkline::render_view(model, cam, o3);
            for (int variant = 0; variant < 5; ++variant) {
                const inkline::ViewOptions o = options(variant);
                const inkline::View& v =
                    variant == 4 ? ref : session ? sessions[variant].render(cam) : inkline::render_view(model, cam, o);
                std::uint64_t h = 0;
                std::size_t differ = 0, differ_vis = 0;
                for (std::size_t i = 0; i < v.drawing.pieces.size(); ++i) {
                    const auto& p = v.drawing.pieces[i];
                    // Without exact hidden QI only visible / hidden is defined (hidden pieces keep
                    // a lower bound, which depends on how their cluster was decided).
                    const int qi = o.exact_hidden ? p.qi : p.qi > 0;
                    h = mix(h, std::uint64_t(p.kind) | std::uint64_t(p.curve) << 8 | std::uint64_t(std::uint32_t(qi)) << 40);
                    for (const auto& q : p.points) h = mix(mix(h, bits(q.x)), bits(q.y));
                    for (const auto& s : v.spans[i]) h = mix(mix(mix(h, s.edge), bits(s.s0)), bits(s.s1));
                    const inkline::View& r = variant == 3 ? ref3 : ref;
                    if (i < r.drawing.pieces.size()) {
                        differ += r.drawing.pieces[i].qi != p.qi;
                        const bool vis_differs = (r.drawing.pieces[i].qi == 0) != (p.qi == 0);
                        differ_vis += vis_differs;
                        if (vis_differs && details) {
                            double len = 0.0;
                            for (std::size_t q = 1; q < p.points.size(); ++q) len += glm::length(p.points[q] - p.points[q - 1]);
                            std::printf("  piece %zu (kind %d, edge %u): QI %d, reference %d, %.4f px from (%.2f, %.2f)\n", i,
                                        int(p.kind), v.spans[i].front().edge, p.qi, r.drawing.pieces[i].qi, len,
                                        p.points.front().x, p.points.front().y);
                        }
                    }
                }
                const auto& s = v.drawing.stats;
                Total& t = total[variant];
                t.pieces += s.pieces, t.rays += s.ray_tests, t.walks += s.walks, t.differ += differ, t.differ_vis += differ_vis;
                std::printf("%s cam %2d var %d: pieces %zu crossings %zu clusters %zu walks %zu rays %zu differ %zu/%zu hash %016llx\n",
                            name.c_str(), k, variant, s.pieces, s.crossings, s.clusters, s.walks, s.ray_tests, differ,
                            differ_vis, (unsigned long long)h);
            }
        }
    }
    if (!geometry_order.empty()) {
        for (int variant = 0; variant < 5; ++variant) {
            const GeometryTotals& t = geometry_total[variant];
            std::printf("total var %d: %zu cases, %zu differ (more than 1e-6 px) from the %s order's drawing, by %.3g px (at most %.3g px a case) "
                        "(%zu meshes skipped)\n", variant, t.cases, t.differing, geometry_order.c_str(), t.differ_px,
                        t.max_px, skipped);
        }
        return 0;
    }
    for (int variant = 0; variant < 5; ++variant) {
        const Total& t = total[variant];
        std::printf("total var %d: pieces %zu rays %zu walks %zu differ %zu/%zu (%zu meshes skipped)\n", variant, t.pieces,
                    t.rays, t.walks, t.differ, t.differ_vis, skipped);
    }
    return 0;
}
