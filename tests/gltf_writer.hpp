// A glTF 2.0 writer for tests: meshes (float positions, uint32 indices), nodes, and the scene
// saved as .gltf with its .bin, or as one .glb (test_scene, test_intersections).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include "model/mesh_io.hpp"

namespace inkline_test {

inline void write_file(const std::filesystem::path& p, const std::string& content) {
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f << content;
}

// A glTF 2.0 document with its binary buffer: float positions and uint32 indices per mesh.
struct Gltf {
    nlohmann::json doc = {{"asset", {{"version", "2.0"}}}, {"scene", 0},        {"scenes", nlohmann::json::array()},
                          {"nodes", nlohmann::json::array()},        {"meshes", nlohmann::json::array()},
                          {"accessors", nlohmann::json::array()},    {"bufferViews", nlohmann::json::array()},
                          {"buffers", nlohmann::json::array()}};
    std::string bin;

    int view(const void* data, std::size_t bytes, int target) {
        while (bin.size() % 4) bin.push_back('\0');
        const std::size_t at = bin.size();
        bin.append(static_cast<const char*>(data), bytes);
        doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", at}, {"byteLength", bytes}, {"target", target}});
        return int(doc["bufferViews"].size()) - 1;
    }
    int add_mesh(const inkline::TriangleMesh& m, const std::string& name) {
        std::vector<float> p;
        glm::dvec3 lo(1e300), hi(-1e300);
        for (const auto& v : m.positions) {
            p.insert(p.end(), {float(v.x), float(v.y), float(v.z)});
            lo = glm::min(lo, v), hi = glm::max(hi, v);
        }
        std::vector<std::uint32_t> idx;
        for (const auto& t : m.triangles) idx.insert(idx.end(), t.begin(), t.end());
        const int pv = view(p.data(), p.size() * 4, 34962), iv = view(idx.data(), idx.size() * 4, 34963);
        auto& acc = doc["accessors"];
        acc.push_back({{"bufferView", pv}, {"componentType", 5126}, {"count", m.positions.size()}, {"type", "VEC3"},
                       {"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}});
        acc.push_back({{"bufferView", iv}, {"componentType", 5125}, {"count", idx.size()}, {"type", "SCALAR"}});
        const int n = int(acc.size());
        doc["meshes"].push_back({{"name", name}, {"primitives", {{{"attributes", {{"POSITION", n - 2}}}, {"indices", n - 1}}}}});
        return int(doc["meshes"].size()) - 1;
    }
    int add_node(nlohmann::json node) {
        doc["nodes"].push_back(std::move(node));
        return int(doc["nodes"].size()) - 1;
    }
    // Writes NAME.gltf and NAME.bin into dir; the scene's roots are `roots`.
    std::string save(const std::filesystem::path& dir, const std::string& name, const std::vector<int>& roots) {
        doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
        doc["buffers"] = nlohmann::json::array({{{"uri", name + ".bin"}, {"byteLength", bin.size()}}});
        write_file(dir / (name + ".bin"), bin);
        write_file(dir / (name + ".gltf"), doc.dump(1));
        return (dir / (name + ".gltf")).string();
    }
    // The same as one binary .glb file (JSON chunk, then BIN chunk).
    std::string glb(const std::vector<int>& roots) {
        doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
        doc["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
        std::string js = doc.dump();
        while (js.size() % 4) js.push_back(' ');
        std::string b = bin;
        while (b.size() % 4) b.push_back('\0');
        auto u32 = [](std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
        std::string out = "glTF";
        u32(out, 2);
        u32(out, std::uint32_t(12 + 8 + js.size() + 8 + b.size()));
        u32(out, std::uint32_t(js.size()));
        out += "JSON" + js;
        u32(out, std::uint32_t(b.size()));
        out.append("BIN\0", 4);
        out += b;
        return out;
    }
};

}  // namespace inkline_test
