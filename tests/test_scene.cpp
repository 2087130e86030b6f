// Scene stage (src/scene/): glTF files written here (meshes, nodes with transforms, instances,
// cameras) loaded through Assimp, drawn with visibility across objects; bad files refused with one
// line naming the file.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "cli_util.hpp"
#include "gltf_writer.hpp"
#include "core/error.hpp"
#include "model/primitives.hpp"
#include "pipeline.hpp"
#include "scene/scene.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using inkline_test::Gltf;

namespace {

fs::path scratch() { return inkline_test::scratch("inkline_test_scene_"); }

void write(const fs::path& p, const std::string& content) {
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f << content;
}

double signed_volume(const inkline::TriangleMesh& m, std::uint32_t object) {
    double v = 0.0;
    for (std::size_t f = 0; f < m.triangles.size(); ++f)
        if (m.face_object[f] == object) {
            const auto& t = m.triangles[f];
            v += glm::dot(m.positions[t[0]], glm::cross(m.positions[t[1]], m.positions[t[2]]));
        }
    return v / 6.0;
}

// The scene of CubeInFrontOfSphereHidesItsPart (below), written into `d` as two.gltf.
std::string ball_and_cube(const fs::path& d) {
    Gltf g;
    const int sphere = g.add_mesh(inkline::make_sphere({0, 0, 0}, 1.0, 48, 24), "sphere");
    const int cube = g.add_mesh(inkline::make_box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}), "cube");
    const int cube_node = g.add_node({{"name", "Cube"}, {"mesh", cube}, {"translation", {0, 0, 2}}});
    const int parent = g.add_node({{"name", "Holder"}, {"children", {cube_node}}, {"translation", {0.9, 0, 0}},
                                   {"scale", {1.2, 1.2, 1.2}}});
    const int sphere_node = g.add_node({{"name", "Ball"}, {"mesh", sphere}});
    return g.save(d, "two", {sphere_node, parent});
}

}  // namespace

// A unit-radius sphere at the origin and a cube of side 1.2 in front of it, placed by a parent
// node (translation 0.9, 0, 0, uniform scale 1.2 of a unit cube) and its child (translation 0, 0, 2
// in the parent's frame, so 2.4 in the world's): seen from (0, 0, 8) down -Z, the cube covers
// the right-hand side of the sphere's outline (x from 0.18 to 1.62 in the world), so the outline
// is hidden there and visible elsewhere; the ray reference agrees.
TEST(Scene, CubeInFrontOfSphereHidesItsPart) {
    const fs::path d = scratch();
    const std::string path = ball_and_cube(d);

    const inkline::Scene s = inkline::load_scene(path);
    ASSERT_EQ(s.mesh.object_names.size(), 2u);
    EXPECT_EQ(s.mesh.object_names[0], "Ball");
    EXPECT_EQ(s.mesh.object_names[1], "Cube");
    // The cube's world box: centre (0.9, 0, 2.4), half side 0.6.
    glm::dvec3 lo(1e9), hi(-1e9);
    for (std::size_t f = 0; f < s.mesh.triangles.size(); ++f)
        if (s.mesh.face_object[f] == 1)
            for (auto v : s.mesh.triangles[f]) lo = glm::min(lo, s.mesh.positions[v]), hi = glm::max(hi, s.mesh.positions[v]);
    EXPECT_NEAR(lo.x, 0.3, 1e-6);
    EXPECT_NEAR(hi.x, 1.5, 1e-6);
    EXPECT_NEAR(lo.z, 1.8, 1e-6);
    EXPECT_NEAR(hi.z, 3.0, 1e-6);
    EXPECT_GT(signed_volume(s.mesh, 0), 0.0);
    EXPECT_NEAR(signed_volume(s.mesh, 1), 1.2 * 1.2 * 1.2, 1e-5);

    const inkline::Model model = inkline::Model::load(path, inkline::LoadOptions{});
    // Object ids follow their faces through the model's reordering: the cube's faces lie in its box.
    const inkline::MeshTopology& topo = model.topology();
    ASSERT_EQ(topo.face_object.size(), topo.face_count());
    ASSERT_EQ(topo.object_names.size(), 2u);
    std::size_t cube_faces = 0;
    for (std::uint32_t f = 0; f < topo.face_count(); ++f) {
        if (topo.face_object[f] != 1) continue;
        ++cube_faces;
        for (auto v : topo.faces[f]) EXPECT_GT(topo.positions[v].z, 1.8 - 1e-6) << "face " << f;
    }
    EXPECT_EQ(cube_faces, 12u);
    const inkline::Camera cam = inkline::Camera::perspective({0, 0, 8}, {0, 0, 0}, {0, 1, 0}, 40, 600, 600);
    inkline::ViewOptions rays;
    rays.visibility = inkline::VisibilityMethod::Rays;
    for (const inkline::ViewOptions& o : {inkline::ViewOptions{}, rays}) {
        const inkline::View v = inkline::render_view(model, cam, o);
        // The sphere's outline: points at the projected radius of its silhouette circle.
        const glm::dvec2 centre = cam.project({0, 0, 0});
        const double r_px = glm::length(cam.project({std::sin(std::acos(1.0 / 8.0)), 0, 1.0 / 8.0}) - centre);
        // The cube's front square (z = 3) and back square (z = 1.8) in pixels: behind the front one
        // from x_px of its left edge on (both squares are right of the centre).
        const double cube_left_px = cam.project({0.3, 0, 3.0}).x;
        const double cube_half_px = cam.project({0.3, 0.6, 3.0}).y - cam.project({0.3, 0, 3.0}).y;
        std::size_t hidden = 0, visible = 0;
        for (const auto& p : v.drawing.pieces)
            for (std::size_t k = 1; k + 1 < p.points.size(); ++k) {
                const glm::dvec2 q = p.points[k];
                if (std::abs(glm::length(q - centre) - r_px) > 1.0) continue;  // not on the sphere's outline
                const bool behind = q.x > cube_left_px + 2 && std::abs(q.y - centre.y) < std::abs(cube_half_px) - 2;
                const bool clear = q.x < cube_left_px - 2 || std::abs(q.y - centre.y) > std::abs(cube_half_px) + 2;
                if (behind) {
                    EXPECT_GE(p.qi, 1) << q.x << "," << q.y;
                    ++hidden;
                }
                if (clear) {
                    EXPECT_EQ(p.qi, 0) << q.x << "," << q.y;
                    ++visible;
                }
            }
        EXPECT_GT(hidden, 5u);
        EXPECT_GT(visible, 20u);
    }
}

// One open box (no top) used by two nodes: as it is at x = +2, mirrored (scale -1 along x) at
// x = -2. Open, so nothing re-orients it after loading: the mirrored copy's normals point out of
// the box only because the winding was flipped with the mirror.
TEST(Scene, MirroredInstanceKeepsOutwardNormals) {
    const fs::path d = scratch();
    inkline::TriangleMesh box = inkline::make_box({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
    std::vector<std::array<std::uint32_t, 3>> open;
    for (const auto& t : box.triangles) {
        const glm::dvec3 n = glm::cross(box.positions[t[1]] - box.positions[t[0]], box.positions[t[2]] - box.positions[t[0]]);
        if (n.y <= 0.5 * glm::length(n)) open.push_back(t);  // all but the top side
    }
    box.triangles = open;
    Gltf g;
    const int mesh = g.add_mesh(box, "tray");
    const int a = g.add_node({{"name", "Plain"}, {"mesh", mesh}, {"translation", {2, 0, 0}}});
    const int b = g.add_node({{"name", "Mirrored"}, {"mesh", mesh}, {"translation", {-2, 0, 0}}, {"scale", {-1, 1, 1}}});
    const inkline::Scene s = inkline::load_scene(g.save(d, "mirror", {a, b}));
    ASSERT_EQ(s.mesh.triangles.size(), 2 * open.size());
    EXPECT_EQ(s.mesh.faces_reoriented, 0u);
    for (std::size_t f = 0; f < s.mesh.triangles.size(); ++f) {
        const auto& t = s.mesh.triangles[f];
        const glm::dvec3 p0 = s.mesh.positions[t[0]], p1 = s.mesh.positions[t[1]], p2 = s.mesh.positions[t[2]];
        const glm::dvec3 centre(s.mesh.face_object[f] == 0 ? 2.0 : -2.0, 0, 0);
        EXPECT_GT(glm::dot(glm::cross(p1 - p0, p2 - p0), (p0 + p1 + p2) / 3.0 - centre), 0.0) << "face " << f;
    }
}

// A perspective camera on a child node: parent translation (1, 2, 3), child rotation 90 degrees
// about +Y (quaternion (0, sin 45, 0, cos 45)): the camera sits at (1, 2, 3) and looks down the
// rotated -Z, which is -X; up stays +Y; yfov 0.6 rad. An orthographic camera follows.
TEST(Scene, FileCameraIsReadInWorldCoordinates) {
    const fs::path d = scratch();
    Gltf g;
    const int mesh = g.add_mesh(inkline::make_box({-1, -1, -1}, {1, 1, 1}), "box");
    g.doc["cameras"] = json::array({{{"name", "Lens"}, {"type", "perspective"},
                                     {"perspective", {{"yfov", 0.6}, {"aspectRatio", 1.5}, {"znear", 0.1}, {"zfar", 100}}}},
                                    {{"name", "Plan"}, {"type", "orthographic"},
                                     {"orthographic", {{"xmag", 3.0}, {"ymag", 2.0}, {"znear", 0.1}, {"zfar", 100}}}}});
    const double h = std::sqrt(0.5);
    const int cam = g.add_node({{"name", "CamNode"}, {"camera", 0}, {"rotation", {0, h, 0, h}}});
    const int rig = g.add_node({{"name", "Rig"}, {"children", {cam}}, {"translation", {1, 2, 3}}});
    const int top = g.add_node({{"name", "Top"}, {"camera", 1}, {"translation", {0, 10, 0}}, {"rotation", {-h, 0, 0, h}}});
    const int box = g.add_node({{"name", "Box"}, {"mesh", mesh}});
    const inkline::Scene s = inkline::load_scene(g.save(d, "cams", {box, rig, top}));
    ASSERT_EQ(s.cameras.size(), 2u);
    const inkline::SceneCamera& c = s.cameras[0];
    EXPECT_FALSE(c.orthographic);
    EXPECT_NEAR(c.eye.x, 1.0, 1e-6);
    EXPECT_NEAR(c.eye.y, 2.0, 1e-6);
    EXPECT_NEAR(c.eye.z, 3.0, 1e-6);
    const glm::dvec3 f = glm::normalize(c.target - c.eye);
    EXPECT_NEAR(f.x, -1.0, 1e-6);
    EXPECT_NEAR(f.y, 0.0, 1e-6);
    EXPECT_NEAR(f.z, 0.0, 1e-6);
    EXPECT_NEAR(glm::normalize(c.up).y, 1.0, 1e-6);
    EXPECT_NEAR(c.fov_deg, 0.6 * 180.0 / M_PI, 1e-4);
    EXPECT_NEAR(c.aspect, 1.5, 1e-6);
    const inkline::Camera ic = c.to_camera(900, 600);
    EXPECT_NEAR(ic.fov_deg(), 0.6 * 180.0 / M_PI, 1e-4);
    // The second: straight down from (0, 10, 0) (rotation -90 degrees about +X), 2 x ymag high.
    const inkline::SceneCamera& o = s.cameras[1];
    EXPECT_TRUE(o.orthographic);
    EXPECT_NEAR(o.eye.y, 10.0, 1e-6);
    EXPECT_NEAR(glm::normalize(o.target - o.eye).y, -1.0, 1e-6);
    EXPECT_NEAR(o.ortho_height, 4.0, 1e-5);
    // Model keeps them.
    const inkline::Model m = inkline::Model::load((d / "cams.gltf").string(), inkline::LoadOptions{});
    ASSERT_EQ(m.cameras().size(), 2u);
    EXPECT_EQ(m.cameras()[0].name, "CamNode");
}

namespace {
struct BadFile {
    std::string path, problem;  // the file, and words its error must hold
};

// Bad scene files written into `d`, each with the words its refusal must hold: the issue's list
// (truncated .glb, wrong buffer lengths, indices out of range, NaN in transforms, a missing .bin,
// cyclic and absurdly deep node graphs, empty scenes) and what else Assimp reads wrongly.
std::vector<BadFile> bad_scene_files(const fs::path& d) {
    auto base = [] {
        Gltf g;
        g.add_mesh(inkline::make_box({-1, -1, -1}, {1, 1, 1}), "box");
        return g;
    };
    std::vector<BadFile> cases;
    {  // truncated .glb: cut inside the binary chunk, and inside the JSON chunk
        Gltf g = base();
        const int n = g.add_node({{"mesh", 0}});
        const std::string glb = g.glb({n});
        write(d / "whole.glb", glb);
        write(d / "cut_bin.glb", glb.substr(0, glb.size() - 100));
        write(d / "cut_json.glb", glb.substr(0, 40));
        const std::string size = std::to_string(glb.size());
        cases.push_back({(d / "cut_bin.glb").string(), "truncated: the binary glTF header says " + size + " bytes, the file has " +
                                                           std::to_string(glb.size() - 100)});
        cases.push_back({(d / "cut_json.glb").string(), "truncated: the binary glTF header says " + size + " bytes, the file has 40"});
        // The header's length right but a chunk's too long: the JSON chunk, then the binary one.
        std::string json_long = glb, bin_long = glb;
        const std::uint32_t json_length = 100000;
        std::memcpy(json_long.data() + 12, &json_length, 4);
        std::uint32_t real_json = 0;
        const std::uint32_t bin_length = 5000;
        std::memcpy(&real_json, glb.data() + 12, 4);
        std::memcpy(bin_long.data() + 20 + real_json, &bin_length, 4);
        write(d / "json_long.glb", json_long);
        write(d / "bin_long.glb", bin_long);
        cases.push_back({(d / "json_long.glb").string(), "the JSON chunk's 100000 bytes run past the file's " + size});
        cases.push_back({(d / "bin_long.glb").string(), "truncated: the binary chunk ends"});
        // A glb loads only with its chunks whole (the uncut file loads).
        const inkline::Scene whole = inkline::load_scene((d / "whole.glb").string());
        EXPECT_EQ(whole.mesh.triangles.size(), 12u);
    }
    {  // a buffer that claims more bytes than its .bin holds
        Gltf g = base();
        const std::string p = g.save(d, "long_buffer", {g.add_node({{"mesh", 0}})});
        json doc = json::parse(std::ifstream(p));
        doc["buffers"][0]["byteLength"] = 100000;
        write(p, doc.dump());
        cases.push_back({p, "byteLength exceeds"});
    }
    {  // a buffer view beyond its buffer
        Gltf g = base();
        const std::string p = g.save(d, "long_view", {g.add_node({{"mesh", 0}})});
        json doc = json::parse(std::ifstream(p));
        doc["bufferViews"][1]["byteLength"] = 4000;
        write(p, doc.dump());
        cases.push_back({p, "out of range"});
    }
    {  // every index out of range
        Gltf g;
        inkline::TriangleMesh t;
        t.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        t.triangles = {{0, 1, 7}, {7, 8, 9}};
        g.add_mesh(t, "bad");
        cases.push_back({g.save(d, "index_range", {g.add_node({{"mesh", 0}})}), "mesh 'bad': all 2 of its triangles refer to vertices beyond its 3 (indices out of range)"});
        // One index out of range of a box's 8 vertices (Assimp drops that triangle with only a log line).
        inkline::TriangleMesh box = inkline::make_box({-1, -1, -1}, {1, 1, 1});
        box.triangles[5][2] = 8;
        Gltf h;
        h.add_mesh(box, "box");
        cases.push_back({h.save(d, "index_one", {h.add_node({{"mesh", 0}})}),
                         "mesh 'box': 1 of its 12 triangles refer to vertices beyond its 8 (indices out of range)"});
    }
    {  // accessors of the wrong kind for their role: float indices, 2-component positions
        Gltf g = base();
        g.doc["accessors"][1]["componentType"] = 5126;
        cases.push_back({g.save(d, "float_indices", {g.add_node({{"mesh", 0}})}), "mesh 0: its indices are of componentType 5126"});
        Gltf h = base();
        h.doc["accessors"][0]["type"] = "VEC2";
        cases.push_back({h.save(d, "vec2_positions", {h.add_node({{"mesh", 0}})}),
                         "POSITION accessor is of type \"VEC2\" (glTF requires VEC3)"});
    }
    {  // not JSON (an input of this kind timed out under the fuzzer: fuzz/regressions/gltf-invalid-json)
        Gltf g = base();
        const std::string p = g.save(d, "not_json", {g.add_node({{"mesh", 0}})});
        std::ifstream in(p);
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        write(p, text.substr(0, 1) + "vt " + text.substr(1));
        cases.push_back({p, "not valid JSON: parse error at line 1, column 2"});
    }
    {  // NaN in a transform: the world matrix overflows (1e200 x 1e200)
        Gltf g = base();
        const int c = g.add_node({{"mesh", 0}, {"scale", {1e200, 1e200, 1e200}}});
        const int p = g.add_node({{"children", {c}}, {"scale", {1e200, 1e200, 1e200}}});
        cases.push_back({g.save(d, "inf_transform", {p}), "NaN or infinite"});
    }
    {  // the .bin is missing
        Gltf g = base();
        const std::string p = g.save(d, "no_bin", {g.add_node({{"mesh", 0}})});
        fs::remove(d / "no_bin.bin");
        cases.push_back({p, "no_bin.bin"});
    }
    {  // a cycle: two nodes each the other's child
        Gltf g = base();
        g.add_node({{"mesh", 0}, {"children", {1}}});
        g.add_node({{"children", {0}}});
        cases.push_back({g.save(d, "cycle", {0}), "cyclic node graph"});
    }
    {  // a chain of nodes deeper than kMaxNodeDepth, and an absurdly deep one
        for (int depth : {inkline::kMaxNodeDepth + 10, 100000}) {
            Gltf g = base();
            g.add_node({{"mesh", 0}});
            for (int i = 1; i < depth; ++i) g.add_node({{"children", {i - 1}}});
            cases.push_back({g.save(d, "deep" + std::to_string(depth), {depth - 1}), "deeper than"});
        }
    }
    {  // an empty scene, and a scene of nodes without meshes
        Gltf g;
        cases.push_back({g.save(d, "empty", {}), "incomplete scene"});
        Gltf h;
        cases.push_back({h.save(d, "no_mesh", {h.add_node({{"name", "lonely"}})}), "incomplete scene"});
        write(d / "asset_only.gltf", R"({"asset": {"version": "2.0"}})");
        cases.push_back({(d / "asset_only.gltf").string(), "No scene"});
    }
    write(d / "garbage.glb", "glTF\x02\x00\x00\x00garbage");
    cases.push_back({(d / "garbage.glb").string(), "truncated: the file ends inside the 12-byte binary glTF header"});
    write(d / "not_binary.glb", "solid cube\nendsolid cube\n");  // (Assimp's other readers read past a buffer on such bytes)
    cases.push_back({(d / "not_binary.glb").string(), "not a binary glTF file (it does not start with 'glTF')"});
    write(d / "garbage.fbx", "not an fbx at all\n");
    cases.push_back({(d / "garbage.fbx").string(), "unexpected token"});
    return cases;
}
}  // namespace

// Bad scene files: each refused with one line that starts with the file's path and names the
// problem; no crash (the 100000-level node chain overflowed the stack inside Assimp's reader
// before load_scene checked glTF node graphs itself).
TEST(Scene, BadFilesAreRefusedWithOneLine) {
    const std::vector<BadFile> cases = bad_scene_files(scratch());
    ASSERT_EQ(cases.size(), 22u);
    for (const BadFile& c : cases) {
        try {
            const inkline::Scene s = inkline::load_scene(c.path);
            ADD_FAILURE() << c.path << ": accepted (" << s.mesh.triangles.size() << " triangles)";
        } catch (const inkline::Error& e) {
            const std::string m = e.what();
            EXPECT_EQ(m.rfind(c.path + ": ", 0), 0u) << m;
            EXPECT_NE(m.find(c.problem), std::string::npos) << c.path << ": expected '" << c.problem << "' in " << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
            EXPECT_GT(m.size(), c.path.size() + 4) << m;
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The command: tolerant by default with one warning line per kind of repair, --strict refuses;
// a scene's first perspective camera when no camera flag is given, --camera=NAME, --camera=frame.

namespace {
// The command's exit code and output (tests/cli_util.hpp).
inkline_test::Result run(const std::string& args, const fs::path& d) { return inkline_test::run_inkline("", args, d); }
std::size_t count_lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }
}  // namespace

TEST(SceneCli, TolerantByDefaultStrictRefuses) {
    const fs::path d = scratch();
    // A tetrahedron with a fin on edge 0-1 (non-manifold) and a face that repeats a corner.
    write(d / "fin.off", "OFF\n5 6 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0.5 -1 0.5\n"
                         "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 0 4 1\n3 1 1 2\n");
    const inkline_test::Result ok = run("render " + (d / "fin.off").string() + " -o " + (d / "fin.svg").string(), d);
    EXPECT_EQ(ok.code, 0) << ok.err;
    EXPECT_TRUE(fs::exists(d / "fin.svg"));
    EXPECT_EQ(count_lines(ok.err), 2u) << ok.err;
    EXPECT_NE(ok.err.find("inkline: warning: " + (d / "fin.off").string() + ": dropped 1 degenerate"), std::string::npos)
        << ok.err;
    EXPECT_NE(ok.err.find("cut the surface at 1 non-manifold edges"), std::string::npos) << ok.err;
    const inkline_test::Result strict = run("render " + (d / "fin.off").string() + " --strict -o " + (d / "strict.svg").string(), d);
    EXPECT_EQ(strict.code, 1);
    EXPECT_EQ(count_lines(strict.err), 1u) << strict.err;
    EXPECT_NE(strict.err.find("repeats vertex index 1"), std::string::npos) << strict.err;
    EXPECT_FALSE(fs::exists(d / "strict.svg"));
}

// Assimp, Cairo and the window's libraries are loaded only by what needs them (docs/loading.md,
// "Start-up"): the dynamic loader's own list of the files it opens (LD_DEBUG=files) for an SVG
// render names none of them, a PNG render names Cairo, a scene file Assimp's module; without the
// module, a scene file is refused in one line naming it while OFF still renders.
TEST(SceneCli, LibrariesAreLoadedOnlyWhenNeeded) {
    const fs::path d = scratch();
    write(d / "tet.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    Gltf g;
    const std::string glb = g.save(d, "box", {g.add_node({{"name", "Box"}, {"mesh", g.add_mesh(inkline::make_box({-1, -1, -1}, {1, 1, 1}), "box")}})});
    const auto loaded = [&](const std::string& args) {
        const inkline_test::Result r = inkline_test::run_inkline("LD_DEBUG=files ", args, d);
        EXPECT_EQ(r.code, 0) << args << ": " << r.err;
        std::string files;  // the libraries named by "file=NAME [0];  ..." lines
        for (std::size_t at = 0; (at = r.err.find("file=", at)) != std::string::npos; at += 5)
            files += r.err.substr(at + 5, r.err.find_first_of(" \n", at) - at - 5) + " ";
        return files;
    };
    const std::string svg = loaded("render " + (d / "tet.off").string() + " -o " + (d / "tet.svg").string());
    EXPECT_NE(svg.find("libstdc++"), std::string::npos) << svg;  // the loader's lines were read
    for (const char* lib : {"libcairo", "libassimp", "libinkline_assimp", "libglfw", "libGL", "libX11"})
        EXPECT_EQ(svg.find(lib), std::string::npos) << lib << " loaded for an SVG render: " << svg;
    const std::string png = loaded("render " + (d / "tet.off").string() + " --size=64x64 -o " + (d / "tet.png").string());
    EXPECT_NE(png.find("libcairo.so.2"), std::string::npos) << png;
    EXPECT_EQ(png.find("libassimp"), std::string::npos) << png;
    const std::string scene = loaded("render " + glb + " -o " + (d / "box.svg").string());
    EXPECT_NE(scene.find("libinkline_assimp.so"), std::string::npos) << scene;
    EXPECT_EQ(scene.find("libcairo"), std::string::npos) << scene;

    fs::create_directories(d / "no_modules");
    const std::string env = "INKLINE_MODULE_DIR=" + (d / "no_modules").string() + " ";
    const inkline_test::Result refused = inkline_test::run_inkline(env, "render " + glb + " -o " + (d / "x.svg").string(), d);
    EXPECT_EQ(refused.code, 1);
    EXPECT_EQ(count_lines(refused.err), 1u) << refused.err;
    EXPECT_EQ(refused.err.rfind("inkline: " + (d / "no_modules" / "libinkline_assimp.so").string() + ": cannot be loaded", 0), 0u)
        << refused.err;
    EXPECT_FALSE(fs::exists(d / "x.svg"));
    EXPECT_EQ(inkline_test::run_inkline(env, "render " + (d / "tet.off").string() + " -o " + (d / "y.svg").string(), d).code, 0);
}

TEST(SceneCli, FileCameraByDefaultByNameOrFramed) {
    const fs::path d = scratch();
    Gltf g;
    const int mesh = g.add_mesh(inkline::make_box({-1, -1, -1}, {1, 1, 1}), "box");
    g.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}},
                                    {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}});
    const int a = g.add_node({{"name", "Front"}, {"camera", 0}, {"translation", {0, 0, 10}}});
    const int b = g.add_node({{"name", "Side"}, {"camera", 1}, {"translation", {10, 0, 0}}, {"rotation", {0, std::sqrt(0.5), 0, std::sqrt(0.5)}}});
    const std::string path = g.save(d, "cams", {g.add_node({{"name", "Box"}, {"mesh", mesh}}), a, b});
    const std::string out = " -o " + (d / "x.json").string();
    const inkline_test::Result first = run("render " + path + out, d);
    ASSERT_EQ(first.code, 0) << first.err;
    EXPECT_NE(first.out.find("camera: --eye=0,0,10 --target=0,0,9 --up=0,1,0 --fov=28.64788975654116"), std::string::npos)
        << first.out;
    const inkline_test::Result side = run("render " + path + out + " --camera=Side", d);
    ASSERT_EQ(side.code, 0) << side.err;
    EXPECT_NE(side.out.find("--eye=10,0,0 --target=9.00000"), std::string::npos) << side.out;
    EXPECT_NE(side.out.find("--fov=45.83662"), std::string::npos) << side.out;
    // A camera named and a camera flag: the flag overrides, the file's camera gives the rest.
    const inkline_test::Result fov = run("render " + path + out + " --camera=Front --fov=20", d);
    EXPECT_NE(fov.out.find("camera: --eye=0,0,10 --target=0,0,9 --up=0,1,0 --fov=20 "), std::string::npos) << fov.out;
    // Any camera flag without --camera: framed, as for a mesh file.
    const inkline_test::Result flag = run("render " + path + out + " --fov=20", d);
    EXPECT_NE(flag.out.find("--target=0,0,0 --up=0,1,0 --fov=20 "), std::string::npos) << flag.out;
    const inkline_test::Result framed = run("render " + path + out + " --camera=frame", d);
    EXPECT_NE(framed.out.find("--fov=30 "), std::string::npos) << framed.out;
    EXPECT_EQ(framed.out.find("--eye=0,0,10"), std::string::npos) << framed.out;
    const inkline_test::Result missing = run("render " + path + out + " --camera=Top", d);
    EXPECT_EQ(missing.code, 2);
    EXPECT_NE(missing.err.find("--camera: the model's file has no camera 'Top' (its cameras: 'Front', 'Side'"),
              std::string::npos)
        << missing.err;
}

// Objects in the outputs (issue 40 part 2): the ball and the cube of CubeInFrontOfSphereHidesItsPart,
// seen from (0, 0, 8). Every piece knows its object: the pieces on the ball's outline circle
// are the ball's, the creases (the sphere has none: its faces turn by 7.5 degrees) the cube's.
// The command's SVG has a group per object inside each layer, labelled with the node's name, and
// its JSON names the object of every polyline.
TEST(SceneOutput, PiecesKnowTheirObjectsAndTheOutputsTellThemApart) {
    const fs::path d = scratch();
    const std::string path = ball_and_cube(d);

    const inkline::Model model = inkline::Model::load(path, inkline::LoadOptions{});
    const inkline::Camera cam = inkline::Camera::perspective({0, 0, 8}, {0, 0, 0}, {0, 1, 0}, 40, 600, 600);
    inkline::ViewOptions rays;
    rays.visibility = inkline::VisibilityMethod::Rays;
    rays.exact_hidden = true;
    for (const inkline::ViewOptions& o : {inkline::ViewOptions{}, rays}) {
        const inkline::View v = inkline::render_view(model, cam, o);
        EXPECT_EQ(v.drawing.object_names, (std::vector<std::string>{"Ball", "Cube"}));
        const glm::dvec2 centre = cam.project({0, 0, 0});
        const double r_px = glm::length(cam.project({std::sin(std::acos(1.0 / 8.0)), 0, 1.0 / 8.0}) - centre);
        std::size_t ball = 0, cube_pieces = 0;
        for (const auto& p : v.drawing.pieces) {
            const bool on_circle = std::all_of(p.points.begin(), p.points.end(), [&](const glm::dvec2& q) {
                return std::abs(glm::length(q - centre) - r_px) < 1.0;
            });
            if (p.kind == inkline::LineKind::Crease) {
                EXPECT_EQ(p.object, 1u);
                ++cube_pieces;
            } else if (on_circle && p.points.size() > 2) {
                EXPECT_EQ(p.object, 0u);
                ++ball;
            }
        }
        EXPECT_EQ(ball, 2u);  // the outline cut where it passes behind the cube: one arc in view, one behind
        EXPECT_GT(cube_pieces, 8u);  // the cube's 12 edges, some cut by the ball's outline
    }

    const inkline_test::Result svg = run("render " + path + " --eye=0,0,8 --target=0,0,0 --fov=40 --size=600x600 -o " +
                                         (d / "two.svg").string(), d);
    ASSERT_EQ(svg.code, 0) << svg.err;
    const std::string text = inkline_test::slurp(d / "two.svg");
    const std::size_t layer = text.find("<g id=\"silhouette-visible\" inkscape:groupmode=\"layer\"");
    const std::size_t ball_group = text.find("<g id=\"silhouette-visible-object0\" inkscape:label=\"Ball\">");
    const std::size_t cube_group = text.find("<g id=\"silhouette-visible-object1\" inkscape:label=\"Cube\">");
    ASSERT_NE(layer, std::string::npos) << text;
    ASSERT_NE(ball_group, std::string::npos) << text;
    ASSERT_NE(cube_group, std::string::npos) << text;
    EXPECT_LT(layer, ball_group);
    EXPECT_LT(ball_group, cube_group);
    // Every path of a group carries its object's name; the crease layer holds the cube only.
    const std::size_t ball_end = text.find("</g>", ball_group);
    EXPECT_EQ(text.substr(ball_group, ball_end - ball_group).find("data-object=\"Cube\""), std::string::npos);
    EXPECT_NE(text.substr(ball_group, ball_end - ball_group).find("data-object=\"Ball\""), std::string::npos);
    EXPECT_NE(text.find("<g id=\"crease-visible-object1\" inkscape:label=\"Cube\">"), std::string::npos);
    EXPECT_EQ(text.find("<g id=\"crease-visible-object0\""), std::string::npos);
    EXPECT_EQ(std::system(("rsvg-convert -o " + (d / "two.png").string() + " " + (d / "two.svg").string()).c_str()), 0);

    // The same groups in a styled drawing (sketchy: marks of one look kept apart per object).
    const inkline_test::Result styled = run("render " + path + " --eye=0,0,8 --target=0,0,0 --fov=40 --size=600x600 "
                                            "--style=sketchy -o " + (d / "styled.svg").string(), d);
    ASSERT_EQ(styled.code, 0) << styled.err;
    const std::string st = inkline_test::slurp(d / "styled.svg");
    const std::size_t s_layer = st.find("<g id=\"silhouette-visible\" inkscape:groupmode=\"layer\"");
    const std::size_t s_ball = st.find("<g id=\"silhouette-visible-object0\" inkscape:label=\"Ball\" data-object=\"Ball\">");
    const std::size_t s_cube = st.find("<g id=\"silhouette-visible-object1\" inkscape:label=\"Cube\" data-object=\"Cube\">");
    ASSERT_NE(s_layer, std::string::npos) << st;
    ASSERT_NE(s_ball, std::string::npos) << st;
    ASSERT_NE(s_cube, std::string::npos) << st;
    EXPECT_LT(s_layer, s_ball);
    EXPECT_LT(s_ball, s_cube);
    EXPECT_NE(st.find("<g id=\"crease-visible-object1\" inkscape:label=\"Cube\""), std::string::npos);
    EXPECT_EQ(st.find("<g id=\"crease-visible-object0\""), std::string::npos);
    EXPECT_EQ(std::system(("rsvg-convert -o " + (d / "styled.png").string() + " " + (d / "styled.svg").string()).c_str()), 0);

    const inkline_test::Result js = run("render " + path + " --eye=0,0,8 --target=0,0,0 --fov=40 --size=600x600 -o " +
                                        (d / "two.json").string(), d);
    ASSERT_EQ(js.code, 0) << js.err;
    const json j = json::parse(inkline_test::slurp(d / "two.json"));
    std::size_t named[2] = {0, 0};
    for (const auto& p : j["polylines"]) {
        ASSERT_TRUE(p.contains("object")) << p.dump();
        const std::string o = p["object"];
        ASSERT_TRUE(o == "Ball" || o == "Cube") << o;
        ++named[o == "Cube"];
        if (p["kind"] == "crease") {
            EXPECT_EQ(o, "Cube");
        }
    }
    EXPECT_GT(named[0], 0u);
    EXPECT_GT(named[1], 0u);
}

// The same bad files through the command: exit 1, one line on stderr naming the file and the
// problem, and no output file.
TEST(SceneCli, BadFilesExitOneWithOneLineAndNoOutput) {
    const fs::path d = scratch();
    const std::vector<BadFile> cases = bad_scene_files(d);
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const fs::path out = d / ("out" + std::to_string(i) + ".svg");
        const inkline_test::Result r = run("render " + cases[i].path + " -o " + out.string(), d);
        EXPECT_EQ(r.code, 1) << cases[i].path << ": " << r.err;
        EXPECT_EQ(count_lines(r.err), 1u) << r.err;
        EXPECT_EQ(r.err.rfind("inkline: " + cases[i].path + ": ", 0), 0u) << r.err;
        EXPECT_NE(r.err.find(cases[i].problem), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out)) << out;
    }
}

// A camera that cannot make a view (glTF's yfov 0; Assimp passes it on): left out with a warning
// by default, so the drawing frames the model; refused by name with --strict.
TEST(SceneCli, UnusableFileCameraIsLeftOutOrRefused) {
    const fs::path d = scratch();
    Gltf g;
    const int mesh = g.add_mesh(inkline::make_box({-1, -1, -1}, {1, 1, 1}), "box");
    g.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.0}, {"znear", 0.1}}}}});
    const int cam = g.add_node({{"name", "Cam"}, {"camera", 0}, {"translation", {0, 0, 10}}});
    const std::string path = g.save(d, "bad_cam", {g.add_node({{"name", "Box"}, {"mesh", mesh}}), cam});
    const inkline::Scene s = inkline::load_scene(path);
    EXPECT_TRUE(s.cameras.empty());
    EXPECT_EQ(s.mesh.repairs.cameras_dropped, 1u);
    const inkline_test::Result ok = run("render " + path + " -o " + (d / "ok.json").string(), d);
    EXPECT_EQ(ok.code, 0) << ok.err;
    EXPECT_EQ(ok.err, "inkline: warning: " + path +
                          ": left out 1 of the file's cameras that cannot make a view (the first, camera 'Cam': field "
                          "of view must be in (0, 180) degrees)\n");
    EXPECT_NE(ok.out.find("--fov=30 "), std::string::npos) << ok.out;  // framed
    const inkline_test::Result strict = run("render " + path + " --strict -o " + (d / "strict.json").string(), d);
    EXPECT_EQ(strict.code, 1);
    EXPECT_EQ(strict.err, "inkline: " + path + ": camera 'Cam': field of view must be in (0, 180) degrees\n");
    EXPECT_FALSE(fs::exists(d / "strict.json"));
}

// LoadOptions::progress: through Assimp's reading (a .glb, read through inkline's IO system) and
// inkline's own parser (an OFF of the same sphere), the fractions never go back, the file's bytes
// are all reported read, and the last call (Model::load's) is the only one marked done, at 1.
TEST(Scene, ProgressReportsTheWholeLoadInOrder) {
    const fs::path d = scratch();
    const inkline::TriangleMesh sphere = inkline::make_sphere({0, 0, 0}, 1.0, 64, 32);
    Gltf g;
    g.add_mesh(sphere, "sphere");
    write(d / "sphere.glb", g.glb({g.add_node({{"mesh", 0}})}));
    std::string off = "OFF\n" + std::to_string(sphere.positions.size()) + " " + std::to_string(sphere.triangles.size()) + " 0\n";
    for (const auto& p : sphere.positions) off += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    for (const auto& t : sphere.triangles) off += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
    write(d / "sphere.off", off);
    for (const char* name : {"sphere.glb", "sphere.off"}) {
        std::vector<inkline::LoadProgress> calls;
        inkline::LoadOptions options;
        options.progress = [&](const inkline::LoadProgress& p) { calls.push_back(p); };
        const inkline::Model m = inkline::Model::load((d / name).string(), options);
        EXPECT_EQ(m.topology().face_count(), sphere.triangles.size()) << name;
        ASSERT_GE(calls.size(), 4u) << name;  // parsed, repair steps, ordered, done
        const std::uint64_t size = fs::file_size(d / name);
        std::uint64_t most = 0;
        for (std::size_t i = 0; i < calls.size(); ++i) {
            if (i > 0) {
                EXPECT_GE(calls[i].fraction, calls[i - 1].fraction) << name << " call " << i;
            }
            EXPECT_EQ(calls[i].done, i + 1 == calls.size()) << name << " call " << i;
            most = std::max(most, calls[i].bytes_read);
        }
        EXPECT_EQ(most, size) << name;
        EXPECT_EQ(calls.back().fraction, 1.0) << name;
    }
}
