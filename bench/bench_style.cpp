// Stylization time of one frame per preset (strokes, offsets, noise, outlines, brush quads, and
// for `hatched` the shading strokes with their ray tests; depth and tone per line point for the
// presets whose widths use them) against the visibility time of the same
// frame, on the sample meshes with the default camera (1024 x 1024; visible lines, and hidden ones
// for the presets that draw them). Both in process CPU time (all threads), so a loaded machine
// does not skew the ratio: style_ms per iteration, vis_ms the least of 5 runs of the visibility
// stage (build_pieces + assign_qi_appel, as render_view runs it). The drawing to pixels (Cairo)
// is timed apart (`draw_png/`). Usage: bench_style [--benchmark_filter=armadillo].
#include <benchmark/benchmark.h>

#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "core/clock.hpp"
#include "output/styled.hpp"
#include "pipeline.hpp"
#include "style/attributes.hpp"
#include "style/hatching.hpp"
#include "style/style.hpp"
#include "style/stylize.hpp"

namespace {

const char* kMeshes[] = {"armadillo", "fandisk", "bunny00", "elephant", "ChineseDragon-10kv", "knot1"};
const char* kStyles[] = {"clean", "technical", "sketchy", "charcoal", "ink-brush", "hatched"};

struct Frame {
    std::unique_ptr<inkline::Model> model;
    inkline::Camera camera;
    inkline::View view;
    double vis_ms = 0.0;  // visibility stage, process CPU ms, least of 5 runs
};

const Frame* frame(const std::string& name, bool hidden) {
    static std::map<std::string, std::unique_ptr<Frame>> cache;
    auto& f = cache[name + (hidden ? "/hidden" : "")];
    if (!f) {
        const std::string path = std::string(INKLINE_DATA_DIR) + "/meshes/" + name + ".off";
        if (!std::filesystem::exists(path)) return nullptr;
        f = std::make_unique<Frame>();
        f->model = std::make_unique<inkline::Model>(inkline::Model::load(path));
        f->model->rays();
        f->model->self_intersecting_faces();
        f->camera = inkline::Camera::framing(f->model->topology().bounds, 1024, 1024);
        f->camera.set_near(inkline::default_near(f->model->topology()));
        inkline::ViewOptions opt;
        opt.exact_hidden = hidden;
        f->view = inkline::render_view(*f->model, f->camera, opt);
        const inkline::MeshTopology& mesh = f->model->topology();
        const inkline::Features features = inkline::extract_features(mesh, f->camera);
        f->vis_ms = 1e300;
        for (int i = 0; i < 5; ++i) {
            const double t0 = inkline::process_cpu_seconds();
            inkline::PieceGraph g = inkline::build_pieces(mesh, features, f->camera);
            inkline::assign_qi_appel(mesh, f->camera, features.face_front,
                                     [&]() -> const inkline::RayCaster& { return f->model->rays(); }, g,
                                     {hidden, f->model->pierced_faces(), true});
            f->vis_ms = std::min(f->vis_ms, 1e3 * (inkline::process_cpu_seconds() - t0));
            benchmark::DoNotOptimize(g);
        }
    }
    return f.get();
}

inkline::StyledDrawing stylize(const Frame& f, const inkline::Style& style, std::size_t* hatches) {
    std::vector<std::vector<glm::dvec2>> h;
    if (style.hatching.enabled)
        for (auto& s : inkline::hatch_strokes(f.model->topology(), f.camera, f.model->rays(), style.hatching))
            h.push_back(std::move(s.points));
    *hatches = h.size();
    std::optional<inkline::PointAttributes> attr;
    if (style.uses_attributes())
        attr = inkline::point_attributes(f.model->topology(), f.camera, f.view.drawing, f.view.spans,
                                         style.light_at_camera, style.light);
    return inkline::stylize(f.view.drawing, style, false, h, nullptr, attr ? &*attr : nullptr);
}

void BM_Stylize(benchmark::State& state, const char* mesh, const char* style_name) {
    const inkline::Style style = inkline::load_style(style_name);
    const Frame* f = frame(mesh, style.draw_hidden);
    if (!f) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    std::size_t hatches = 0;
    double total = 0.0;
    for (auto _ : state) {
        const double t0 = inkline::process_cpu_seconds();
        auto sd = stylize(*f, style, &hatches);
        total += inkline::process_cpu_seconds() - t0;
        benchmark::DoNotOptimize(sd);
    }
    const double ms = 1e3 * total / double(std::max<std::int64_t>(1, state.iterations()));
    state.counters["style_ms"] = ms;
    state.counters["vis_ms"] = f->vis_ms;
    state.counters["style_over_vis"] = ms / f->vis_ms;
    state.counters["hatches"] = double(hatches);
}

void BM_Draw(benchmark::State& state, const char* mesh, const char* style_name) {
    const inkline::Style style = inkline::load_style(style_name);
    const Frame* f = frame(mesh, style.draw_hidden);
    if (!f) return state.SkipWithError("mesh not found (run scripts/setup.sh)");
    std::size_t hatches = 0;
    const auto sd = stylize(*f, style, &hatches);
    for (auto _ : state) benchmark::DoNotOptimize(inkline::styled_to_bytes(sd, inkline::Format::Png));
}

int reg = [] {
    for (const char* m : kMeshes)
        for (const char* s : kStyles) {
            benchmark::RegisterBenchmark((std::string("stylize/") + m + "/" + s).c_str(), BM_Stylize, m, s)
                ->Unit(benchmark::kMillisecond);
            benchmark::RegisterBenchmark((std::string("draw_png/") + m + "/" + s).c_str(), BM_Draw, m, s)
                ->Unit(benchmark::kMillisecond);
        }
    return 0;
}();

}  // namespace

BENCHMARK_MAIN();
