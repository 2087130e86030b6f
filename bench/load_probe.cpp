// Loading alone, for whole-process timings and profilers (bench/run_loading.sh).
//   load_probe write NAME[@N] DIR   writes DIR/NAME[@N].off, .glb, .ply and .stl: the sample mesh
//                                    NAME (INKLINE_DATA_DIR/meshes/NAME.off), N rounds of Loop
//                                    subdivision, positions rounded to float in every file so they
//                                    hold the same geometry (the .glb: float positions, uint32
//                                    indices, one node; .ply and .stl binary little-endian)
//   load_probe load FILE [N [T]]     loads FILE N times (default 1) as `inkline render` does
//                                    (Model::load, tolerant, T threads, default 1) and prints the
//                                    fastest of the N in wall seconds: parse and repair alone, the
//                                    whole Model::load, and Model::load with the self-intersections
//                                    (what a render waits for before its first view); and the
//                                    first load's two (a render's case: later loads reuse memory)
//   load_probe stages FILE [N [T]]   the least of N of each stage of a render's loading, in CPU
//                                    seconds of the thread (steadier than wall time on a shared
//                                    machine): parse and repair (load_mesh), Hilbert order, topology,
//                                    and the lazy parts a render may build (self-intersections,
//                                    ray-test index); with T threads (default 1) the stages that
//                                    use them do (the Hilbert orders beside the repairs, as
//                                    Model::load), and the figures are wall seconds
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.hpp"
#include "core/error.hpp"
#include "model/mesh_io.hpp"
#include "model/reorder.hpp"
#include "model/self_intersections.hpp"
#include "visibility/ray_caster.hpp"
#include "model/subdivide.hpp"
#include "pipeline.hpp"
#include "scene/scene.hpp"

namespace {

void append_u32(std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }

void write_off(const inkline::TriangleMesh& m, const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw inkline::Error(path, "cannot write");
    std::fprintf(f, "OFF\n%zu %zu 0\n", m.positions.size(), m.triangles.size());
    for (const auto& p : m.positions) std::fprintf(f, "%.9g %.9g %.9g\n", p.x, p.y, p.z);
    for (const auto& t : m.triangles) std::fprintf(f, "3 %u %u %u\n", t[0], t[1], t[2]);
    std::fclose(f);
}

void write_glb(const inkline::TriangleMesh& m, const std::string& path) {
    std::string bin;
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (const auto& p : m.positions)
        for (int k = 0; k < 3; ++k) {
            const float v = float(p[k]);
            bin.append(reinterpret_cast<const char*>(&v), 4);
            lo[k] = std::min(lo[k], v), hi[k] = std::max(hi[k], v);
        }
    const std::size_t index_at = bin.size();
    for (const auto& t : m.triangles)
        for (auto i : t) append_u32(bin, i);
    char json[2048];
    std::snprintf(json, sizeof json,
                  "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
                  "\"nodes\":[{\"name\":\"mesh\",\"mesh\":0}],"
                  "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
                  "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\","
                  "\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]},"
                  "{\"bufferView\":1,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}],"
                  "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu,\"target\":34962},"
                  "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu,\"target\":34963}],"
                  "\"buffers\":[{\"byteLength\":%zu}]}",
                  m.positions.size(), lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], 3 * m.triangles.size(), index_at,
                  index_at, bin.size() - index_at, bin.size());
    std::string js = json;
    while (js.size() % 4) js.push_back(' ');
    std::string out = "glTF";
    append_u32(out, 2);
    append_u32(out, std::uint32_t(12 + 8 + js.size() + 8 + bin.size()));
    append_u32(out, std::uint32_t(js.size()));
    out += "JSON" + js;
    append_u32(out, std::uint32_t(bin.size()));
    out.append("BIN\0", 4);
    out += bin;
    std::ofstream(path, std::ios::binary) << out;
}

void write_ply(const inkline::TriangleMesh& m, const std::string& path) {
    std::string out = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(m.positions.size()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                      std::to_string(m.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& p : m.positions)
        for (int k = 0; k < 3; ++k) {
            const float v = float(p[k]);
            out.append(reinterpret_cast<const char*>(&v), 4);
        }
    for (const auto& t : m.triangles) {
        out.push_back(char(3));
        for (auto i : t) append_u32(out, i);
    }
    std::ofstream(path, std::ios::binary) << out;
}

void write_stl(const inkline::TriangleMesh& m, const std::string& path) {
    std::string out(80, ' ');
    append_u32(out, std::uint32_t(m.triangles.size()));
    for (const auto& t : m.triangles) {
        out.append(12, '\0');  // the normal: readers recompute it
        for (auto i : t)
            for (int k = 0; k < 3; ++k) {
                const float v = float(m.positions[i][k]);
                out.append(reinterpret_cast<const char*>(&v), 4);
            }
        out.append(2, '\0');
    }
    std::ofstream(path, std::ios::binary) << out;
}

int write(const std::string& name, const std::string& dir) {
    const auto at = name.find('@');
    const int levels = at == std::string::npos ? 0 : std::stoi(name.substr(at + 1));
    inkline::TriangleMesh m =
        inkline::subdivide_loop(inkline::load_mesh(std::string(INKLINE_DATA_DIR) + "/meshes/" + name.substr(0, at) + ".off"),
                                levels);
    for (auto& p : m.positions) p = glm::dvec3(glm::vec3(p));  // the same float geometry in both files
    write_off(m, dir + "/" + name + ".off");
    write_glb(m, dir + "/" + name + ".glb");
    write_ply(m, dir + "/" + name + ".ply");
    write_stl(m, dir + "/" + name + ".stl");
    std::printf("%s: %zu vertices, %zu triangles\n", name.c_str(), m.positions.size(), m.triangles.size());
    return 0;
}

int load(const std::string& path, int repeat, int threads) {
    // Model::load first, as in a render (one load a process): the parse alone after it frees
    // arrays that a later load in this process reuses (src/app/huge_pages.cpp keeps freed large
    // blocks), so the first load is the render's case and later ones may be faster.
    double parse = 1e300, whole = 1e300, ready = 1e300, first_whole = 0.0, first_ready = 0.0;
    std::size_t triangles = 0;
    for (int r = 0; r < repeat; ++r) {
        auto t0 = inkline::StageClock::now();
        {
            const inkline::Model model = inkline::Model::load(path, inkline::LoadOptions{.threads = threads});
            const double w = inkline::seconds_since(t0);
            model.self_intersections(threads);  // (with threads > 1 started by Model::load already)
            const double d = inkline::seconds_since(t0);
            if (r == 0) first_whole = w, first_ready = d;
            whole = std::min(whole, w);
            ready = std::min(ready, d);
        }
        t0 = inkline::StageClock::now();
        const inkline::TriangleMesh m = inkline::is_scene_file(path) ? inkline::load_scene(path).mesh : inkline::load_mesh(path);
        parse = std::min(parse, inkline::seconds_since(t0));
        triangles = m.triangles.size();
    }
    std::printf("%s: %zu triangles, parse+repair %.4f s, Model::load %.4f s, load and self-intersections %.4f s "
                "(%d threads; the first load: %.4f s, %.4f s)\n",
                path.c_str(), triangles, parse, whole, ready, threads, first_whole, first_ready);
    return 0;
}


int stages(const std::string& path, int repeat, int threads) {
    double t[5] = {1e300, 1e300, 1e300, 1e300, 1e300};
    std::size_t triangles = 0;
    const auto clock = threads > 1 ? inkline::wall_seconds : inkline::thread_cpu_seconds;
    for (int r = 0; r < repeat; ++r) {
        double t0 = clock();
        const auto lap = [&](double& least) {
            const double now = clock();
            least = std::min(least, now - t0);
            t0 = now;
        };
        inkline::HilbertOrderAhead ahead;  // (as Model::load: with threads, the orders beside the repairs)
        inkline::TriangleMesh m = inkline::load_mesh(path, {}, threads > 1 ? &ahead : nullptr);
        lap(t[0]);
        triangles = m.triangles.size();
        const std::optional<inkline::HilbertOrders> known = ahead.take();
        inkline::TriangleMesh ordered =
            known ? inkline::hilbert_ordered(std::move(m), *known, threads) : inkline::hilbert_ordered(std::move(m), threads);
        lap(t[1]);
        const inkline::MeshTopology topo = inkline::build_topology(std::move(ordered));
        lap(t[2]);
        const inkline::SelfIntersections si = inkline::self_intersections(topo, threads);
        lap(t[3]);
        const inkline::RayCaster rays(topo);
        lap(t[4]);
    }
    std::printf("%s: %zu triangles, parse+repair %.4f s, hilbert %.4f s, topology %.4f s, "
                "self-intersections %.4f s, ray index %.4f s\n",
                path.c_str(), triangles, t[0], t[1], t[2], t[3], t[4]);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        if (argc == 4 && std::strcmp(argv[1], "write") == 0) return write(argv[2], argv[3]);
        if (argc >= 3 && argc <= 5 && std::strcmp(argv[1], "stages") == 0)
            return stages(argv[2], argc >= 4 ? std::atoi(argv[3]) : 1, argc == 5 ? std::atoi(argv[4]) : 1);
        if (argc >= 3 && argc <= 5 && std::strcmp(argv[1], "load") == 0)
            return load(argv[2], argc >= 4 ? std::atoi(argv[3]) : 1, argc == 5 ? std::atoi(argv[4]) : 1);
    } catch (const inkline::Error& e) {
        std::fprintf(stderr, "load_probe: %s\n", e.what());
        return 1;
    }
    std::fprintf(stderr, "usage: load_probe write NAME[@N] DIR | load FILE [N [THREADS]] | stages FILE [N [THREADS]]\n");
    return 2;
}
