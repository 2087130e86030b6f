// View-dependent progressive mesh (seed 000: Jeong, Ni, Lee, Markosian 2005, section 3.1, on a
// Hoppe 96/97 vertex hierarchy): detail control by one adaptive mesh instead of smoothed copies.
//
// Takes: a model's topology (its arrays read in place, not copied) or a validated TriangleMesh
// (model/mesh_io.hpp), once; then a Camera and a target image area per view. Gives: the adapted TriangleMesh for that view, drawn by the pipeline as any model.
//
// The hierarchy is the input's full sequence of half-edge collapses in quadric order (OpenMesh's
// Decimater with its progressive-mesh module), kept as two flat arrays: a collapse moves no vertex,
// so every adapted mesh's vertices are input vertices at their input positions, and no detail is
// invented. OpenMesh's VDPM headers were not used: they hold only the node tree and the viewing
// parameters; the selective refinement itself lives in OpenMesh's viewer application (not shipped
// by Debian) and needs its own balanced .pm file format.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "core/camera.hpp"
#include "model/mesh_io.hpp"
#include "model/topology.hpp"

namespace inkline {

// The refinement criterion of section 3.1. A vertex's size is the average image-space area of the
// triangles of its 1-ring: A_img = k A / d^2 (perspective: k = F^2, d the vertex's depth, clamped
// at the near plane) or k A (orthographic: k = F^2). A vertex is split when A_img > split * T and
// collapsed when A_img < collapse * T (the seed's 1.42 and 0.7: a collapse about doubles a ring's
// area, so the band is just wide enough to hold a mesh that stops changing).
struct DetailCriterion {
    double target_area_px = 0.0;  // T in square pixels; 0: no adaptation (the input as it is)
    double collapse = 0.7;        // t_c
    double split = 1.42;          // t_s
    // Detail map: T at a vertex is target_area_px * map(pixel, depth) when set (its pixel
    // position and depth). 0 keeps full detail there; larger values coarsen.
    std::function<double(glm::dvec2 pixel, double depth)> map;
    double target_at(const Camera& camera, const glm::dvec3& p) const;
};

// A_img of one triangle's world area `area` seen at depth `depth` (the criterion's k A / d^2).
// (inline: the front's scan calls it per active vertex a frame)
inline double image_area(const Camera& camera, double area, double depth) {
    const double k = camera.focal() * camera.focal();
    if (camera.is_ortho()) return k * area;
    const double d = std::max(depth, camera.near_distance() > 0.0 ? camera.near_distance() : 1e-12);
    return k * area / (d * d);
}

struct AdaptStats {
    std::size_t collapses = 0;  // collapses applied (from the input)
    std::size_t passes = 0;     // passes over the hierarchy until one changed nothing
    std::size_t triangles = 0;  // of the adapted mesh
    std::size_t vertices = 0;
    double seconds = 0.0;
};

// The input's arrays as a hierarchy reads them: a model's, or the hierarchy's own mesh.
struct PmInput {
    const std::vector<glm::dvec3>& positions;
    const std::vector<std::array<std::uint32_t, 3>>& triangles;
    const std::vector<std::uint32_t>& face_object;     // (empty for a single object)
    const std::vector<std::string>& object_names;
    // A copy as a mesh of its own (tests and tools: the hierarchy itself never copies).
    operator TriangleMesh() const;
};

class ProgressiveMesh {
public:
    // Records the collapse sequence of a model's mesh and reads the model's arrays from then on
    // (no copy: `topology` must outlive the hierarchy and its fronts). A mesh OpenMesh cannot hold
    // as a manifold (complex vertices) gets an empty hierarchy: it is then drawn at full detail.
    // `progress` (optional) hears the collapses recorded so far and their most (vertices - 1) about
    // a hundred times during the build (armadillo@2: about 20 s); what it throws stops the build
    // within a hundredth of it and reaches the caller (the window stops a build it no longer needs).
    using BuildProgress = std::function<void(std::size_t collapses, std::size_t most)>;
    // The most collapses a hierarchy of `vertices` vertices can record (BuildProgress's `most`).
    static std::size_t most_collapses(std::size_t vertices) { return vertices > 0 ? vertices - 1 : 0; }
    explicit ProgressiveMesh(const MeshTopology& topology, const BuildProgress& progress = {});
    // The same over a mesh of its own (kept: tests and tools without a Model).
    explicit ProgressiveMesh(TriangleMesh mesh);
    // A collapse sequence recorded before for this topology (read from --cache: see
    // detail/progressive_mesh_cache.hpp), `seconds` what getting it cost. Throws
    // std::invalid_argument when the lists differ in length or name a vertex the topology lacks.
    ProgressiveMesh(const MeshTopology& topology, std::vector<std::uint32_t> removed, std::vector<std::uint32_t> kept,
                    double seconds);

    // The input's arrays (the model's, or the mesh given above).
    PmInput input() const { return {*positions_, *triangles_, *face_object_, *object_names_}; }
    std::size_t collapses() const { return removed_.size(); }
    double build_seconds() const { return build_seconds_; }
    // Bytes held by the hierarchy (the two arrays), an own copy of the input apart.
    std::size_t hierarchy_bytes() const { return (removed_.capacity() + kept_.capacity()) * sizeof(std::uint32_t); }
    // Collapse i moves removed_vertex()[i] onto kept_vertex()[i] (input vertex indices, in order).
    const std::vector<std::uint32_t>& removed_vertex() const { return removed_; }
    const std::vector<std::uint32_t>& kept_vertex() const { return kept_; }

    // The mesh converged to the criterion at `camera` (no geomorphs: a single frame). Starting from
    // the input, the collapses are replayed in hierarchy order, each applied when its removed vertex
    // is smaller than collapse * T, it is legal (OpenMesh's link condition; no face normal turned
    // by more than 90 degrees) and it leaves no vertex of the changed rings above split * T (or
    // above its own size, for a vertex already there: only the input's own triangles are). Passes
    // repeat until one applies nothing, so the mesh meets the criterion except at the hierarchy's
    // limits. Vertices are renumbered in input order; surviving faces keep the input's order;
    // `input_vertex`, when given, receives each output vertex's input index.
    TriangleMesh adapt(const Camera& camera, const DetailCriterion& criterion, AdaptStats* stats = nullptr,
                       std::vector<std::uint32_t>* input_vertex = nullptr, std::size_t max_passes = 32) const;

private:
    std::unique_ptr<const TriangleMesh> owned_;  // (on the heap: a moved hierarchy's pointers stay valid)
    const std::vector<glm::dvec3>* positions_ = nullptr;
    const std::vector<std::array<std::uint32_t, 3>>* triangles_ = nullptr;
    const std::vector<std::uint32_t>* face_object_ = nullptr;
    const std::vector<std::string>* object_names_ = nullptr;
    std::vector<std::uint32_t> removed_, kept_;  // collapse i moves removed_[i] onto kept_[i]
    double build_seconds_ = 0.0;
    void build(const BuildProgress& progress = {});
};

// A model's vertices and faces (and objects) as a TriangleMesh (a copy).
TriangleMesh triangle_mesh_of(const MeshTopology& topology);

// Per vertex of `mesh`: the average image area of its 1-ring's triangles (0 for a vertex in no
// triangle), as the criterion measures it.
std::vector<double> ring_image_areas(const TriangleMesh& mesh, const Camera& camera);

}  // namespace inkline
