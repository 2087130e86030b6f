// The exact frame (exhaustive finder, Appel visibility: the bench's reference row) on 1..N
// threads, stage by stage, along the bench's orbit (src/app/bench.cpp). Each thread count has its
// own session and the counts take turns frame by frame (a burst of load on a shared machine then
// slows every count alike). Per stage: the median ms per frame (wall clock) and its share of the
// one-thread frame; per count: the frame's median, its CPU time (the process's CPU clock: all
// threads' work), the ratio to one thread, and whether every drawing equals the one-thread one
// (a hash of every piece: kind, curve, QI, points). On a loaded machine the calling thread's CPU
// time per frame is the steadier measure of the split (see its row).
// Usage: frame_threads MESH[@N] [--frames=F] [--threads=1,2,...] [--surface] [--markdown=FILE]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/clock.hpp"
#include "bench_models.hpp"

namespace {


double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
    h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    return h;
}

std::uint64_t drawing_hash(const inkline::Drawing& d) {
    std::uint64_t h = 0;
    for (const inkline::Piece& p : d.pieces) {
        h = mix(h, std::uint64_t(p.kind) | std::uint64_t(p.curve) << 8 | std::uint64_t(std::uint32_t(p.qi)) << 40);
        for (const auto& q : p.points) {
            std::uint64_t x, y;
            std::memcpy(&x, &q.x, 8);
            std::memcpy(&y, &q.y, 8);
            h = mix(mix(h, x), y);
        }
    }
    return h;
}

// The stages of a frame, in pipeline order.
constexpr const char* kStages[] = {"silhouette search", "cusps + chaining", "features, rest", "pieces (crossings)",
                                   "QI propagation",    "walks",            "ray tests",      "surface lines",
                                   "frame, rest"};
constexpr int kStageCount = int(std::size(kStages));

struct Column {
    int threads = 1;
    std::unique_ptr<inkline::ViewSession> session;
    std::vector<double> stage[kStageCount];
    std::vector<double> frame, cpu, caller_cpu;
    std::vector<std::uint64_t> hashes;
};

void record(Column& c, const inkline::View& v, double wall, double cpu, double caller_cpu) {
    const inkline::DrawingStats& s = v.drawing.stats;
    const inkline::FinderStats& f = v.features.stats;
    const double values[kStageCount] = {
        f.seconds_search,
        f.seconds_chain,
        std::max(0.0, s.seconds_features - s.seconds_surface_lines - f.seconds_search - f.seconds_chain),
        s.seconds_pieces,
        s.seconds_propagation,
        s.seconds_walks,
        s.seconds_ray_tests,
        s.seconds_surface_lines + s.seconds_surface_visibility,
        std::max(0.0, wall - s.seconds_total - s.seconds_surface_visibility),
    };
    for (int k = 0; k < kStageCount; ++k) c.stage[k].push_back(values[k]);
    c.frame.push_back(wall);
    c.cpu.push_back(cpu);
    c.caller_cpu.push_back(caller_cpu);
    c.hashes.push_back(drawing_hash(v.drawing));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: frame_threads MESH[@N] [--frames=F] [--threads=1,2] [--surface] [--markdown=FILE]\n");
        return 2;
    }
    const std::string name = argv[1];
    int frames = 30;
    std::vector<int> counts{1, 2};
    bool surface = false;
    std::string markdown;
    for (int i = 2; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("--frames=", 0) == 0) frames = std::max(1, std::stoi(a.substr(9)));
        else if (a.rfind("--threads=", 0) == 0) {
            counts.clear();
            std::stringstream ss(a.substr(10));
            for (std::string t; std::getline(ss, t, ',');) counts.push_back(std::max(1, std::stoi(t)));
        } else if (a == "--surface") surface = true;
        else if (a.rfind("--markdown=", 0) == 0) markdown = a.substr(11);
        else {
            std::fprintf(stderr, "frame_threads: unknown argument %s\n", a.c_str());
            return 2;
        }
    }
    const inkline::Model* model = bench_model_for(name, "frame_threads");
    if (!model) return 1;
    const inkline::MeshTopology& mesh = model->topology();
    std::vector<Column> columns(counts.size());
    for (std::size_t c = 0; c < counts.size(); ++c) {
        inkline::ViewOptions o;
        o.exact_hidden = false;  // as the bench's rows: visible lines
        o.threads = counts[c];
        o.finder.threads = counts[c];
        if (surface) o.surface.suggestive = true;
        columns[c].threads = counts[c];
        columns[c].session = std::make_unique<inkline::ViewSession>(*model, o);
    }
    if (surface) model->curvature();  // once per model: not a frame's time
    model->rays();
    model->self_intersections();
    for (int i = 0; i < frames; ++i) {
        const double degrees = 360.0 * double(i) / double(frames);
        auto cam = inkline::Camera::perspective(orbit_eye(mesh, degrees), mesh.bounds.center(), {0, 1, 0}, 30.0, 1024, 1024);
        cam.set_near(inkline::default_near(mesh));
        for (Column& c : columns) {
            const double w0 = inkline::wall_seconds(), c0 = inkline::process_cpu_seconds(), t0 = inkline::thread_cpu_seconds();
            const inkline::View& v = c.session->render(cam);
            record(c, v, inkline::wall_seconds() - w0, inkline::process_cpu_seconds() - c0, inkline::thread_cpu_seconds() - t0);
        }
    }
    double load1 = 0.0;
    if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
        if (std::fscanf(f, "%lf", &load1) != 1) load1 = 0.0;
        std::fclose(f);
    }
    const Column& one = columns.front();
    const double frame1 = median(one.frame);
    char head[256];
    std::snprintf(head, sizeof head, "### %s (%zu triangles, orbit, %d frames, 1024x1024, load average %.2f)\n\n| stage |",
                  name.c_str(), mesh.face_count(), frames, load1);
    std::string md = head;
    for (const Column& c : columns) md += " " + std::to_string(c.threads) + " thr ms |";
    md += " share of " + std::to_string(one.threads) + "-thread frame |";
    if (columns.size() > 1) md += " share of " + std::to_string(columns.back().threads) + "-thread frame |";
    md += "\n|---|";
    for (std::size_t c = 0; c < columns.size() + 1 + (columns.size() > 1); ++c) md += "---:|";
    md += "\n";
    char buf[64];
    for (int k = 0; k < kStageCount; ++k) {
        if (!surface && k == 7) continue;
        md += std::string("| ") + kStages[k] + " |";
        for (const Column& c : columns) {
            std::snprintf(buf, sizeof buf, " %.3f |", 1e3 * median(c.stage[k]));
            md += buf;
        }
        std::snprintf(buf, sizeof buf, " %.1f %% |", frame1 > 0 ? 100.0 * median(one.stage[k]) / frame1 : 0.0);
        md += buf;
        if (columns.size() > 1) {
            const double fl = median(columns.back().frame);
            std::snprintf(buf, sizeof buf, " %.1f %% |", fl > 0 ? 100.0 * median(columns.back().stage[k]) / fl : 0.0);
            md += buf;
        }
        md += "\n";
    }
    auto row = [&](const char* label, auto value) {
        md += std::string("| ") + label + " |";
        for (const Column& c : columns) {
            md += ' ';
            md += value(c);
            md += " |";
        }
        md += columns.size() > 1 ? " | |\n" : " |\n";
    };
    row("**frame (median ms)**", [&](const Column& c) {
        std::snprintf(buf, sizeof buf, "**%.3f**", 1e3 * median(c.frame));
        return std::string(buf);
    });
    row("frame / 1-thread frame", [&](const Column& c) {
        std::snprintf(buf, sizeof buf, "%.3f", median(c.frame) / frame1);
        return std::string(buf);
    });
    row("CPU ms (all threads)", [&](const Column& c) {
        std::snprintf(buf, sizeof buf, "%.3f", 1e3 * median(c.cpu));
        return std::string(buf);
    });
    // The calling thread's CPU time: the frame's serial work and its own parts (it waits for the
    // workers asleep), so the frame's length on free cores less any imbalance between the parts;
    // unlike wall time, hardly changed by other processes on the machine.
    row("calling thread's CPU ms", [&](const Column& c) {
        std::snprintf(buf, sizeof buf, "%.3f", 1e3 * median(c.caller_cpu));
        return std::string(buf);
    });
    row("calling thread's CPU / 1-thread CPU", [&](const Column& c) {
        std::snprintf(buf, sizeof buf, "%.3f", median(c.caller_cpu) / median(one.caller_cpu));
        return std::string(buf);
    });
    // Amdahl's law from that ratio r on n threads, r = s + (1 - s) / n: the frame's serial share s
    // (an upper bound: imbalance between the parts counts as serial).
    row("serial share (Amdahl, from that ratio)", [&](const Column& c) {
        const double r = median(c.caller_cpu) / median(one.caller_cpu), n = double(c.threads);
        if (c.threads < 2) return std::string("-");
        std::snprintf(buf, sizeof buf, "%.0f %%", 100.0 * std::clamp((r * n - 1.0) / (n - 1.0), 0.0, 1.0));
        return std::string(buf);
    });
    row("drawings equal to 1 thread", [&](const Column& c) {
        std::size_t same = 0;
        for (std::size_t i = 0; i < c.hashes.size(); ++i) same += c.hashes[i] == one.hashes[i];
        return std::to_string(same) + "/" + std::to_string(c.hashes.size());
    });
    std::fputs(md.c_str(), stdout);
    if (!markdown.empty()) std::ofstream(markdown, std::ios::app) << md << "\n";
    for (const Column& c : columns)
        for (std::size_t i = 0; i < c.hashes.size(); ++i)
            if (c.hashes[i] != one.hashes[i]) return 3;  // a drawing differs from one thread's
    return 0;
}
