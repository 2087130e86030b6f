#include "detail/moving_self_intersections.hpp"

#include <algorithm>
#include <cmath>

namespace inkline {
namespace {

struct Box {
    glm::dvec3 lo, hi;
    bool meets(const Box& o) const {  // closed: faces that only touch are candidates too
        return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y && lo.z <= o.hi.z && o.lo.z <= hi.z;
    }
};

Box face_box(const MeshTopology& mesh, std::uint32_t f) {
    const auto& t = mesh.faces[f];
    const glm::dvec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    return {glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c))};
}

// A uniform grid over the moving faces' boxes (each listed in every cell its box meets, compressed
// rows), asked whether a box meets any of them.
class MovingGrid {
public:
    explicit MovingGrid(std::vector<Box> boxes) : boxes_(std::move(boxes)) {
        all_ = boxes_[0];
        double size = 0.0;  // the boxes' mean largest side: about one box a cell
        for (const Box& b : boxes_) {
            all_.lo = glm::min(all_.lo, b.lo), all_.hi = glm::max(all_.hi, b.hi);
            const glm::dvec3 d = b.hi - b.lo;
            size += std::max(d.x, std::max(d.y, d.z));
        }
        size /= double(boxes_.size());
        const glm::dvec3 extent = all_.hi - all_.lo;
        for (int k = 0; k < 3; ++k) {
            dims_[k] = size > 0.0 ? int(std::clamp(std::ceil(extent[k] / size), 1.0, 128.0)) : 1;
            scale_[k] = extent[k] > 0.0 ? dims_[k] / extent[k] : 0.0;
        }
        begin_.assign(std::size_t(dims_[0]) * dims_[1] * dims_[2] + 1, 0);
        for_cells(boxes_, [&](std::uint32_t, std::size_t c) { ++begin_[c + 1]; });
        for (std::size_t c = 1; c < begin_.size(); ++c) begin_[c] += begin_[c - 1];
        items_.resize(begin_.back());
        std::vector<std::uint32_t> fill(begin_.begin(), begin_.end() - 1);
        for_cells(boxes_, [&](std::uint32_t i, std::size_t c) { items_[fill[c]++] = i; });
    }

    bool meets_any(const Box& b) const {
        if (!b.meets(all_)) return false;
        const auto [lo, hi] = cell_range(b);
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) {
                    const std::size_t c = cell(x, y, z);
                    for (std::uint32_t k = begin_[c]; k < begin_[c + 1]; ++k)
                        if (b.meets(boxes_[items_[k]])) return true;
                }
        return false;
    }

private:
    std::vector<Box> boxes_;
    Box all_;
    int dims_[3];
    double scale_[3];
    std::vector<std::uint32_t> begin_, items_;

    std::size_t cell(int x, int y, int z) const { return (std::size_t(z) * dims_[1] + y) * dims_[0] + x; }
    int clamp_cell(double v, int k) const {
        return std::clamp(int(std::floor((v - all_.lo[k]) * scale_[k])), 0, dims_[k] - 1);
    }
    std::pair<std::array<int, 3>, std::array<int, 3>> cell_range(const Box& b) const {
        std::array<int, 3> lo, hi;
        for (int k = 0; k < 3; ++k) lo[k] = clamp_cell(b.lo[k], k), hi[k] = clamp_cell(b.hi[k], k);
        return {lo, hi};
    }
    template <class Fn>
    void for_cells(const std::vector<Box>& boxes, Fn&& fn) const {
        for (std::uint32_t i = 0; i < boxes.size(); ++i) {
            const auto [lo, hi] = cell_range(boxes[i]);
            for (int z = lo[2]; z <= hi[2]; ++z)
                for (int y = lo[1]; y <= hi[1]; ++y)
                    for (int x = lo[0]; x <= hi[0]; ++x) fn(i, cell(x, y, z));
        }
    }
};

// Per face: 1 for a face whose box meets a moving face's box (2 for a moving face).
std::vector<std::uint8_t> candidates(const MeshTopology& mesh, const std::vector<std::uint8_t>& moved_vertex,
                                     MovingSearchStats& stats) {
    const std::size_t nf = mesh.face_count();
    std::vector<std::uint8_t> out(nf, 0);
    std::vector<Box> moving;
    for (std::uint32_t f = 0; f < nf; ++f) {
        const auto& t = mesh.faces[f];
        if (moved_vertex[t[0]] || moved_vertex[t[1]] || moved_vertex[t[2]]) {
            out[f] = 2;
            moving.push_back(face_box(mesh, f));
        }
    }
    stats.moving_faces = moving.size();
    if (moving.empty()) return out;
    const MovingGrid grid(std::move(moving));
    for (std::uint32_t f = 0; f < nf; ++f)
        if (!out[f] && grid.meets_any(face_box(mesh, f))) out[f] = 1;
    return out;
}

// The faces marked in `take`, as a mesh of its own (faces in the mesh's order, corners in theirs),
// with each of its faces' and vertices' numbers in the mesh; with `across`, also the faces across
// their edges, so that each marked face's edges keep the orientation and faces they have in the
// mesh (the cuts depend on them).
struct SubMesh {
    MeshTopology topology;
    std::vector<std::uint32_t> face, vertex;
};

SubMesh sub_mesh(const MeshTopology& mesh, std::vector<std::uint8_t>& take, bool across) {
    const std::size_t nf = mesh.face_count();
    if (across)
        for (std::uint32_t f = 0; f < nf; ++f)
            if (take[f] == 1)
                for (const std::uint32_t g : mesh.face_edges[f].face)
                    if (g != kNoFace && !take[g]) take[g] = 2;
    SubMesh s;
    TriangleMesh m;
    std::vector<std::uint32_t> index(mesh.vertex_count(), UINT32_MAX);
    for (std::uint32_t f = 0; f < nf; ++f)
        if (take[f]) {
            s.face.push_back(f);
            for (const std::uint32_t v : mesh.faces[f]) index[v] = 0;
        }
    for (std::uint32_t v = 0; v < index.size(); ++v)
        if (index[v] == 0) {
            index[v] = std::uint32_t(s.vertex.size());
            s.vertex.push_back(v);
            m.positions.push_back(mesh.positions[v]);
        }
    m.triangles.reserve(s.face.size());
    for (const std::uint32_t f : s.face) {
        const auto& t = mesh.faces[f];
        m.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
    }
    s.topology = build_topology(std::move(m), mesh.crease_degrees);
    return s;
}

}  // namespace

SelfIntersections self_intersections_of_moving(const MeshTopology& mesh, const std::vector<std::uint8_t>& moved_vertex,
                                               MovingSearchStats* stats) {
    MovingSearchStats local;
    MovingSearchStats& st = stats ? *stats : local;
    st = {};
    SelfIntersections out;
    out.faces.assign(mesh.face_count(), 0);
    std::vector<std::uint8_t> take = candidates(mesh, moved_vertex, st);
    if (st.moving_faces == 0) return out;
    for (std::uint8_t& c : take) c = c != 0;
    st.candidate_faces = std::size_t(std::count(take.begin(), take.end(), std::uint8_t(1)));
    // Two passes: the candidates' flags first (no pair list, no cuts: the cheap part of the search),
    // then the pairs and cuts among the flagged faces only (both faces of a pair are flagged).
    {
        const SubMesh s = sub_mesh(mesh, take, false);
        const std::vector<std::uint8_t> flags = self_intersecting_faces(s.topology);
        std::fill(take.begin(), take.end(), 0);
        for (std::uint32_t f = 0; f < flags.size(); ++f) take[s.face[f]] = flags[f];
    }
    if (std::find(take.begin(), take.end(), std::uint8_t(1)) == take.end()) return out;
    const SubMesh s = sub_mesh(mesh, take, true);
    st.searched_faces = s.face.size();
    const MeshTopology& sub = s.topology;
    const SelfIntersections found = self_intersections(sub);
    for (std::uint32_t f = 0; f < found.faces.size(); ++f)
        if (found.faces[f]) out.faces[s.face[f]] = 1;
    out.flagged = found.flagged;
    out.pairs.reserve(found.pairs.size());
    for (const auto& [f, g] : found.pairs) out.pairs.push_back({s.face[f], s.face[g]});
    out.cuts.reserve(found.cuts.size());
    for (const EdgeCut& c : found.cuts) {
        // The edge as the corner of its first face, in both meshes (corners are kept in order).
        const std::uint32_t fs = sub.edge_face[c.edge][0];
        int j = 0;
        while (sub.face_edges[fs].edge[j] != c.edge) ++j;
        const std::uint32_t e = mesh.face_edges[s.face[fs]].edge[j];
        // A candidate's edges run as in the mesh (both faces kept); only an edge of a face across
        // one, met by a pair the embedded assumption excludes, can run the other way.
        const bool same = s.vertex[sub.edge_vertex[c.edge][0]] == mesh.edge_vertex[e][0];
        out.cuts.push_back({e, same ? c.s : 1.0 - c.s});
    }
    std::sort(out.cuts.begin(), out.cuts.end());
    return out;
}

}  // namespace inkline
