// The progressive mesh (src/detail/progressive_mesh.hpp) along a dolly: hierarchy build time and
// memory, then per frame the adaptation (ms, triangles kept, collapses, passes) and the drawing's
// line density (visible silhouette and suggestive-contour length per square pixel of the model's
// image disc), beside the density of the full mesh. Not a test: numbers go to bench/results/pm.md.
//
//   pm_dolly [MESH[@N]] [PX] [FRAMES] [FROM] [TO]   (defaults armadillo 4 9 1 8: distances in
//                                                     multiples of the framed distance)
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "bench_models.hpp"
#include "core/clock.hpp"
#include "pm_bench_util.hpp"
#include "detail/progressive_mesh.hpp"

using namespace inkline;
using inkline::process_cpu_seconds;
using inkline::bench::status_mib;

namespace {

// Visible ink (silhouettes, suggestive contours) in pixels over the image area of the model's
// bounding sphere (issue 43's measure, so that the two methods' tables compare).
double line_density(const View& view, const MeshTopology& mesh, const Camera& cam,
                    std::optional<LineKind> kind = std::nullopt) {
    double length = 0.0;
    for (const Piece& p : view.drawing.pieces)
        if (p.qi == 0 && (!kind || p.kind == *kind))
            for (std::size_t i = 1; i < p.points.size(); ++i) length += glm::length(p.points[i] - p.points[i - 1]);
    const double radius_px = mesh.bounds.half_diagonal() * cam.focal() / glm::length(cam.eye() - mesh.bounds.center());
    return length / (M_PI * radius_px * radius_px);
}

}  // namespace

int main(int argc, char** argv) {
    const std::string name = argc > 1 ? argv[1] : "armadillo";
    const double px = argc > 2 ? std::atof(argv[2]) : 4.0;
    const int frames = argc > 3 ? std::atoi(argv[3]) : 9;
    const double from = argc > 4 ? std::atof(argv[4]) : 1.0, to = argc > 5 ? std::atof(argv[5]) : 8.0;
    const Model* model = bench_model_for(name, "pm_dolly");
    if (!model) return 1;
    const double rss_model = status_mib("VmRSS");
    const auto t0 = StageClock::now();
    const double cpu0 = process_cpu_seconds();
    const ProgressiveMesh pm(model->topology());
    const double build = seconds_since(t0), build_cpu = process_cpu_seconds() - cpu0;
    std::printf("%s: %zu triangles, hierarchy of %zu collapses built in %.3f s (%.3f s CPU), %.2f MiB of arrays; "
                "RSS %.1f -> %.1f MiB (peak %.1f MiB)\n",
                name.c_str(), model->topology().faces.size(), pm.collapses(), build, build_cpu,
                pm.hierarchy_bytes() / 1048576.0,
                rss_model, status_mib("VmRSS"), status_mib("VmHWM"));
    const Camera framed = Camera::framing(model->topology().bounds, 1024, 1024);
    const glm::dvec3 c = model->topology().bounds.center();
    DetailCriterion criterion;
    criterion.target_area_px = px * px;
    ViewOptions options;
    options.surface.suggestive = true;
    options.features.kinds[int(LineKind::Crease)] = false;  // silhouettes and suggestive contours
    std::printf("frame distance triangles collapses passes adapt_ms adapt_cpu_ms density_pm density_full suggestive_pm suggestive_full\n");
    for (int k = 0; k < frames; ++k) {
        const double t = frames > 1 ? double(k) / (frames - 1) : 0.0;
        const double times = from * std::pow(to / from, t);  // geometric: the same zoom factor a frame
        const Camera cam = Camera::perspective(c + times * (framed.eye() - c), c, framed.up(), framed.fov_deg(), 1024, 1024);
        AdaptStats s;
        const double c0 = process_cpu_seconds();
        TriangleMesh mesh = pm.adapt(cam, criterion, &s);
        const double adapt_cpu = process_cpu_seconds() - c0;
        const Model adapted(std::move(mesh), model->topology().crease_degrees);
        const View v_pm = render_view(adapted, cam, options), v_full = render_view(*model, cam, options);
        const double d_pm = line_density(v_pm, model->topology(), cam);
        const double d_full = line_density(v_full, model->topology(), cam);
        const double s_pm = line_density(v_pm, model->topology(), cam, LineKind::Suggestive);
        const double s_full = line_density(v_full, model->topology(), cam, LineKind::Suggestive);
        std::printf("%d %.3f %zu %zu %zu %.1f %.1f %.5f %.5f %.5f %.5f\n", k, times, s.triangles, s.collapses,
                    s.passes, s.seconds * 1e3, adapt_cpu * 1e3, d_pm, d_full, s_pm, s_full);
    }
    std::printf("peak RSS %.1f MiB\n", status_mib("VmHWM"));
    return 0;
}
