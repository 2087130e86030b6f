#include "scene/scene.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <exception>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <unordered_set>

#include <assimp/Importer.hpp>
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

// The JSON of a .gltf file or of a .glb's first chunk ("" when the file is neither, or too short
// to hold one: Assimp then says what is wrong).
std::string gltf_json(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (data.size() >= 20 && data.compare(0, 4, "glTF") == 0) {
        std::uint32_t length = 0;
        std::memcpy(&length, data.data() + 12, 4);
        if (data.compare(16, 4, "JSON") != 0 || length > data.size() - 20) return "";
        return data.substr(20, length);
    }
    return lower_extension(path) == "gltf" ? data : std::string();
}

// Checks what Assimp's glTF reader follows by recursion, so that no file can exhaust the stack:
// JSON nesting (its JSON parser recurses per level) and the node graph (recursion per child
// level). Refuses nesting deeper than kMaxJsonDepth, node graphs deeper than kMaxNodeDepth, cycles
// and children out of range, by name.
constexpr int kMaxJsonDepth = 512;
void check_gltf_structure(const std::string& path) {
    const std::string text = gltf_json(path);
    if (text.empty()) return;
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
    const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("nodes") || !doc["nodes"].is_array()) return;
    const auto& nodes = doc["nodes"];
    const std::size_t n = nodes.size();
    std::vector<std::vector<std::size_t>> children(n);
    std::vector<int> parents(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (!nodes[i].is_object() || !nodes[i].contains("children") || !nodes[i]["children"].is_array()) continue;
        for (const auto& c : nodes[i]["children"]) {
            if (!c.is_number_unsigned() || c.get<std::size_t>() >= n)
                throw Error(path, "node " + std::to_string(i) + " has a child that is not one of the " + std::to_string(n) +
                                      " nodes");
            children[i].push_back(c.get<std::size_t>());
            ++parents[c.get<std::size_t>()];
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

}  // namespace

Camera SceneCamera::to_camera(int width, int height) const {
    try {
        if (orthographic) return Camera::orthographic(eye, target, up, ortho_height, width, height);
        return Camera::perspective(eye, target, up, fov_deg, width, height);
    } catch (const std::invalid_argument& e) {
        throw Error("camera '" + name + "'", e.what());
    }
}

bool is_scene_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext.empty() || ext == "obj" || ext == "off" || ext == "ply" || ext == "stl") return false;
    return Assimp::Importer().IsExtensionSupported("." + ext);
}

Scene load_scene(const std::string& path, const LoadOptions& options) {
    {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec)) throw Error(path, "cannot open: no such file");
    }
    check_gltf_structure(path);
    Assimp::Importer importer;
    // The file's own axes: Collada's up axis is not turned into +Y.
    importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
    const aiScene* s = nullptr;
    try {
        s = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_ValidateDataStructure);
    } catch (const std::exception& e) {
        throw Error(path, one_line(e.what(), path));
    }
    if (!s) throw Error(path, one_line(importer.GetErrorString(), path));
    if (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE) throw Error(path, "incomplete scene (no geometry, or a file Assimp could not finish)");
    if (!s->mRootNode) throw Error(path, "scene has no nodes");
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
    repair_mesh(out.mesh, path, options);
    return out;
}

}  // namespace inkline
