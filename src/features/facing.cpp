#include "features/facing.hpp"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/predicates.hpp"

namespace inkline {

// The view's bound. With E = eye - origin, R = facing_radius, the trusted unit normal n' within
// 2^-21 of the exact unit normal n* per component, d' within 2^-20 R of dot(n*, a - origin):
//   |dot(n', float(E)) - dot(n*, E)| <= 2^-21 |E|_1 + (2^-24 + eps)|E|_1 <= 2^-20 |E|_1,
//   float evaluation (3 products, 3 sums) <= 5 * 2^-24 (|E|_1 + R) < 2^-21 (|E|_1 + R),
// so the float distance errs by less than 2^-19 (|E|_1 + R); the bound takes twice that, plus an
// absolute floor for the subnormal range. Orthographic: E = -forward and no offset term (w = 0).
// Outside the bound the float sign is the exact sign; inside, the exact predicate decides.
void FacingFilter::bind(const MeshTopology& mesh, const Camera& camera) {
    const bool ortho = camera.is_ortho();
    const glm::dvec3 e = ortho ? -camera.forward() : camera.eye() - mesh.facing_origin;
    ex = float(e.x);
    ey = float(e.y);
    ez = float(e.z);
    w = ortho ? 0.0f : 1.0f;
    const double l1 = std::abs(e.x) + std::abs(e.y) + std::abs(e.z);
    bound = float(0x1p-18 * (l1 + (ortho ? 0.0 : mesh.facing_radius)) + 1e-36);
    if (!std::isfinite(ex) || !std::isfinite(ey) || !std::isfinite(ez) || !std::isfinite(bound))
        bound = INFINITY;  // out of float range: every face goes to the exact test
}

void FaceFacing::bind(const MeshTopology& mesh, const Camera& camera) {
    mesh_ = &mesh;
    camera_ = camera;
    exact_ = 0;
    filter_.bind(mesh, camera);
}

void FaceFacing::begin_lazy(const MeshTopology& mesh, const Camera& camera) {
    const std::size_t nf = mesh.face_count();
    if (full_ || state_.size() != nf + 1 || mesh_ != &mesh) {
        state_.assign(nf + 1, kUnknown);
        state_[nf] = kSentinel;
    } else {
        for (std::uint32_t f : touched_) state_[f] = kUnknown;
    }
    touched_.clear();
    full_ = false;
    bind(mesh, camera);
}

void FaceFacing::begin_full(const MeshTopology& mesh, const Camera& camera) {
    bind(mesh, camera);
    const std::size_t nf = mesh.face_count();
    state_.resize(nf + 1);
    state_[nf] = kSentinel;
    touched_.clear();
    full_ = true;
    const MeshTopology::FacingPlane* __restrict p = mesh.facing.data();
    std::uint8_t* __restrict out = state_.data();
    const float ex = filter_.ex, ey = filter_.ey, ez = filter_.ez, w = filter_.w, b = filter_.bound;
    // Front 2, back 0, undecided (or NaN plane) 1: resolved exactly when first read.
    for (std::size_t f = 0; f < nf; ++f) {
        const float det = p[f].nx * ex + p[f].ny * ey + p[f].nz * ez - w * p[f].d;
        out[f] = std::uint8_t(std::uint8_t(det > b) + std::uint8_t(!(det < -b)));
    }
}

float FaceFacing::signed_distance(std::uint32_t f) const { return filter_.signed_distance(mesh_->facing[f]); }

std::uint8_t FaceFacing::filter(std::uint32_t f) const { return filter_(mesh_->facing[f]); }

std::uint8_t FaceFacing::resolve(std::uint32_t f) const {
    std::uint8_t s = full_ ? kUnknown : filter(f);
    if (s == kUnknown) {
        const MeshTopology& m = *mesh_;
        const auto& v = m.faces[f];
        ++exact_;
        s = orient_eye(camera_, m.positions[v[0]], m.positions[v[1]], m.positions[v[2]]) > 0 ? kFront : kBack;
    }
    state_[f] = s;
    if (!full_) touched_.push_back(f);
    return s;
}

std::vector<std::uint8_t> FaceFacing::all() const {
    std::vector<std::uint8_t> out(size());
    for (std::uint32_t f = 0; f < out.size(); ++f) out[f] = (*this)[f];
    return out;
}

}  // namespace inkline
