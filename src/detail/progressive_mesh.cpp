#include "detail/progressive_mesh.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <stdexcept>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModProgMeshT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <OpenMesh/Tools/Decimater/Observer.hh>
#include <glm/geometric.hpp>

namespace inkline {
namespace {

struct PmTraits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
};
using OMesh = OpenMesh::TriMesh_ArrayKernelT<PmTraits>;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Vertex i and face f of `in` become OpenMesh's handles i and f; false when OpenMesh refuses a
// face (a complex vertex: OpenMesh's half-edges hold manifold vertices only).
bool to_openmesh(const ProgressiveMesh& in, OMesh& out) {
    out.request_vertex_status();
    out.request_edge_status();
    out.request_halfedge_status();
    out.request_face_status();
    for (const glm::dvec3& p : in.input().positions) out.add_vertex(OMesh::Point(p.x, p.y, p.z));
    for (const auto& t : in.input().triangles) {
        const auto f = out.add_face(OMesh::VertexHandle(int(t[0])), OMesh::VertexHandle(int(t[1])),
                                    OMesh::VertexHandle(int(t[2])));
        if (!f.is_valid()) return false;
    }
    return true;
}

glm::dvec3 to_glm(const OMesh::Point& p) { return {p[0], p[1], p[2]}; }

glm::dvec3 twice_area_normal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return glm::cross(b - a, c - a);
}

// Replays the hierarchy's collapses on one OpenMesh copy of the input under the criterion. The
// vertices never move, so each vertex's k/d^2 and target are computed once.
class Adapter {
public:
    Adapter(const std::vector<glm::dvec3>& positions, const Camera& camera, const DetailCriterion& criterion)
        : criterion_(criterion) {
        scale_.resize(positions.size());
        target_.resize(positions.size());
        for (std::size_t v = 0; v < positions.size(); ++v) {
            const glm::dvec3& p = positions[v];
            scale_[v] = image_area(camera, 1.0, camera.depth(p));
            target_[v] = criterion.target_at(camera, p);
        }
    }
    OMesh mesh;

    // One pass over the hierarchy; returns the collapses applied.
    std::size_t pass(const std::vector<std::uint32_t>& removed, const std::vector<std::uint32_t>& kept) {
        std::size_t applied = 0;
        for (std::size_t i = 0; i < removed.size(); ++i)
            if (try_collapse(OMesh::VertexHandle(int(removed[i])), OMesh::VertexHandle(int(kept[i])))) ++applied;
        return applied;
    }

private:
    const DetailCriterion& criterion_;
    std::vector<double> scale_, target_;

    bool try_collapse(OMesh::VertexHandle r, OMesh::VertexHandle k) {
        if (mesh.status(r).deleted() || mesh.status(k).deleted()) return false;
        const double t_r = target_[r.idx()];
        if (!(t_r > 0.0) || !(image_size(r) < criterion_.collapse * t_r)) return false;
        const auto h = mesh.find_halfedge(r, k);  // invalid when a skipped collapse made them neighbours
        if (!h.is_valid() || !mesh.is_collapse_ok(h)) return false;
        if (flips(r, k) || !rings_stay_in_band(r, k)) return false;
        mesh.collapse(h);
        return true;
    }

    // The average world area of v's ring triangles now (collapse of r onto k not made) or after it.
    double ring_area(OMesh::VertexHandle v, OMesh::VertexHandle r, OMesh::VertexHandle k, bool after) const {
        double sum = 0.0;
        std::size_t count = 0;
        const auto add_faces_of = [&](OMesh::VertexHandle around, bool skip_with_k) {
            for (auto f : mesh.vf_range(around)) {
                glm::dvec3 p[3];
                bool has_r = false, has_k = false;
                int j = 0;
                for (auto u : mesh.fv_range(f)) {
                    has_r |= u == r;
                    has_k |= u == k;
                    p[j++] = to_glm(mesh.point(after && u == r ? k : u));
                }
                if (after && ((has_r && has_k) || (skip_with_k && has_k))) continue;  // gone with the collapse
                sum += 0.5 * glm::length(twice_area_normal(p[0], p[1], p[2]));
                ++count;
            }
        };
        add_faces_of(v, false);
        if (after && v == k) add_faces_of(r, true);  // k inherits r's faces
        return count ? sum / double(count) : 0.0;
    }

    double image_size(OMesh::VertexHandle v) const { return scale_[v.idx()] * ring_area(v, v, v, false); }

    // A face of r's ring that would turn over (or vanish) when r moves onto k.
    bool flips(OMesh::VertexHandle r, OMesh::VertexHandle k) const {
        const glm::dvec3 to = to_glm(mesh.point(k));
        for (auto f : mesh.vf_range(r)) {
            glm::dvec3 before[3], after[3];
            bool has_k = false;
            int j = 0;
            for (auto u : mesh.fv_range(f)) {
                has_k |= u == k;
                before[j] = to_glm(mesh.point(u));
                after[j] = u == r ? to : before[j];
                ++j;
            }
            if (has_k) continue;
            const glm::dvec3 n0 = twice_area_normal(before[0], before[1], before[2]);
            const glm::dvec3 n1 = twice_area_normal(after[0], after[1], after[2]);
            if (!(glm::dot(n0, n1) > 0.0)) return true;
        }
        return false;
    }

    // No vertex whose ring changes (k and r's other neighbours) ends above split * T, unless it was
    // there already and does not grow.
    bool rings_stay_in_band(OMesh::VertexHandle r, OMesh::VertexHandle k) const {
        const auto ok = [&](OMesh::VertexHandle u) {
            const double limit = criterion_.split * target_[u.idx()];
            const double now = scale_[u.idx()] * ring_area(u, r, k, false);
            const double then = scale_[u.idx()] * ring_area(u, r, k, true);
            return then <= std::max(limit, now);
        };
        if (!ok(k)) return false;
        for (auto u : mesh.vv_range(r))
            if (u != k && !ok(u)) return false;
        return true;
    }
};

// The live part of `mesh`: vertices renumbered in input order, faces in input order.
TriangleMesh compact(const OMesh& mesh, const ProgressiveMesh& input, std::vector<std::uint32_t>* input_vertex) {
    TriangleMesh out;
    if (input_vertex) input_vertex->clear();
    std::vector<std::uint32_t> index(mesh.n_vertices(), UINT32_MAX);
    for (auto v : mesh.vertices())  // (skips deleted ones)
        if (!mesh.is_isolated(v)) {
            index[v.idx()] = std::uint32_t(out.positions.size());
            out.positions.push_back(input.input().positions[v.idx()]);
            if (input_vertex) input_vertex->push_back(std::uint32_t(v.idx()));
        }
    for (auto f : mesh.faces()) {
        std::array<std::uint32_t, 3> t{};
        int j = 0;
        // (OpenMesh's face circulator may start at any corner: rotate to keep the input's first
        // corner first when it survives, so an untouched face is the input's face exactly)
        for (auto u : mesh.fv_range(f)) t[j++] = index[u.idx()];
        const auto first = std::find(t.begin(), t.end(), index[input.input().triangles[f.idx()][0]]);
        if (first != t.end()) std::rotate(t.begin(), first, t.end());
        out.triangles.push_back(t);
    }
    if (!input.input().face_object.empty()) {
        out.object_names = input.input().object_names;
        for (auto f : mesh.faces()) out.face_object.push_back(input.input().face_object[f.idx()]);
    }
    return out;
}

}  // namespace

double DetailCriterion::target_at(const Camera& camera, const glm::dvec3& p) const {
    if (!map) return target_area_px;
    return target_area_px * map(camera.project(p), camera.depth(p));
}

ProgressiveMesh::ProgressiveMesh(const MeshTopology& topology, const BuildProgress& progress)
    : positions_(&topology.positions), triangles_(&topology.faces), face_object_(&topology.face_object),
      object_names_(&topology.object_names) {
    build(progress);
}

ProgressiveMesh::ProgressiveMesh(const MeshTopology& topology, std::vector<std::uint32_t> removed,
                                 std::vector<std::uint32_t> kept, double seconds)
    : positions_(&topology.positions), triangles_(&topology.faces), face_object_(&topology.face_object),
      object_names_(&topology.object_names), removed_(std::move(removed)), kept_(std::move(kept)),
      build_seconds_(seconds) {
    const std::size_t n = topology.vertex_count();
    const auto outside = [n](std::uint32_t v) { return v >= n; };
    if (removed_.size() != kept_.size() || std::any_of(removed_.begin(), removed_.end(), outside) ||
        std::any_of(kept_.begin(), kept_.end(), outside))
        throw std::invalid_argument("a progressive mesh's collapse records do not fit its mesh");
}

ProgressiveMesh::ProgressiveMesh(TriangleMesh mesh) : owned_(std::make_unique<const TriangleMesh>(std::move(mesh))) {
    positions_ = &owned_->positions;
    triangles_ = &owned_->triangles;
    face_object_ = &owned_->face_object;
    object_names_ = &owned_->object_names;
    build();
}

PmInput::operator TriangleMesh() const {
    TriangleMesh m;
    m.positions = positions;
    m.triangles = triangles;
    m.face_object = face_object;
    m.object_names = object_names;
    return m;
}

namespace {
// Passes the decimater's count of collapses on to a BuildProgress. What the callback throws (to
// stop the build) is kept and the decimater asked to abort, so that it never unwinds through
// OpenMesh; build() throws it again once the decimater has returned.
class ProgressObserver : public OpenMesh::Decimater::Observer {
public:
    ProgressObserver(const ProgressiveMesh::BuildProgress& progress, std::size_t most)
        : Observer(std::max<std::size_t>(most / 100, 1)), progress_(progress), most_(most) {}
    void notify(std::size_t step) override {
        if (stopped_) return;
        try {
            progress_(step, most_);
        } catch (...) {
            stopped_ = std::current_exception();
        }
    }
    bool abort() const override { return bool(stopped_); }
    void rethrow() const {
        if (stopped_) std::rethrow_exception(stopped_);
    }

private:
    const ProgressiveMesh::BuildProgress& progress_;
    std::size_t most_;
    std::exception_ptr stopped_;
};
}  // namespace

void ProgressiveMesh::build(const BuildProgress& progress) {
    const auto t0 = std::chrono::steady_clock::now();
    OMesh m;
    if (to_openmesh(*this, m)) {
        m.request_face_normals();
        m.update_face_normals();
        using Decimater = OpenMesh::Decimater::DecimaterT<OMesh>;
        Decimater decimater(m);
        OpenMesh::Decimater::ModQuadricT<OMesh>::Handle quadric;
        OpenMesh::Decimater::ModNormalFlippingT<OMesh>::Handle no_flip;
        OpenMesh::Decimater::ModProgMeshT<OMesh>::Handle record;
        decimater.add(quadric);
        decimater.add(no_flip);
        decimater.add(record);
        decimater.module(quadric).unset_max_err();
        const std::size_t most = most_collapses(positions_->size());
        ProgressObserver observer(progress, most);
        if (progress) decimater.set_observer(&observer);
        if (decimater.initialize()) {
            decimater.decimate();  // to the coarsest mesh the legality rules allow
            observer.rethrow();
            for (const auto& c : decimater.module(record).pmi()) {
                removed_.push_back(std::uint32_t(c.v0.idx()));
                kept_.push_back(std::uint32_t(c.v1.idx()));
            }
        }
    }
    removed_.shrink_to_fit();
    kept_.shrink_to_fit();
    build_seconds_ = seconds_since(t0);
    if (progress) progress(removed_.size(), removed_.size());  // (done: the decimater stops short of `most`)
}

TriangleMesh ProgressiveMesh::adapt(const Camera& camera, const DetailCriterion& criterion, AdaptStats* stats,
                                    std::vector<std::uint32_t>* input_vertex, std::size_t max_passes) const {
    const auto t0 = std::chrono::steady_clock::now();
    AdaptStats s;
    TriangleMesh out;
    if (!(criterion.target_area_px > 0.0) || removed_.empty()) {
        out = input();
        if (input_vertex) {
            input_vertex->resize(out.positions.size());
            for (std::size_t v = 0; v < out.positions.size(); ++v) (*input_vertex)[v] = std::uint32_t(v);
        }
    } else {
        Adapter adapter(input().positions, camera, criterion);
        to_openmesh(*this, adapter.mesh);  // (succeeded when the hierarchy was built)
        while (s.passes < max_passes) {
            ++s.passes;
            const std::size_t applied = adapter.pass(removed_, kept_);
            s.collapses += applied;
            if (applied == 0) break;
        }
        out = compact(adapter.mesh, *this, input_vertex);
    }
    s.triangles = out.triangles.size();
    s.vertices = out.positions.size();
    s.seconds = seconds_since(t0);
    if (stats) *stats = s;
    return out;
}

TriangleMesh triangle_mesh_of(const MeshTopology& topology) {
    TriangleMesh m;
    m.positions = topology.positions;
    m.triangles = topology.faces;
    m.face_object = topology.face_object;
    m.object_names = topology.object_names;
    return m;
}

std::vector<double> ring_image_areas(const TriangleMesh& mesh, const Camera& camera) {
    std::vector<double> sum(mesh.positions.size(), 0.0);
    std::vector<std::uint32_t> count(mesh.positions.size(), 0);
    for (const auto& t : mesh.triangles) {
        const double a = 0.5 * glm::length(twice_area_normal(mesh.positions[t[0]], mesh.positions[t[1]],
                                                             mesh.positions[t[2]]));
        for (std::uint32_t v : t) {
            sum[v] += a;
            ++count[v];
        }
    }
    std::vector<double> out(mesh.positions.size(), 0.0);
    for (std::size_t v = 0; v < out.size(); ++v)
        if (count[v]) out[v] = image_area(camera, sum[v] / count[v], camera.depth(mesh.positions[v]));
    return out;
}

}  // namespace inkline
