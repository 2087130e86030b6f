// The window's toon-shaded base coat under the lines (`view --detail`, as in seed 000's results):
// the mesh a view was drawn from, in three flat tones of a warm grey by its smooth normal against
// a light above-left of the eye. Its own GL program and buffers (GL 3.3 core), apart from GlScene.
#pragma once

#include <cstdint>
#include <vector>

#include "core/camera.hpp"
#include "model/topology.hpp"

namespace inkline {

// A mesh ready for the coat: float positions relative to `centre` and area-weighted vertex
// normals, interleaved (6 floats a vertex), and its triangles. Built off the GL thread.
struct CoatMesh {
    std::vector<float> vertices;
    std::vector<std::uint32_t> triangles;
    glm::dvec3 centre{0.0};
    double radius = 1.0;  // bounds the mesh around centre (the depth range)
    void build(const MeshTopology& mesh, const glm::dvec3& centre, double radius);
};

class ToonCoat {
public:
    ToonCoat() = default;
    ~ToonCoat();
    ToonCoat(const ToonCoat&) = delete;
    ToonCoat& operator=(const ToonCoat&) = delete;
    // Uploads `mesh` when `fresh` (or on first use), then draws it with depth test into the
    // current framebuffer at `camera` (a GL context must be current).
    void draw(const Camera& camera, const CoatMesh& mesh, bool fresh);

private:
    unsigned prog_ = 0, vao_ = 0, bufs_[2] = {0, 0};
    std::size_t indices_ = 0;
};

}  // namespace inkline
