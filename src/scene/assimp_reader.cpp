// libinkline_assimp.so: Assimp's reading of scene files, behind scene/scene_reader.hpp. Calls no
// function of inkline_core (linked with --no-undefined to keep it so): Error and the progress
// reporter are header-only, the repairs and camera checks stay in the program.
#include "scene/scene_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <exception>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <unordered_set>

#include <assimp/DefaultIOSystem.h>
#include <assimp/IOStream.hpp>
#include <assimp/Importer.hpp>
#include <assimp/ProgressHandler.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace inkline {
namespace {

std::string lower_extension(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    if (!e.empty()) e.erase(0, 1);
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
    return e;
}

// Assimp's messages may span lines and repeat the path; the error contract is one line that
// names the file once, at its start.
std::string one_line(std::string s, const std::string& path) {
    for (std::size_t at; !path.empty() && (at = s.find(path)) != std::string::npos;) s.replace(at, path.size(), "(this file)");
    for (char& c : s)
        if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    const auto b = s.find_first_not_of(' ');
    s = b == std::string::npos ? std::string() : s.substr(b, s.find_last_not_of(' ') - b + 1);
    if (s.size() > 300) s = s.substr(0, 297) + "...";
    return s.empty() ? "unknown error" : s;
}

// aiMatrix4x4 is row-major (a1..a4 the first row) and maps column vectors, as glm does.
glm::dmat4 to_glm(const aiMatrix4x4& m) {
    glm::dmat4 g(1.0);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) g[c][r] = m[r][c];
    return g;
}

bool finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

std::string node_name(const aiNode* node) {
    const std::string n = node->mName.C_Str();
    return n.empty() ? "(unnamed node)" : n;
}

// Every node that holds meshes, placed by its world transform: one object per such node.
class SceneBuilder {
public:
    SceneBuilder(const aiScene& scene, const std::string& path, TriangleMesh& mesh)
        : scene_(scene), path_(path), mesh_(mesh) {}

    void add_nodes() {
        struct Item {
            const aiNode* node;
            glm::dmat4 parent;
            int depth;
        };
        std::vector<Item> stack{{scene_.mRootNode, glm::dmat4(1.0), 0}};
        std::unordered_set<const aiNode*> seen;
        while (!stack.empty()) {
            const Item it = stack.back();
            stack.pop_back();
            if (!it.node) continue;
            if (!seen.insert(it.node).second)
                throw Error(path_, "node '" + node_name(it.node) + "' is its own ancestor or listed twice (cyclic node graph)");
            if (it.depth > kMaxNodeDepth)
                throw Error(path_, "node graph deeper than " + std::to_string(kMaxNodeDepth) + " levels");
            const glm::dmat4 world = it.parent * to_glm(it.node->mTransformation);
            if (!finite(world)) throw Error(path_, "node '" + node_name(it.node) + "' has a NaN or infinite transform");
            if (it.node->mNumMeshes > 0) add_instance(*it.node, world);
            for (unsigned c = it.node->mNumChildren; c-- > 0;)  // reversed: children visited in file order
                stack.push_back({it.node->mChildren[c], world, it.depth + 1});
        }
    }

    std::size_t skipped_primitives() const { return skipped_; }

private:
    void add_instance(const aiNode& node, const glm::dmat4& world) {
        const std::uint32_t object = std::uint32_t(mesh_.object_names.size());
        mesh_.object_names.push_back(node_name(&node));
        const glm::dmat3 linear(world);
        const bool mirrored = glm::determinant(linear) < 0.0;  // keep normals outward: flip the winding
        for (unsigned k = 0; k < node.mNumMeshes; ++k) {
            const unsigned mi = node.mMeshes[k];
            if (mi >= scene_.mNumMeshes || !scene_.mMeshes[mi])
                throw Error(path_, "node '" + node_name(&node) + "' refers to mesh " + std::to_string(mi) + " of " +
                                       std::to_string(scene_.mNumMeshes));
            const aiMesh& m = *scene_.mMeshes[mi];
            if (mesh_.positions.size() + m.mNumVertices >= UINT32_MAX)
                throw Error(path_, "more than 2^32 vertices in the scene");
            const std::uint32_t base = std::uint32_t(mesh_.positions.size());
            for (unsigned v = 0; v < m.mNumVertices; ++v) {
                const aiVector3D& p = m.mVertices[v];
                mesh_.positions.push_back(glm::dvec3(world * glm::dvec4(p.x, p.y, p.z, 1.0)));
            }
            for (unsigned f = 0; f < m.mNumFaces; ++f) {
                const aiFace& face = m.mFaces[f];
                if (face.mNumIndices != 3) {  // points and lines have no surface to draw
                    ++skipped_;
                    continue;
                }
                std::array<std::uint32_t, 3> t{};
                for (int c = 0; c < 3; ++c) {
                    if (face.mIndices[c] >= m.mNumVertices)
                        throw Error(path_, "mesh '" + std::string(m.mName.C_Str()) + "' face " + std::to_string(f) +
                                               " refers to vertex " + std::to_string(face.mIndices[c]) + " of " +
                                               std::to_string(m.mNumVertices));
                    t[c] = base + face.mIndices[c];
                }
                if (mirrored) std::swap(t[1], t[2]);
                mesh_.triangles.push_back(t);
                mesh_.face_object.push_back(object);
            }
        }
    }

    const aiScene& scene_;
    const std::string& path_;
    TriangleMesh& mesh_;
    std::size_t skipped_ = 0;
};

// The world transform of a node: the product along its parent chain.
glm::dmat4 world_of(const aiNode* node, const std::string& path) {
    glm::dmat4 w(1.0);
    for (int depth = 0; node; node = node->mParent, ++depth) {
        if (depth > kMaxNodeDepth) throw Error(path, "node graph deeper than " + std::to_string(kMaxNodeDepth) + " levels");
        w = to_glm(node->mTransformation) * w;
    }
    return w;
}

// Assimp's aiCamera: position, look-at direction and up in the node's frame; mHorizontalFOV is
// documented as half the horizontal angle (radians), but Assimp's glTF 2 importer stores
// yfov * aspectRatio there (measured: yfov 0.6, aspect 1.5 gives 0.9), so glTF's yfov is read back
// as mHorizontalFOV / aspect; mAspect is width / height (0: not given), mOrthographicWidth half
// the horizontal width (0: perspective).
SceneCamera scene_camera(const aiScene& scene, const aiCamera& cam, const std::string& path) {
    SceneCamera c;
    c.name = cam.mName.C_Str();
    const aiNode* node = scene.mRootNode ? scene.mRootNode->FindNode(cam.mName) : nullptr;
    const glm::dmat4 world = node ? world_of(node, path) : glm::dmat4(1.0);
    if (!finite(world)) throw Error(path, "camera '" + c.name + "' has a NaN or infinite transform");
    const glm::dmat3 linear(world);
    // Assimp's glTF 2 importer also copies the camera node's translation into mPosition, which the
    // node's transform already holds (measured: a node at (0, 0, 10) put the eye at (0, 0, 20)); a
    // glTF camera sits at its node's origin.
    const bool gltf = lower_extension(path) == "gltf" || lower_extension(path) == "glb";
    const glm::dvec3 local = gltf ? glm::dvec3(0.0) : glm::dvec3(cam.mPosition.x, cam.mPosition.y, cam.mPosition.z);
    c.eye = glm::dvec3(world * glm::dvec4(local, 1.0));
    const glm::dvec3 look = linear * glm::dvec3(cam.mLookAt.x, cam.mLookAt.y, cam.mLookAt.z);
    c.up = linear * glm::dvec3(cam.mUp.x, cam.mUp.y, cam.mUp.z);
    const double len = glm::length(look);
    c.target = c.eye + (len > 0.0 ? look / len : look);
    c.aspect = cam.mAspect > 0.0f && std::isfinite(cam.mAspect) ? double(cam.mAspect) : 0.0;
    const double aspect = c.aspect > 0.0 ? c.aspect : 1.0;
    if (cam.mOrthographicWidth > 0.0f) {
        c.orthographic = true;
        c.ortho_height = 2.0 * double(cam.mOrthographicWidth) / aspect;
    } else {
        const std::string ext = lower_extension(path);
        const double fov_rad = ext == "gltf" || ext == "glb"
                                   ? double(cam.mHorizontalFOV) / aspect
                                   : 2.0 * std::atan(std::tan(double(cam.mHorizontalFOV)) / aspect);
        c.fov_deg = fov_rad * 180.0 / M_PI;
    }
    return c;
}

std::uint32_t u32_at(const std::string& data, std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, data.data() + at, 4);  // little-endian files on little-endian hosts
    return v;
}

// The JSON of a .gltf file or of a .glb's first chunk ("" when the file is neither glTF 2.0 text nor
// a binary glTF: Assimp then says what is wrong). Of a .glb only the header and the JSON chunk are
// read; a .glb shorter than its header's length, or whose chunks run past its end, is refused here
// as truncated (Assimp reads such files when what it needs happens to be there).
std::string gltf_json(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string head(20, '\0');
    in.read(head.data(), 20);
    head.resize(std::size_t(in.gcount()));
    const std::string ext = lower_extension(path);
    if (head.compare(0, 4, "glTF") != 0) {
        // Not left to Assimp: it then tries its other readers on the bytes, and one of them reads
        // past its buffer (ASan in Assimp 5.2.5; fuzz/regressions/glb-no-magic).
        if (ext == "glb") throw Error(path, "not a binary glTF file (it does not start with 'glTF')");
        if (ext != "gltf") return "";
        in.clear();
        in.seekg(0);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    }
    in.clear();
    in.seekg(0, std::ios::end);
    const std::uint64_t size = std::uint64_t(in.tellg());
    if (head.size() < 12) throw Error(path, "truncated: the file ends inside the 12-byte binary glTF header");
    const std::uint32_t length = u32_at(head, 8);
    if (length > size)
        throw Error(path, "truncated: the binary glTF header says " + std::to_string(length) + " bytes, the file has " +
                              std::to_string(size));
    if (u32_at(head, 4) != 2) return "";  // glTF 1 binary (KHR_binary_glTF): Assimp's own checks
    if (head.size() < 20) throw Error(path, "truncated: the file ends before its first chunk");
    const std::uint32_t json_length = u32_at(head, 12);
    if (std::uint64_t(json_length) + 20 > length)
        throw Error(path, "truncated: the JSON chunk's " + std::to_string(json_length) + " bytes run past the file's " +
                              std::to_string(length));
    if (head.compare(16, 4, "JSON") != 0) return "";
    std::string json(json_length, '\0');
    in.seekg(20);
    in.read(json.data(), json_length);
    if (std::uint64_t(json_length) + 20 + 8 <= length) {  // a second chunk (BIN): its length must fit too
        std::string chunk(4, '\0');
        in.seekg(20 + json_length);
        in.read(chunk.data(), 4);
        const std::uint64_t bin_end = 20 + std::uint64_t(json_length) + 8 + u32_at(chunk, 0);
        if (in && bin_end > length)
            throw Error(path, "truncated: the binary chunk ends " + std::to_string(bin_end) + " bytes in, the file has " +
                                  std::to_string(length));
    }
    return json;
}

// Refuses JSON nested deeper than kMaxJsonDepth (the JSON parsers recurse per level), before
// anything parses it.
constexpr int kMaxJsonDepth = 512;
void check_json_depth(const std::string& text, const std::string& path) {
    int depth = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                throw Error(path, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

// Refuses node graphs with children out of range, cycles, or deeper than kMaxNodeDepth (Assimp's
// glTF reader follows children by recursion).
void check_node_graph(const nlohmann::json& nodes, const std::string& path) {
    const std::size_t n = nodes.size();
    std::vector<std::vector<std::size_t>> children(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (!nodes[i].is_object() || !nodes[i].contains("children") || !nodes[i]["children"].is_array()) continue;
        for (const auto& c : nodes[i]["children"]) {
            if (!c.is_number_unsigned() || c.get<std::size_t>() >= n)
                throw Error(path, "node " + std::to_string(i) + " has a child that is not one of the " + std::to_string(n) +
                                      " nodes");
            children[i].push_back(c.get<std::size_t>());
        }
    }
    // Depth by iterative search from every node; a node met again on the current path is a cycle.
    std::vector<int> state(n, 0);  // 0 new, 1 on the path, 2 done
    std::vector<int> height(n, 0);
    for (std::size_t root = 0; root < n; ++root) {
        if (state[root]) continue;
        std::vector<std::pair<std::size_t, std::size_t>> stack{{root, 0}};  // node, next child
        state[root] = 1;
        while (!stack.empty()) {
            auto& [v, k] = stack.back();
            if (k < children[v].size()) {
                const std::size_t c = children[v][k++];
                if (state[c] == 1) throw Error(path, "node " + std::to_string(c) + " is its own ancestor (cyclic node graph)");
                if (state[c] == 0) {
                    state[c] = 1;
                    stack.push_back({c, 0});
                }
                continue;
            }
            for (std::size_t c : children[v]) height[v] = std::max(height[v], height[c] + 1);
            if (height[v] > kMaxNodeDepth)
                throw Error(path, "node graph deeper than " + std::to_string(kMaxNodeDepth) + " levels");
            state[v] = 2;
            stack.pop_back();
        }
    }
}

// What a glTF file says it holds, to check Assimp's scene against: per primitive (in file order)
// the triangles it lists, or -1 where that is not simply known (not a triangle list, or an
// accessor Assimp refuses itself).
struct GltfFacts {
    bool known = false;  // a glTF 2.0 document was read
    std::vector<std::int64_t> triangles;
    std::vector<std::int64_t> vertices;  // per primitive: its POSITION count (-1: not known)
    std::vector<std::string> names;      // per primitive: its mesh's name
    std::uint64_t buffer_bytes = 0;  // of the buffers in files of their own (.bin), for the progress
};

// An accessor's field, or -1 when absent or not an unsigned number.
std::int64_t accessor_field(const nlohmann::json& accessors, const nlohmann::json& index, const char* field) {
    if (!index.is_number_unsigned() || index.get<std::size_t>() >= accessors.size()) return -1;
    const auto& a = accessors[index.get<std::size_t>()];
    if (!a.is_object() || !a.contains(field) || !a[field].is_number_unsigned()) return -1;
    return a[field].get<std::int64_t>();
}

// Refuses the primitives' accessors that glTF forbids in their role and Assimp would read as
// garbage (measured with Assimp 5.2.5: float indices and 2-component positions draw nonsense),
// and records the triangles each triangle-list primitive lists.
void check_primitives(const nlohmann::json& doc, const std::string& path, GltfFacts& facts) {
    static const nlohmann::json kEmpty = nlohmann::json::array();
    const auto& meshes = doc.contains("meshes") && doc["meshes"].is_array() ? doc["meshes"] : kEmpty;
    const auto& accessors = doc.contains("accessors") && doc["accessors"].is_array() ? doc["accessors"] : kEmpty;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        if (!meshes[m].is_object() || !meshes[m].contains("primitives") || !meshes[m]["primitives"].is_array()) continue;
        for (const auto& p : meshes[m]["primitives"]) {
            std::int64_t triangles = -1, vertices = -1;
            const std::string where = "mesh " + std::to_string(m);
            if (p.is_object() && p.contains("indices")) {
                const std::int64_t type = accessor_field(accessors, p["indices"], "componentType");
                if (type >= 0 && type != 5121 && type != 5123 && type != 5125)
                    throw Error(path, where + ": its indices are of componentType " + std::to_string(type) +
                                          " (glTF allows unsigned byte, short or int: 5121, 5123, 5125)");
            }
            if (p.is_object() && p.contains("attributes") && p["attributes"].is_object() &&
                p["attributes"].contains("POSITION")) {
                const auto& index = p["attributes"]["POSITION"];
                if (index.is_number_unsigned() && index.get<std::size_t>() < accessors.size()) {
                    const auto& a = accessors[index.get<std::size_t>()];
                    if (a.is_object() && a.contains("type") && a["type"] != "VEC3")
                        throw Error(path, where + ": its POSITION accessor is of type " + a["type"].dump() +
                                              " (glTF requires VEC3)");
                }
                const bool triangle_list = !p.contains("mode") || p["mode"] == 4;
                const std::int64_t corners = p.contains("indices") ? accessor_field(accessors, p["indices"], "count")
                                                                   : accessor_field(accessors, index, "count");
                if (triangle_list && corners >= 0) triangles = corners / 3;
                vertices = accessor_field(accessors, index, "count");
            }
            facts.triangles.push_back(triangles);
            facts.vertices.push_back(vertices);
            facts.names.push_back(meshes[m].contains("name") && meshes[m]["name"].is_string()
                                      ? meshes[m]["name"].get<std::string>()
                                      : std::string());
        }
    }
}

// Checks what Assimp's glTF 2 reader follows by recursion, so that no file can exhaust the stack
// (JSON nesting, the node graph), refuses what it would read wrongly (check_primitives) and
// truncated binary files (gltf_json), each by name. Returns what the file holds.
GltfFacts check_gltf(const std::string& path) {
    GltfFacts facts;
    const std::string text = gltf_json(path);
    if (text.empty()) return facts;
    check_json_depth(text, path);
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        const std::string m = e.what();
        const auto at = m.find("] ");  // nlohmann's "[json.exception.parse_error.101] parse error at ..."
        throw Error(path, "not valid JSON: " + one_line(at == std::string::npos ? m : m.substr(at + 2), path));
    }
    if (!doc.is_object()) return facts;
    if (doc.contains("asset") && doc["asset"].is_object() && doc["asset"].contains("version") &&
        doc["asset"]["version"].is_string() && doc["asset"]["version"].get<std::string>().rfind("1", 0) == 0)
        return facts;  // glTF 1: Assimp's own checks
    if (doc.contains("nodes") && doc["nodes"].is_array()) check_node_graph(doc["nodes"], path);
    check_primitives(doc, path, facts);
    if (doc.contains("buffers") && doc["buffers"].is_array())
        for (const auto& b : doc["buffers"])
            if (b.is_object() && b.contains("uri") && b["uri"].is_string() &&
                b["uri"].get<std::string>().rfind("data:", 0) != 0 && b.contains("byteLength") &&
                b["byteLength"].is_number_unsigned())
                facts.buffer_bytes += b["byteLength"].get<std::uint64_t>();
    facts.known = true;
    return facts;
}

// Assimp's glTF 2 reader drops the triangles whose indices are out of range with only a log
// line; inkline refuses such files by name. Assimp's meshes are not in the file's order (it makes
// them as nodes refer to them, and skips the unreferenced), so each is matched to the file's
// primitives by its vertex count (POSITION's count, which Assimp keeps): where all primitives of
// that count list the same number of triangles and the mesh has fewer, some were dropped.
void check_triangles_kept(const aiScene& s, const GltfFacts& facts, const std::string& path) {
    if (!facts.known) return;
    std::map<std::int64_t, std::int64_t> listed;  // vertex count -> triangles (-1: primitives disagree)
    for (std::size_t i = 0; i < facts.triangles.size(); ++i) {
        if (facts.vertices[i] < 0 || facts.triangles[i] < 0) continue;
        const auto [it, inserted] = listed.try_emplace(facts.vertices[i], facts.triangles[i]);
        if (!inserted && it->second != facts.triangles[i]) it->second = -1;
    }
    for (unsigned i = 0; i < s.mNumMeshes; ++i) {
        const aiMesh* m = s.mMeshes[i];
        if (!m || (m->mPrimitiveTypes & ~unsigned(aiPrimitiveType_TRIANGLE)) != 0) continue;
        const auto it = listed.find(std::int64_t(m->mNumVertices));
        if (it == listed.end() || it->second < 0 || std::int64_t(m->mNumFaces) >= it->second) continue;
        throw Error(path, "mesh '" + std::string(m->mName.C_Str()) + "': " +
                              std::to_string(it->second - std::int64_t(m->mNumFaces)) + " of its " +
                              std::to_string(it->second) + " triangles refer to vertices beyond its " +
                              std::to_string(m->mNumVertices) + " (indices out of range)");
    }
}

// Assimp's glTF 2 reader refuses a mesh whose every triangle has an index out of range as a mesh
// "has no faces"; its error then says why when the file lists triangles for that mesh.
std::string explain_gltf_error(const std::string& message, const GltfFacts& facts) {
    for (std::size_t i = 0; i < facts.names.size(); ++i)
        if (facts.triangles[i] > 0 && facts.vertices[i] >= 0 &&
            message.find("Mesh \"" + facts.names[i] + "\" has no faces") != std::string::npos)
            return "mesh '" + facts.names[i] + "': all " + std::to_string(facts.triangles[i]) +
                   " of its triangles refer to vertices beyond its " + std::to_string(facts.vertices[i]) +
                   " (indices out of range)";
    return message;
}

// Assimp reads through this: large reads go in pieces of at most 4 MiB, and the bytes read so far
// (of every file the import opens) are reported, so a large file shows its progress while read.
class ProgressIO : public Assimp::DefaultIOSystem {
public:
    ProgressIO(LoadProgressReporter& progress, double share) : progress_(progress), share_(share) {}
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        Assimp::IOStream* inner = Assimp::DefaultIOSystem::Open(file, mode);
        return inner ? new Stream(*this, inner) : nullptr;
    }
    void Close(Assimp::IOStream* stream) override { delete stream; }

private:
    class Stream : public Assimp::IOStream {
    public:
        Stream(ProgressIO& io, Assimp::IOStream* inner) : io_(io), inner_(inner) {}
        ~Stream() override { io_.Assimp::DefaultIOSystem::Close(inner_); }
        size_t Read(void* buffer, size_t size, size_t count) override {
            if (size == 0 || count == 0) return 0;
            // In pieces of bytes (Assimp reads a glb's whole binary chunk as one element).
            const size_t total = size * count;
            size_t done = 0;
            while (done < total) {
                const size_t want = std::min(kPiece, total - done);
                const size_t got = account(inner_->Read(static_cast<char*>(buffer) + done, 1, want));
                done += got;
                if (got < want) break;
            }
            return done / size;
        }
        size_t Write(const void* buffer, size_t size, size_t count) override { return inner_->Write(buffer, size, count); }
        aiReturn Seek(size_t offset, aiOrigin origin) override { return inner_->Seek(offset, origin); }
        size_t Tell() const override { return inner_->Tell(); }
        size_t FileSize() const override { return inner_->FileSize(); }
        void Flush() override { inner_->Flush(); }

    private:
        static constexpr size_t kPiece = size_t(4) << 20;
        size_t account(size_t bytes) {
            io_.bytes_ += bytes;
            io_.progress_.bytes(io_.bytes_, 0.0, io_.share_);
            return bytes;
        }
        ProgressIO& io_;
        Assimp::IOStream* inner_;
    };
    LoadProgressReporter& progress_;
    double share_;
    std::uint64_t bytes_ = 0;
};

// Assimp's own progress (the end of its reading, its post-processing steps), onto the parse stage.
class ProgressSteps : public Assimp::ProgressHandler {
public:
    explicit ProgressSteps(LoadProgressReporter& progress) : progress_(progress) {}
    bool Update(float percentage) override {
        if (percentage >= 0.0f) progress_.at(double(percentage) * kProgressParsed);
        return true;
    }

private:
    LoadProgressReporter& progress_;
};

class AssimpReader final : public SceneReader {
public:
    bool reads_extension(const std::string& extension) const override {
        return Assimp::Importer().IsExtensionSupported(extension);
    }
    Scene read(const std::string& path, const LoadOptions& options, std::uint64_t& progress_bytes) const override;
};

Scene AssimpReader::read(const std::string& path, const LoadOptions& options, std::uint64_t& progress_bytes) const {
    std::uint64_t file_bytes = 0;
    {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec)) throw Error(path, "cannot open: no such file");
        file_bytes = std::filesystem::file_size(path, ec);
    }
    const GltfFacts facts = check_gltf(path);
    progress_bytes = file_bytes + facts.buffer_bytes;
    LoadProgressReporter progress(&options.progress, progress_bytes);
    Assimp::Importer importer;
    // The file's own axes: Collada's up axis is not turned into +Y.
    importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
    if (progress.active()) {  // the importer owns both
        importer.SetIOHandler(new ProgressIO(progress, 0.5 * kProgressParsed));
        importer.SetProgressHandler(new ProgressSteps(progress));
    }
    // Post-processing: triangulation only (polygons of the formats that have them; nothing to do
    // for glTF) and the validation that keeps malformed data out. No vertex joining (inkline
    // welds by exact position itself, per object: repair_mesh), no pre-transforming (instances
    // are placed here, once per node) and no normals (the topology computes its own).
    // The triangles kept are compared with the file's before validation, which would refuse a mesh
    // left without any under a name that does not say why.
    const aiScene* s = nullptr;
    try {
        s = importer.ReadFile(path, 0);
        if (s) check_triangles_kept(*s, facts, path);
        if (s) s = importer.ApplyPostProcessing(aiProcess_ValidateDataStructure | aiProcess_Triangulate);
    } catch (const std::exception& e) {
        if (dynamic_cast<const Error*>(&e)) throw;
        throw Error(path, explain_gltf_error(one_line(e.what(), path), facts));
    }
    if (!s) throw Error(path, explain_gltf_error(one_line(importer.GetErrorString(), path), facts));
    if (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE) throw Error(path, "incomplete scene (no geometry, or a file Assimp could not finish)");
    if (!s->mRootNode) throw Error(path, "scene has no nodes");
    progress.stage(kProgressParsed);
    Scene out;
    SceneBuilder builder(*s, path, out.mesh);
    builder.add_nodes();
    if (out.mesh.triangles.empty())
        throw Error(path, builder.skipped_primitives() > 0
                              ? "no faces: the scene holds " + std::to_string(builder.skipped_primitives()) +
                                    " points or lines only"
                              : std::string("no faces in the scene"));
    for (unsigned i = 0; i < s->mNumCameras; ++i)
        if (s->mCameras[i]) out.cameras.push_back(scene_camera(*s, *s->mCameras[i], path));
    return out;  // the importer frees Assimp's copy of the meshes before the repairs
}

}  // namespace

}  // namespace inkline

extern "C" __attribute__((visibility("default"))) const inkline::SceneReader* inkline_scene_reader_v1() {
    static const inkline::AssimpReader reader;
    return &reader;
}
