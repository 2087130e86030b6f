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
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "pipeline.hpp"

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

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> meshes;
    bool session = false, details = false;
    double distance = 1.0;
    int threads = 1;
    const std::string dir = std::string(INKLINE_DATA_DIR) + "/meshes/";
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--session") == 0) {
            session = true;
        } else if (std::strcmp(argv[i], "--details") == 0) {
            details = true;
        } else if (std::strncmp(argv[i], "--distance=", 11) == 0) {
            distance = std::stod(argv[i] + 11);
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
        std::mt19937 rng(7u);
        auto options = [threads](int variant) {
            inkline::ViewOptions o;
            o.threads = threads;
            o.visibility = variant == 4 ? inkline::VisibilityMethod::Rays : inkline::VisibilityMethod::Appel;
            o.exact_hidden = variant == 0 || variant == 4;
            o.walk = variant != 2;
            if (variant == 3) o.features.kinds[int(inkline::LineKind::Crease)] = false;
            return o;
        };
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
    for (int variant = 0; variant < 5; ++variant) {
        const Total& t = total[variant];
        std::printf("total var %d: pieces %zu rays %zu walks %zu differ %zu/%zu (%zu meshes skipped)\n", variant, t.pieces,
                    t.rays, t.walks, t.differ, t.differ_vis, skipped);
    }
    return 0;
}
