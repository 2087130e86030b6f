// estimate_curvature for a sequence of meshes drawn from one fixed set of vertices and faces (a
// progressive mesh's adapted meshes: each vertex and face is one of the input's, with its corners
// remapped), recomputed from one mesh to the next only where it can have changed.
//
// Takes, per mesh, its MeshTopology and each vertex's and face's id in the fixed set, both
// increasing with the index (face ids: so that a vertex meets its faces in the same order in every
// mesh; both: so that one merge matches a mesh to the last, with no map sized by the fixed set). Gives the mesh's CurvatureField, bit for bit estimate_curvature's: a vertex's normal and
// areas depend on its faces, its curvature on its neighbours' normals, its derivative on their
// curvature, so the values are recomputed at the vertices within three rings of a face whose
// corners or corner positions changed (and of a face that went away), with estimate_curvature's
// own per-face and per-vertex steps summed in the same order; every other vertex keeps its value.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "curvature/curvature.hpp"

namespace inkline {

class IncrementalCurvature {
public:
    IncrementalCurvature();
    ~IncrementalCurvature();
    IncrementalCurvature(const IncrementalCurvature&) = delete;
    IncrementalCurvature& operator=(const IncrementalCurvature&) = delete;

    // The field of `mesh`; `vertex_id[v]` and `face_id[f]` are its vertices' and faces' ids (each
    // increasing with the index; std::invalid_argument otherwise). The field lives until the next
    // call.
    const CurvatureField& update(const MeshTopology& mesh, const std::vector<std::uint32_t>& vertex_id,
                                 const std::vector<std::uint32_t>& face_id);
    const CurvatureField& field() const;
    // Vertices whose values the last update computed (the rest were carried over).
    std::size_t recomputed_vertices() const;

private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace inkline
