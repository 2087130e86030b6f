// Implicit smoothing of a level (multiscale_smoothing.hpp). The linear algebra is Eigen's (a
// dependency of CGAL): a sparse matrix and its simplicial LDL^T factorization.
#include "detail/multiscale_smoothing.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Sparse>
#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

namespace inkline {

struct LevelSmoother::Impl {
    Eigen::SparseMatrix<double> laplacian, squared;  // D - A (degree on the diagonal, -1 per edge); its square
    // Every level's matrix has the same pattern (W only changes the diagonal): its fill-reducing
    // ordering and symbolic factorization are computed once, per order.
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver[2];
    bool analysed[2] = {false, false};
};

LevelSmoother::LevelSmoother(const MeshTopology& mesh) : impl_(std::make_unique<Impl>()), mesh_(&mesh) {
    const auto n = Eigen::Index(mesh.vertex_count());
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(4 * mesh.edge_count() + mesh.vertex_count());
    std::vector<double> degree(mesh.vertex_count(), 0.0);
    for (const auto& e : mesh.edge_vertex) {
        t.emplace_back(Eigen::Index(e[0]), Eigen::Index(e[1]), -1.0);
        t.emplace_back(Eigen::Index(e[1]), Eigen::Index(e[0]), -1.0);
        degree[e[0]] += 1.0;
        degree[e[1]] += 1.0;
    }
    for (Eigen::Index v = 0; v < n; ++v) t.emplace_back(v, v, degree[std::size_t(v)]);
    impl_->laplacian.resize(n, n);
    impl_->laplacian.setFromTriplets(t.begin(), t.end());
}

LevelSmoother::~LevelSmoother() = default;

void LevelSmoother::smooth(double t, int order, const std::vector<double>& anchor, std::vector<glm::dvec3>& pos) {
    const Eigen::SparseMatrix<double>& L = impl_->laplacian;
    const auto n = L.rows();
    if (order == 2 && impl_->squared.size() == 0) impl_->squared = L * L;
    Eigen::SparseMatrix<double> a = t * (order == 2 ? impl_->squared : L);
    const auto weight = [&anchor](Eigen::Index v) { return anchor.empty() ? 1.0 : anchor[std::size_t(v)]; };
    for (Eigen::Index v = 0; v < n; ++v) a.coeffRef(v, v) += weight(v);
    auto& solver = impl_->solver[order == 2];
    if (!impl_->analysed[order == 2]) solver.analyzePattern(a);
    impl_->analysed[order == 2] = true;
    solver.factorize(a);
    Eigen::MatrixXd rhs(n, 3);
    for (Eigen::Index v = 0; v < n; ++v)
        for (int c = 0; c < 3; ++c) rhs(v, c) = weight(v) * pos[std::size_t(v)][c];
    const Eigen::MatrixXd x = solver.solve(rhs);
    for (Eigen::Index v = 0; v < n; ++v) pos[std::size_t(v)] = {x(v, 0), x(v, 1), x(v, 2)};
}

std::vector<double> LevelSmoother::thickness(const std::vector<glm::dvec3>& pos) const {
    const MeshTopology& mesh = *mesh_;
    const std::size_t n = pos.size();
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : pos) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const glm::dvec3 centre = 0.5 * (lo + hi);  // (single precision: coordinates about the centre)
    const double size = glm::length(hi - lo);
    std::vector<glm::dvec3> normal(n, glm::dvec3(0.0));
    for (const auto& f : mesh.faces) {
        const glm::dvec3 a = glm::cross(pos[f[1]] - pos[f[0]], pos[f[2]] - pos[f[0]]);
        for (std::uint32_t v : f) normal[v] += a;
    }
    RTCDevice device = rtcNewDevice(nullptr);
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), n));
    for (std::size_t v = 0; v < n; ++v)
        for (int k = 0; k < 3; ++k) vb[3 * v + k] = float(pos[v][k] - centre[k]);
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.face_count()));
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        for (int k = 0; k < 3; ++k) ib[3 * f + k] = mesh.faces[f][k];
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    std::vector<double> out(n, size);
    for (std::size_t v = 0; v < n; ++v) {
        const double length = glm::length(normal[v]);
        if (!(length > 0.0)) continue;
        const glm::dvec3 d = -normal[v] / length, o = pos[v] - centre;
        RTCRayHit rh{};
        rh.ray.org_x = float(o.x), rh.ray.org_y = float(o.y), rh.ray.org_z = float(o.z);
        rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
        rh.ray.tnear = float(1e-4 * size);
        rh.ray.tfar = float(size);
        rh.ray.mask = 0xffffffffu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &rh);
        if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) out[v] = double(rh.ray.tfar);
    }
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    // One ray is noisy: the ring's mean, twice.
    std::vector<double> sum(n), count(n);
    for (int pass = 0; pass < 2; ++pass) {
        std::fill(sum.begin(), sum.end(), 0.0);
        std::fill(count.begin(), count.end(), 0.0);
        for (const auto& e : mesh.edge_vertex) {
            sum[e[0]] += out[e[1]], count[e[0]] += 1.0;
            sum[e[1]] += out[e[0]], count[e[1]] += 1.0;
        }
        for (std::size_t v = 0; v < n; ++v) out[v] = (out[v] + sum[v]) / (1.0 + count[v]);
    }
    return out;
}

}  // namespace inkline
