// Per-vertex curvature and its derivative: Rusinkiewicz, "Estimating curvatures and their derivatives on
// triangle meshes" (3DPVT 2004). Conventions follow the author's own code (trimesh2), which the
// suggestive contours we are compared with are drawn from: vertex normals weighted as in Max (1999),
// Voronoi corner areas as in Meyer et al. (2003), per-face least squares in a frame of the face, each face's
// tensor rotated into each corner's vertex frame and averaged by corner area. Differences from it, all in
// cases it leaves undefined or where we state a different convention: signed order k1 >= k2 (trimesh2
// orders by magnitude), averages normalized by the corner areas of the faces whose fit succeeded
// (trimesh2 divides by the whole point area), degenerate faces and vertices with fewer than two usable
// faces marked instead of giving NaN or an unweighted guess, and doubles throughout (trimesh2: floats).
#include "curvature/curvature.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace inkline {

namespace {

using glm::dvec3;

// A face is used for fits and areas only when twice its area exceeds this fraction of its longest
// squared edge (roughly: its smallest height above 1e-10 of its longest edge). Below it the cross
// product's rounding (about 1e-16 of the squared edge) leaves the face normal's direction
// meaningless, and a frame built on it would be NaN.
constexpr double kMinRelativeArea = 1e-10;

// Solves the symmetric positive definite tridiagonal system (diagonal `diag`, off-diagonal `off`) for
// the right-hand side x, in place, by LDL^T (the normal equations of both fits are tridiagonal in
// the order of the unknowns used here). Fails when a pivot drops below 1e-12 of its diagonal entry:
// the fit is then ill-conditioned (the face's edges do not span its plane) and is left out.
template <int N>
bool solve_tridiagonal(const double (&diag)[N], const double (&off)[N - 1], double (&x)[N]) {
    double d[N], l[N - 1];
    d[0] = diag[0];
    if (!(d[0] > 1e-12 * diag[0])) return false;
    for (int k = 1; k < N; ++k) {
        l[k - 1] = off[k - 1] / d[k - 1];
        d[k] = diag[k] - l[k - 1] * off[k - 1];
        if (!(d[k] > 1e-12 * diag[k])) return false;
    }
    for (int k = 1; k < N; ++k) x[k] -= l[k - 1] * x[k - 1];
    x[N - 1] /= d[N - 1];
    for (int k = N - 2; k >= 0; --k) x[k] = x[k] / d[k] - l[k] * x[k + 1];
    return true;
}

// Turns the orthonormal tangent pair (u, v) by the least rotation that takes its normal cross(u, v) to
// the unit vector new_n, so that a tensor given in one tangent plane can be read in another (nearly
// parallel) one. Opposite normals: a half turn about the normal (any turn would do).
void rotate_frame(dvec3& u, dvec3& v, const dvec3& new_n) {
    const dvec3 old_n = glm::cross(u, v);
    const double ndot = glm::dot(old_n, new_n);
    if (ndot <= -1.0 + 1e-12) {
        u = -u;
        v = -v;
        return;
    }
    // Subtracting the component along perp_old and adding it along the matching direction in the new
    // plane, with the normalizations folded into one factor.
    const dvec3 perp_old = new_n - ndot * old_n;
    const dvec3 dperp = (old_n + new_n) / (1.0 + ndot);
    u -= dperp * glm::dot(u, perp_old);
    v -= dperp * glm::dot(v, perp_old);
}

// How a vertex frame (d1, d2) and a face frame (t, b) meet: the cosines of d1 and d2, turned into the
// face's plane, against t and b. Turning the face frame into the vertex's plane instead gives the
// transposed cosines (the least rotation one way is the inverse of the least rotation the other way),
// so one FrameChange serves both directions.
struct FrameChange {
    double u1, v1, u2, v2;  // d1.t, d1.b, d2.t, d2.b (d1, d2 turned)
    FrameChange transposed() const { return {u1, u2, v1, v2}; }
};
FrameChange frame_change(const dvec3& t, const dvec3& b, const dvec3& face_n, dvec3 d1, dvec3 d2) {
    rotate_frame(d1, d2, face_n);
    return {glm::dot(d1, t), glm::dot(d1, b), glm::dot(d2, t), glm::dot(d2, b)};
}

// A symmetric 2-tensor {uu, uv, vv} in the old frame read in the new one; `c` gives the new frame's
// axes in the old one (u1, v1: first axis; u2, v2: second).
std::array<double, 3> project_tensor(const FrameChange& c, const std::array<double, 3>& k) {
    const auto [u1, v1, u2, v2] = c;
    return {k[0] * u1 * u1 + k[1] * (2.0 * u1 * v1) + k[2] * v1 * v1,
            k[0] * u1 * u2 + k[1] * (u1 * v2 + u2 * v1) + k[2] * v1 * v2,
            k[0] * u2 * u2 + k[1] * (2.0 * u2 * v2) + k[2] * v2 * v2};
}

// A symmetric 3-tensor {uuu, uuv, uvv, vvv} likewise.
std::array<double, 4> project_cubic(const FrameChange& fc, const std::array<double, 4>& c) {
    const auto [u1, v1, u2, v2] = fc;
    return {c[0] * u1 * u1 * u1 + c[1] * 3.0 * u1 * u1 * v1 + c[2] * 3.0 * u1 * v1 * v1 + c[3] * v1 * v1 * v1,
            c[0] * u1 * u1 * u2 + c[1] * (u1 * u1 * v2 + 2.0 * u2 * u1 * v1) +
                c[2] * (u2 * v1 * v1 + 2.0 * u1 * v1 * v2) + c[3] * v1 * v1 * v2,
            c[0] * u1 * u2 * u2 + c[1] * (u2 * u2 * v1 + 2.0 * u1 * u2 * v2) +
                c[2] * (u1 * v2 * v2 + 2.0 * u2 * v2 * v1) + c[3] * v1 * v2 * v2,
            c[0] * u2 * u2 * u2 + c[1] * 3.0 * u2 * u2 * v2 + c[2] * 3.0 * u2 * v2 * v2 + c[3] * v2 * v2 * v2};
}

// A face's edges e[j] (opposite corner j: from corner j+1 to corner j+2, as e[j] = p[j+2] - p[j+1]) and
// its frame: t along e[0], n the unit normal, b = cross(n, t).
struct FaceGeometry {
    dvec3 e[3];
    double l2[3];
    dvec3 t, b, n;
    double area = 0.0;
    bool usable = false;  // not degenerate (kMinRelativeArea): frame and corner areas defined
};

FaceGeometry face_geometry(const MeshTopology& mesh, std::uint32_t f) {
    const auto& v = mesh.faces[f];
    const dvec3 p0 = mesh.positions[v[0]], p1 = mesh.positions[v[1]], p2 = mesh.positions[v[2]];
    FaceGeometry g;
    g.e[0] = p2 - p1;
    g.e[1] = p0 - p2;
    g.e[2] = p1 - p0;
    for (int j = 0; j < 3; ++j) g.l2[j] = glm::dot(g.e[j], g.e[j]);
    const dvec3 n = glm::cross(g.e[0], g.e[1]);
    const double twice_area = std::sqrt(glm::dot(n, n));
    g.area = 0.5 * twice_area;
    g.usable = twice_area > kMinRelativeArea * std::max({g.l2[0], g.l2[1], g.l2[2]}) && std::isfinite(twice_area);
    if (g.usable) {
        g.n = n / twice_area;
        g.t = g.e[0] / std::sqrt(g.l2[0]);
        g.b = glm::cross(g.n, g.t);
    }
    return g;
}

// What the fits read of a usable face: its frame and its edges in it (e[j] = u[j] t + v[j] b).
struct FaceFrame {
    dvec3 t, b, n;
    double u[3], v[3];
};

// Voronoi areas of a face's corners (Meyer et al. 2003): the part of the face nearer to each corner
// than to the others, or, in an obtuse face, half the face for the obtuse corner and a quarter each
// for the others (the mixed area that keeps every part positive).
std::array<double, 3> corner_areas(const FaceGeometry& g) {
    const double* l2 = g.l2;
    // Barycentric weights of the circumcentre; one <= 0: the face is obtuse (or right) at that corner.
    const double bcw[3] = {l2[0] * (l2[1] + l2[2] - l2[0]), l2[1] * (l2[2] + l2[0] - l2[1]),
                           l2[2] * (l2[0] + l2[1] - l2[2])};
    const double A = g.area;
    std::array<double, 3> c{};
    for (int j = 0; j < 3; ++j) {
        if (bcw[j] > 0.0) continue;
        const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        c[j1] = -0.25 * l2[j2] * A / glm::dot(g.e[j], g.e[j2]);
        c[j2] = -0.25 * l2[j1] * A / glm::dot(g.e[j], g.e[j1]);
        c[j1] = std::clamp(c[j1], 0.0, A);
        c[j2] = std::clamp(c[j2], 0.0, A - c[j1]);
        c[j] = A - c[j1] - c[j2];
        return c;
    }
    const double scale = 0.5 * A / (bcw[0] + bcw[1] + bcw[2]);
    for (int j = 0; j < 3; ++j) c[j] = scale * (bcw[(j + 1) % 3] + bcw[(j + 2) % 3]);
    return c;
}

// The estimator's state, one member function per phase (in the order estimate_curvature calls them).
struct Estimator {
    const MeshTopology& mesh;
    std::size_t nv, nf;
    std::vector<dvec3> normal;                  // per vertex
    std::vector<dvec3> dir_u;                   // per vertex: a unit tangent; after diagonalize(), dir1
    std::vector<FaceFrame> frame;               // per face (valid where face_usable)
    std::vector<std::uint8_t> face_usable;      // per face
    std::vector<std::array<double, 3>> corner;  // per face: Voronoi corner areas
    std::vector<double> point_area;             // per vertex: sum of its corner areas
    std::vector<std::array<double, 3>> tensor;  // per vertex: second fundamental form in (dir_u, n x dir_u)
    std::vector<std::array<double, 4>> dcurv;   // per vertex: C in (dir1, dir2)
    std::vector<double> weight;                 // per vertex: corner areas of the faces whose fit counted
    std::vector<std::uint8_t> usable_faces;     // per vertex: usable faces around it, saturating at 2
    std::vector<double> k1, k2;
    std::vector<std::uint8_t> valid;            // per vertex: curvature estimated (mark_valid)

    explicit Estimator(const MeshTopology& m) : mesh(m), nv(m.vertex_count()), nf(m.face_count()) {}

    // Vertex normals weighted as in Max (1999): each face's normal scaled by sin(angle) / (product of
    // the corner's two edge lengths), i.e. cross(a, b) / (|a|^2 |b|^2); the corner and point areas;
    // the frames of the faces.
    void faces_pass() {
        normal.assign(nv, dvec3(0.0));
        corner.assign(nf, {0.0, 0.0, 0.0});
        frame.resize(nf);
        face_usable.assign(nf, 0);
        point_area.assign(nv, 0.0);
        usable_faces.assign(nv, 0);
        for (std::uint32_t f = 0; f < nf; ++f) {
            const auto& v = mesh.faces[f];
            const FaceGeometry g = face_geometry(mesh, f);
            if (g.l2[0] > 0.0 && g.l2[1] > 0.0 && g.l2[2] > 0.0) {
                const dvec3 n2 = glm::cross(g.e[0], g.e[1]);  // twice the area times the unit normal
                for (int j = 0; j < 3; ++j) normal[v[j]] += n2 / (g.l2[(j + 1) % 3] * g.l2[(j + 2) % 3]);
            }
            if (!g.usable) continue;
            face_usable[f] = 1;
            FaceFrame& fr = frame[f];
            fr.t = g.t, fr.b = g.b, fr.n = g.n;
            for (int j = 0; j < 3; ++j) fr.u[j] = glm::dot(g.e[j], g.t), fr.v[j] = glm::dot(g.e[j], g.b);
            corner[f] = corner_areas(g);
            for (int j = 0; j < 3; ++j) {
                point_area[v[j]] += corner[f][j];
                usable_faces[v[j]] = std::uint8_t(std::min(2, usable_faces[v[j]] + 1));
            }
        }
    }

    // Unit normals and a tangent frame per vertex (any one: the result does not depend on it).
    void vertex_frames() {
        dir_u.assign(nv, dvec3(0.0));
        for (std::size_t i = 0; i < nv; ++i) {
            const double len = std::sqrt(glm::dot(normal[i], normal[i]));
            if (!(len > 0.0) || !std::isfinite(len)) {
                normal[i] = dvec3(0.0);
                continue;
            }
            const dvec3 n = normal[i] / len;
            normal[i] = n;
            // Duff et al. (2017): an orthonormal basis from a unit vector without a branch on near-axes.
            const double sign = std::copysign(1.0, n.z), a = -1.0 / (sign + n.z), b = n.x * n.y * a;
            dir_u[i] = glm::normalize(dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x));
        }
    }

    bool vertex_usable(std::uint32_t i) const { return usable_faces[i] >= 2 && normal[i] != dvec3(0.0); }

    FrameChange corner_frame(const FaceFrame& fr, std::uint32_t vj) const {
        return frame_change(fr.t, fr.b, fr.n, dir_u[vj], glm::cross(normal[vj], dir_u[vj]));
    }

    // Per face: the second fundamental form that best maps the three edges to the normal differences
    // along them (least squares in the face frame), then pushed to the corners' frames.
    void fit_curvature() {
        tensor.assign(nv, {0.0, 0.0, 0.0});
        weight.assign(nv, 0.0);
        for (std::uint32_t f = 0; f < nf; ++f) {
            if (!face_usable[f]) continue;
            const auto& v = mesh.faces[f];
            const FaceFrame& fr = frame[f];
            double m[3] = {0.0, 0.0, 0.0};
            double uu = 0.0, uv = 0.0, vv = 0.0;
            for (int j = 0; j < 3; ++j) {
                const double u = fr.u[j], w = fr.v[j];
                uu += u * u, uv += u * w, vv += w * w;
                const dvec3 dn = normal[v[(j + 2) % 3]] - normal[v[(j + 1) % 3]];
                const double dnu = glm::dot(dn, fr.t), dnv = glm::dot(dn, fr.b);
                m[0] += dnu * u;
                m[1] += dnu * w + dnv * u;
                m[2] += dnv * w;
            }
            // Unknowns (II_tt, II_tb, II_bb): a tridiagonal system.
            if (!solve_tridiagonal<3>({uu, uu + vv, vv}, {uv, uv}, m)) continue;
            for (int j = 0; j < 3; ++j) {
                const std::uint32_t vj = v[j];
                if (!vertex_usable(vj)) continue;
                const auto c = project_tensor(corner_frame(fr, vj), {m[0], m[1], m[2]});
                const double wt = corner[f][j];
                for (int k = 0; k < 3; ++k) tensor[vj][k] += wt * c[k];
                weight[vj] += wt;
            }
        }
    }

    // Principal curvatures (signed, k1 >= k2) and dir1 from each vertex's averaged tensor.
    void diagonalize() {
        k1.assign(nv, 0.0);
        k2.assign(nv, 0.0);
        for (std::size_t i = 0; i < nv; ++i) {
            if (!(weight[i] > 0.0)) continue;
            const double ku = tensor[i][0] / weight[i], kuv = tensor[i][1] / weight[i], kv = tensor[i][2] / weight[i];
            const double mean = 0.5 * (ku + kv), half = 0.5 * (ku - kv);
            const double delta = std::sqrt(half * half + kuv * kuv);
            k1[i] = mean + delta;
            k2[i] = mean - delta;
            // Eigenvector of k1: the better conditioned of the two rows' null vectors.
            const double x = ku >= kv ? k1[i] - kv : kuv, y = ku >= kv ? kuv : k1[i] - ku;
            const double len = std::sqrt(x * x + y * y);
            if (len > 0.0) {
                const dvec3 pv = glm::cross(normal[i], dir_u[i]);
                dir_u[i] = glm::normalize((x / len) * dir_u[i] + (y / len) * pv);
            }
        }
    }

    // Curvature estimated here: a usable vertex that some face's fit reached, with finite values (read
    // before fit_dcurv reuses `weight`).
    void mark_valid() {
        valid.assign(nv, 0);
        for (std::size_t i = 0; i < nv; ++i)
            valid[i] = vertex_usable(std::uint32_t(i)) && weight[i] > 0.0 && std::isfinite(k1[i]) &&
                       std::isfinite(k2[i]);
    }

    // Per face: the derivative tensor C that best maps the edges to the differences of the corners'
    // second fundamental forms (read in the face frame), then pushed to the corners' principal frames.
    void fit_dcurv() {
        dcurv.assign(nv, {0.0, 0.0, 0.0, 0.0});
        std::fill(weight.begin(), weight.end(), 0.0);
        for (std::uint32_t f = 0; f < nf; ++f) {
            const auto& v = mesh.faces[f];
            if (!face_usable[f] || !valid[v[0]] || !valid[v[1]] || !valid[v[2]]) continue;
            const FaceFrame& fr = frame[f];
            FrameChange fc[3];
            std::array<double, 3> fcurv[3];
            for (int j = 0; j < 3; ++j) {
                fc[j] = corner_frame(fr, v[j]);
                fcurv[j] = project_tensor(fc[j].transposed(), {k1[v[j]], 0.0, k2[v[j]]});
            }
            double m[4] = {0.0, 0.0, 0.0, 0.0};
            double uu = 0.0, uv = 0.0, vv = 0.0;
            for (int j = 0; j < 3; ++j) {
                const auto& a = fcurv[(j + 2) % 3];
                const auto& b = fcurv[(j + 1) % 3];
                const double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
                const double u = fr.u[j], w = fr.v[j];
                uu += u * u, uv += u * w, vv += w * w;
                // The mixed component appears twice in the tensor, so its residual counts twice.
                m[0] += u * d[0];
                m[1] += w * d[0] + 2.0 * u * d[1];
                m[2] += 2.0 * w * d[1] + u * d[2];
                m[3] += w * d[2];
            }
            // Unknowns (C_ttt, C_ttb, C_tbb, C_bbb): a tridiagonal system.
            if (!solve_tridiagonal<4>({uu, 2.0 * uu + vv, uu + 2.0 * vv, vv}, {uv, 2.0 * uv, uv}, m)) continue;
            for (int j = 0; j < 3; ++j) {
                const std::uint32_t vj = v[j];
                const auto c = project_cubic(fc[j], {m[0], m[1], m[2], m[3]});
                const double wt = corner[f][j];
                for (int k = 0; k < 4; ++k) dcurv[vj][k] += wt * c[k];
                weight[vj] += wt;
            }
        }
    }

    void write(CurvatureField& out) const;
};

void Estimator::write(CurvatureField& out) const {
    out.normal.resize(nv);
    out.dir1.resize(nv);
    out.k1.resize(nv);
    out.k2.resize(nv);
    out.dcurv.resize(nv);
    out.point_area.resize(nv);
    out.valid.resize(nv);
    out.invalid_vertices = 0;
    for (std::size_t i = 0; i < nv; ++i) {
        out.normal[i] = glm::vec3(normal[i]);
        out.dir1[i] = glm::vec3(dir_u[i]);
        out.point_area[i] = float(point_area[i]);
        std::array<float, 4> c{0.f, 0.f, 0.f, 0.f};
        bool ok = valid[i] != 0;
        if (ok && weight[i] > 0.0)
            for (int k = 0; k < 4; ++k) c[k] = float(dcurv[i][k] / weight[i]);
        for (float x : c) ok = ok && std::isfinite(x);
        ok = ok && std::isfinite(float(k1[i])) && std::isfinite(float(k2[i]));
        out.valid[i] = ok;
        out.k1[i] = ok ? float(k1[i]) : 0.f;
        out.k2[i] = ok ? float(k2[i]) : 0.f;
        out.dcurv[i] = ok ? c : std::array<float, 4>{0.f, 0.f, 0.f, 0.f};
        out.invalid_vertices += !ok;
    }
}

// Median edge length, exact: the upper median of the squared lengths of all edges, its square root.
// trimesh2 (TriMesh::feature_size) takes the same upper median of about 999 edges of faces drawn at
// random, so its value scatters around this one by a few percent; each edge counts once here, where
// sampling faces counts a border edge half as often as an inner one (the same on closed meshes).
double median_edge_length(const MeshTopology& mesh) {
    const std::size_t ne = mesh.edge_count();
    if (ne == 0) return 0.0;
    std::vector<double> l2(ne);
    for (std::size_t e = 0; e < ne; ++e) {
        const dvec3 d = mesh.positions[mesh.edge_vertex[e][1]] - mesh.positions[mesh.edge_vertex[e][0]];
        l2[e] = glm::dot(d, d);
    }
    std::nth_element(l2.begin(), l2.begin() + ne / 2, l2.end());
    return std::sqrt(l2[ne / 2]);
}

}  // namespace

CurvatureField estimate_curvature(const MeshTopology& mesh) {
    Estimator est(mesh);
    est.faces_pass();
    est.vertex_frames();
    est.fit_curvature();
    est.diagonalize();
    est.mark_valid();
    est.fit_dcurv();
    CurvatureField field;
    est.write(field);
    field.feature_size = median_edge_length(mesh);
    return field;
}

}  // namespace inkline
