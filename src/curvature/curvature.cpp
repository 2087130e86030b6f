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
#include "curvature/incremental_curvature.hpp"
#include "core/sorted_ids.hpp"

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

dvec3 tangent_of(const dvec3& n);

// Max's (1999) weight of a face's normal at its corner j: cross(a, b) / (|a|^2 |b|^2) for the corner's
// two edges a, b (n2: the face's cross(e[0], e[1])); only when no edge is of zero length.
dvec3 normal_term(const FaceGeometry& g, const dvec3& n2, int j) { return n2 / (g.l2[(j + 1) % 3] * g.l2[(j + 2) % 3]); }
bool has_normal_term(const FaceGeometry& g) { return g.l2[0] > 0.0 && g.l2[1] > 0.0 && g.l2[2] > 0.0; }

FaceFrame face_frame(const FaceGeometry& g) {
    FaceFrame fr;
    fr.t = g.t, fr.b = g.b, fr.n = g.n;
    for (int j = 0; j < 3; ++j) fr.u[j] = glm::dot(g.e[j], g.t), fr.v[j] = glm::dot(g.e[j], g.b);
    return fr;
}

// A vertex's unit normal from its summed one, and a tangent (any one: the result does not depend on
// it); both zero when the sum has no direction.
void vertex_frame(dvec3& normal, dvec3& dir_u) {
    const double len = std::sqrt(glm::dot(normal, normal));
    if (!(len > 0.0) || !std::isfinite(len)) {
        normal = dvec3(0.0);
        return;
    }
    normal = normal / len;
    dir_u = tangent_of(normal);
}

// The tangent vertex_frame gives a unit normal (zero for a zero normal).
dvec3 tangent_of(const dvec3& n) {
    if (n == dvec3(0.0)) return dvec3(0.0);
    // Duff et al. (2017): an orthonormal basis from a unit vector without a branch on near-axes.
    const double sign = std::copysign(1.0, n.z), a = -1.0 / (sign + n.z), b = n.x * n.y * a;
    return glm::normalize(dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x));
}

// The second fundamental form that best maps a face's three edges to the normal differences along
// them (least squares in the face frame; corner normals n[j]); false when ill-conditioned.
bool fit_face_curvature(const FaceFrame& fr, const dvec3* const (&n)[3], double (&m)[3]) {
    m[0] = m[1] = m[2] = 0.0;
    double uu = 0.0, uv = 0.0, vv = 0.0;
    for (int j = 0; j < 3; ++j) {
        const double u = fr.u[j], w = fr.v[j];
        uu += u * u, uv += u * w, vv += w * w;
        const dvec3 dn = *n[(j + 2) % 3] - *n[(j + 1) % 3];
        const double dnu = glm::dot(dn, fr.t), dnv = glm::dot(dn, fr.b);
        m[0] += dnu * u;
        m[1] += dnu * w + dnv * u;
        m[2] += dnv * w;
    }
    // Unknowns (II_tt, II_tb, II_bb): a tridiagonal system.
    return solve_tridiagonal<3>({uu, uu + vv, vv}, {uv, uv}, m);
}

FrameChange corner_frame(const FaceFrame& fr, const dvec3& normal, const dvec3& dir_u) {
    return frame_change(fr.t, fr.b, fr.n, dir_u, glm::cross(normal, dir_u));
}

// Principal curvatures (signed, k1 >= k2) and dir1 (into dir_u) from a vertex's summed tensor.
void diagonalize_vertex(const std::array<double, 3>& tensor, double weight, const dvec3& normal, dvec3& dir_u,
                        double& k1, double& k2) {
    k1 = k2 = 0.0;
    if (!(weight > 0.0)) return;
    const double ku = tensor[0] / weight, kuv = tensor[1] / weight, kv = tensor[2] / weight;
    const double mean = 0.5 * (ku + kv), half = 0.5 * (ku - kv);
    const double delta = std::sqrt(half * half + kuv * kuv);
    k1 = mean + delta;
    k2 = mean - delta;
    // Eigenvector of k1: the better conditioned of the two rows' null vectors.
    const double x = ku >= kv ? k1 - kv : kuv, y = ku >= kv ? kuv : k1 - ku;
    const double len = std::sqrt(x * x + y * y);
    if (len > 0.0) {
        const dvec3 pv = glm::cross(normal, dir_u);
        dir_u = glm::normalize((x / len) * dir_u + (y / len) * pv);
    }
}

// The derivative tensor C that best maps a face's edges to the differences of its corners' second
// fundamental forms (read in the face frame; fc[j]: corner j's principal frame against the face's,
// k1[j], k2[j] its curvatures); false when ill-conditioned.
bool fit_face_dcurv(const FaceFrame& fr, const FrameChange (&fc)[3], const double (&k1)[3], const double (&k2)[3],
                    double (&m)[4]) {
    std::array<double, 3> fcurv[3];
    for (int j = 0; j < 3; ++j) fcurv[j] = project_tensor(fc[j].transposed(), {k1[j], 0.0, k2[j]});
    m[0] = m[1] = m[2] = m[3] = 0.0;
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
    return solve_tridiagonal<4>({uu, 2.0 * uu + vv, uu + 2.0 * vv, vv}, {uv, 2.0 * uv, uv}, m);
}

// Curvature estimated at a vertex: usable (two usable faces, a normal), some face's fit reached it,
// finite values.
bool vertex_valid(std::uint8_t usable_faces, const dvec3& normal, double weight, double k1, double k2) {
    return usable_faces >= 2 && normal != dvec3(0.0) && weight > 0.0 && std::isfinite(k1) && std::isfinite(k2);
}

// One vertex of the output field from the estimator's doubles (dcurv: summed, over `weight`).
void write_vertex(CurvatureField& out, std::size_t i, const dvec3& normal, const dvec3& dir1, double point_area,
                  bool valid, double k1, double k2, const std::array<double, 4>& dcurv, double weight) {
    out.normal[i] = glm::vec3(normal);
    out.dir1[i] = glm::vec3(dir1);
    out.point_area[i] = float(point_area);
    std::array<float, 4> c{0.f, 0.f, 0.f, 0.f};
    bool ok = valid;
    if (ok && weight > 0.0)
        for (int k = 0; k < 4; ++k) c[k] = float(dcurv[k] / weight);
    for (float x : c) ok = ok && std::isfinite(x);
    ok = ok && std::isfinite(float(k1)) && std::isfinite(float(k2));
    out.valid[i] = ok;
    out.k1[i] = ok ? float(k1) : 0.f;
    out.k2[i] = ok ? float(k2) : 0.f;
    out.dcurv[i] = ok ? c : std::array<float, 4>{0.f, 0.f, 0.f, 0.f};
}

void resize_field(CurvatureField& out, std::size_t nv) {
    out.normal.resize(nv);
    out.dir1.resize(nv);
    out.k1.resize(nv);
    out.k2.resize(nv);
    out.dcurv.resize(nv);
    out.point_area.resize(nv);
    out.valid.resize(nv);
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

    // Every phase in order: the whole estimate.
    void run_all() {
        faces_pass();
        vertex_frames();
        fit_curvature();
        diagonalize();
        mark_valid();
        fit_dcurv();
    }

    // Vertex normals weighted as in Max (1999); the corner and point areas; the frames of the faces.
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
            if (has_normal_term(g)) {
                const dvec3 n2 = glm::cross(g.e[0], g.e[1]);  // twice the area times the unit normal
                for (int j = 0; j < 3; ++j) normal[v[j]] += normal_term(g, n2, j);
            }
            if (!g.usable) continue;
            face_usable[f] = 1;
            frame[f] = face_frame(g);
            corner[f] = corner_areas(g);
            for (int j = 0; j < 3; ++j) {
                point_area[v[j]] += corner[f][j];
                usable_faces[v[j]] = std::uint8_t(std::min(2, usable_faces[v[j]] + 1));
            }
        }
    }

    // Unit normals and a tangent frame per vertex.
    void vertex_frames() {
        dir_u.assign(nv, dvec3(0.0));
        for (std::size_t i = 0; i < nv; ++i) vertex_frame(normal[i], dir_u[i]);
    }

    bool vertex_usable(std::uint32_t i) const { return usable_faces[i] >= 2 && normal[i] != dvec3(0.0); }

    // Per face: the second fundamental form fit, then pushed to the corners' frames.
    void fit_curvature() {
        tensor.assign(nv, {0.0, 0.0, 0.0});
        weight.assign(nv, 0.0);
        for (std::uint32_t f = 0; f < nf; ++f) {
            if (!face_usable[f]) continue;
            const auto& v = mesh.faces[f];
            const FaceFrame& fr = frame[f];
            double m[3];
            if (!fit_face_curvature(fr, {&normal[v[0]], &normal[v[1]], &normal[v[2]]}, m)) continue;
            for (int j = 0; j < 3; ++j) {
                const std::uint32_t vj = v[j];
                if (!vertex_usable(vj)) continue;
                const auto c = project_tensor(corner_frame(fr, normal[vj], dir_u[vj]), {m[0], m[1], m[2]});
                const double wt = corner[f][j];
                for (int k = 0; k < 3; ++k) tensor[vj][k] += wt * c[k];
                weight[vj] += wt;
            }
        }
    }

    void diagonalize() {
        k1.assign(nv, 0.0);
        k2.assign(nv, 0.0);
        for (std::size_t i = 0; i < nv; ++i) diagonalize_vertex(tensor[i], weight[i], normal[i], dir_u[i], k1[i], k2[i]);
    }

    // (read before fit_dcurv reuses `weight`)
    void mark_valid() {
        valid.assign(nv, 0);
        for (std::size_t i = 0; i < nv; ++i) valid[i] = vertex_valid(usable_faces[i], normal[i], weight[i], k1[i], k2[i]);
    }

    // Per face: the derivative tensor C fit, then pushed to the corners' principal frames.
    void fit_dcurv() {
        dcurv.assign(nv, {0.0, 0.0, 0.0, 0.0});
        std::fill(weight.begin(), weight.end(), 0.0);
        for (std::uint32_t f = 0; f < nf; ++f) {
            const auto& v = mesh.faces[f];
            if (!face_usable[f] || !valid[v[0]] || !valid[v[1]] || !valid[v[2]]) continue;
            const FaceFrame& fr = frame[f];
            FrameChange fc[3];
            double kk1[3], kk2[3], m[4];
            for (int j = 0; j < 3; ++j) {
                fc[j] = corner_frame(fr, normal[v[j]], dir_u[v[j]]);
                kk1[j] = k1[v[j]], kk2[j] = k2[v[j]];
            }
            if (!fit_face_dcurv(fr, fc, kk1, kk2, m)) continue;
            for (int j = 0; j < 3; ++j) {
                const std::uint32_t vj = v[j];
                const auto c = project_cubic(fc[j], {m[0], m[1], m[2], m[3]});
                const double wt = corner[f][j];
                for (int k = 0; k < 4; ++k) dcurv[vj][k] += wt * c[k];
                weight[vj] += wt;
            }
        }
    }

    void write(CurvatureField& out) const {
        resize_field(out, nv);
        out.invalid_vertices = 0;
        for (std::size_t i = 0; i < nv; ++i) {
            write_vertex(out, i, normal[i], dir_u[i], point_area[i], valid[i] != 0, k1[i], k2[i], dcurv[i], weight[i]);
            out.invalid_vertices += !out.valid[i];
        }
    }
};

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
    est.run_all();
    CurvatureField field;
    est.write(field);
    field.feature_size = median_edge_length(mesh);
    return field;
}

// ---- IncrementalCurvature: estimate_curvature's phases restricted to what a mesh change reaches.
// Each phase visits the faces in order, as estimate_curvature does, skipping the faces no vertex
// it recomputes lies on, and adds only into those vertices: each of their sums takes the same terms
// in the same order.

namespace {
constexpr std::uint32_t kNone = UINT32_MAX;

// What a later mesh reads of a vertex: the estimator's doubles (dir: dir1, after diagonalization).
struct VertexValues {
    std::vector<dvec3> normal, dir;
    std::vector<double> k1, k2, point_area;
    std::vector<std::uint8_t> usable_faces, valid;
    void resize(std::size_t n) {
        normal.resize(n), dir.resize(n), k1.resize(n), k2.resize(n), point_area.resize(n);
        usable_faces.resize(n), valid.resize(n);
    }
    void copy(std::uint32_t to, const VertexValues& from, std::uint32_t i) {
        normal[to] = from.normal[i], dir[to] = from.dir[i], k1[to] = from.k1[i], k2[to] = from.k2[i];
        point_area[to] = from.point_area[i], usable_faces[to] = from.usable_faces[i], valid[to] = from.valid[i];
    }
};
}  // namespace

struct IncrementalCurvature::State {
    // This mesh's and the last one's (the last ones in last_*; swapped at the end of an update).
    VertexValues vert, last_vert;
    CurvatureField field, last_field;
    std::vector<std::uint32_t> vertex_id, last_vertex_id, face_id, last_face_id;
    std::vector<dvec3> last_positions;
    std::vector<std::array<std::uint32_t, 3>> last_faces;  // the last mesh's faces (its vertex indices)
    // Scratch for the current mesh. level per vertex: 3 its faces changed (normal, areas), 2 a
    // neighbour's normal did (curvature), 1 a neighbour's curvature did (derivative), 0 none.
    // Where each vertex and face is in the last mesh (kNone: not there), and the last mesh's in this
    // one: both meshes list their ids increasing, so one merge matches them (no map by id).
    std::vector<std::uint32_t> last_slot, now_of_last_vertex, last_face, now_of_last_face;
    std::vector<std::uint8_t> level, moved, face_level;  // face_level: the most of its corners'
    std::vector<FaceFrame> frame;
    std::vector<std::array<double, 3>> corner;
    std::vector<std::uint8_t> face_usable;
    std::vector<std::array<double, 3>> tensor;
    std::vector<std::array<double, 4>> dcurv;
    std::vector<double> weight;
    std::size_t recomputed = 0;

    void map_and_mark(const MeshTopology& m);
    void spread_levels(const MeshTopology& m);
    void faces_pass(const MeshTopology& m);
    void fit_curvature(const MeshTopology& m);
    void fit_dcurv(const MeshTopology& m);
    void write(const MeshTopology& m);
    void remember(const MeshTopology& m);
};

// Each vertex's index in the last mesh; level 3 at the corners of every face that is new, has other
// corners or a corner that moved, and at the remaining corners of every face that went away.
void IncrementalCurvature::State::map_and_mark(const MeshTopology& m) {
    const std::size_t nv = m.vertex_count(), nf = m.face_count();
    match_increasing_ids(vertex_id, last_vertex_id, &last_slot, &now_of_last_vertex);
    match_increasing_ids(face_id, last_face_id, &last_face, &now_of_last_face);
    moved.assign(nv, 0);
    for (std::uint32_t v = 0; v < nv; ++v) {
        const std::uint32_t s = last_slot[v];
        moved[v] = s == kNone || last_positions[s] != m.positions[v];
    }
    level.assign(nv, 0);
    for (std::uint32_t f = 0; f < nf; ++f) {
        const auto& c = m.faces[f];
        const std::uint32_t q = last_face[f];
        bool changed = q == kNone || moved[c[0]] || moved[c[1]] || moved[c[2]];
        // (a corner is the same vertex when its index in the last mesh is the last face's corner)
        for (int j = 0; j < 3 && !changed; ++j) changed = last_faces[q][j] != last_slot[c[j]];
        if (changed) level[c[0]] = level[c[1]] = level[c[2]] = 3;
    }
    for (std::uint32_t q = 0; q < last_face_id.size(); ++q) {
        const std::uint32_t f = now_of_last_face[q];
        bool same = f != kNone;
        for (int j = 0; j < 3 && same; ++j) same = last_faces[q][j] == last_slot[m.faces[f][j]];
        if (same) continue;
        for (const std::uint32_t w : last_faces[q]) {
            const std::uint32_t v = now_of_last_vertex[w];
            if (v != kNone) level[v] = 3;
        }
    }
}

// Level 2 at the corners of faces with a level-3 corner, then 1 at those with a level-2 one; each
// face's level is then its corners' highest (a phase visits the faces of at least its level).
void IncrementalCurvature::State::spread_levels(const MeshTopology& m) {
    for (const std::uint8_t from : {std::uint8_t(3), std::uint8_t(2)})
        for (const auto& c : m.faces) {
            if (std::max({level[c[0]], level[c[1]], level[c[2]]}) < from) continue;
            for (const std::uint32_t v : c) level[v] = std::max(level[v], std::uint8_t(from - 1));
        }
    face_level.resize(m.face_count());
    for (std::size_t f = 0; f < m.face_count(); ++f) {
        const auto& c = m.faces[f];
        face_level[f] = std::max({level[c[0]], level[c[1]], level[c[2]]});
    }
}

// Estimator::faces_pass and vertex_frames for the level-3 vertices (the faces' frames wherever a
// later phase reads them); the tangent again at level 2 (its normal is carried over).
void IncrementalCurvature::State::faces_pass(const MeshTopology& m) {
    const std::size_t nv = m.vertex_count(), nf = m.face_count();
    for (std::uint32_t v = 0; v < nv; ++v)
        if (level[v] == 3) vert.normal[v] = dvec3(0.0), vert.point_area[v] = 0.0, vert.usable_faces[v] = 0;
    frame.resize(nf);
    corner.resize(nf);
    face_usable.resize(nf);
    for (std::uint32_t f = 0; f < nf; ++f) {
        if (face_level[f] == 0) continue;
        const auto& v = m.faces[f];
        const FaceGeometry g = face_geometry(m, f);
        if (face_level[f] == 3 && has_normal_term(g)) {
            const dvec3 n2 = glm::cross(g.e[0], g.e[1]);
            for (int j = 0; j < 3; ++j)
                if (level[v[j]] == 3) vert.normal[v[j]] += normal_term(g, n2, j);
        }
        face_usable[f] = g.usable;
        if (!g.usable) continue;
        frame[f] = face_frame(g);
        corner[f] = corner_areas(g);
        if (face_level[f] < 3) continue;
        for (int j = 0; j < 3; ++j) {
            if (level[v[j]] != 3) continue;
            vert.point_area[v[j]] += corner[f][j];
            vert.usable_faces[v[j]] = std::uint8_t(std::min(2, vert.usable_faces[v[j]] + 1));
        }
    }
    for (std::uint32_t v = 0; v < nv; ++v) {
        if (level[v] == 3) {
            vert.dir[v] = dvec3(0.0);
            vertex_frame(vert.normal[v], vert.dir[v]);
        } else if (level[v] == 2) {
            vert.dir[v] = tangent_of(vert.normal[v]);
        }
    }
}

// Estimator::fit_curvature, diagonalize and mark_valid for the vertices of level 2 and 3.
void IncrementalCurvature::State::fit_curvature(const MeshTopology& m) {
    const std::size_t nv = m.vertex_count(), nf = m.face_count();
    tensor.resize(nv);
    weight.resize(nv);
    for (std::uint32_t v = 0; v < nv; ++v)
        if (level[v] >= 2) tensor[v] = {0.0, 0.0, 0.0}, weight[v] = 0.0;
    const auto usable = [&](std::uint32_t v) { return vert.usable_faces[v] >= 2 && vert.normal[v] != dvec3(0.0); };
    for (std::uint32_t f = 0; f < nf; ++f) {
        if (face_level[f] < 2 || !face_usable[f]) continue;
        const auto& v = m.faces[f];
        const FaceFrame& fr = frame[f];
        double fit[3];
        if (!fit_face_curvature(fr, {&vert.normal[v[0]], &vert.normal[v[1]], &vert.normal[v[2]]}, fit)) continue;
        for (int j = 0; j < 3; ++j) {
            const std::uint32_t vj = v[j];
            if (level[vj] < 2 || !usable(vj)) continue;
            const auto c = project_tensor(corner_frame(fr, vert.normal[vj], vert.dir[vj]), {fit[0], fit[1], fit[2]});
            const double wt = corner[f][j];
            for (int k = 0; k < 3; ++k) tensor[vj][k] += wt * c[k];
            weight[vj] += wt;
        }
    }
    for (std::uint32_t v = 0; v < nv; ++v) {
        if (level[v] < 2) continue;
        diagonalize_vertex(tensor[v], weight[v], vert.normal[v], vert.dir[v], vert.k1[v], vert.k2[v]);
        vert.valid[v] = vertex_valid(vert.usable_faces[v], vert.normal[v], weight[v], vert.k1[v], vert.k2[v]);
    }
}

// Estimator::fit_dcurv for the vertices of level 1 to 3.
void IncrementalCurvature::State::fit_dcurv(const MeshTopology& m) {
    const std::size_t nv = m.vertex_count(), nf = m.face_count();
    dcurv.resize(nv);
    for (std::uint32_t v = 0; v < nv; ++v)
        if (level[v] >= 1) dcurv[v] = {0.0, 0.0, 0.0, 0.0}, weight[v] = 0.0;
    for (std::uint32_t f = 0; f < nf; ++f) {
        const auto& v = m.faces[f];
        if (face_level[f] < 1 || !face_usable[f] || !vert.valid[v[0]] || !vert.valid[v[1]] || !vert.valid[v[2]])
            continue;
        const FaceFrame& fr = frame[f];
        FrameChange fc[3];
        double k1[3], k2[3], fit[4];
        for (int j = 0; j < 3; ++j) {
            fc[j] = corner_frame(fr, vert.normal[v[j]], vert.dir[v[j]]);
            k1[j] = vert.k1[v[j]], k2[j] = vert.k2[v[j]];
        }
        if (!fit_face_dcurv(fr, fc, k1, k2, fit)) continue;
        for (int j = 0; j < 3; ++j) {
            const std::uint32_t vj = v[j];
            if (level[vj] < 1) continue;
            const auto c = project_cubic(fc[j], {fit[0], fit[1], fit[2], fit[3]});
            const double wt = corner[f][j];
            for (int k = 0; k < 4; ++k) dcurv[vj][k] += wt * c[k];
            weight[vj] += wt;
        }
    }
}

// The field: recomputed vertices written as estimate_curvature writes them, the others carried over.
void IncrementalCurvature::State::write(const MeshTopology& m) {
    const std::size_t nv = m.vertex_count();
    resize_field(field, nv);
    field.invalid_vertices = 0;
    for (std::uint32_t v = 0; v < nv; ++v) {
        if (level[v] == 0) {
            const std::uint32_t s = last_slot[v];
            field.normal[v] = last_field.normal[s];
            field.dir1[v] = last_field.dir1[s];
            field.k1[v] = last_field.k1[s];
            field.k2[v] = last_field.k2[s];
            field.dcurv[v] = last_field.dcurv[s];
            field.point_area[v] = last_field.point_area[s];
            field.valid[v] = last_field.valid[s];
        } else {
            write_vertex(field, v, vert.normal[v], vert.dir[v], vert.point_area[v], vert.valid[v] != 0, vert.k1[v],
                         vert.k2[v], dcurv[v], weight[v]);
            ++recomputed;
        }
        field.invalid_vertices += !field.valid[v];
    }
    field.feature_size = median_edge_length(m);
}

void IncrementalCurvature::State::remember(const MeshTopology& m) {
    last_positions.assign(m.positions.begin(), m.positions.end());
    last_faces.assign(m.faces.begin(), m.faces.end());
}

IncrementalCurvature::IncrementalCurvature() : state_(std::make_unique<State>()) {}
IncrementalCurvature::~IncrementalCurvature() = default;
const CurvatureField& IncrementalCurvature::field() const { return state_->last_field; }
std::size_t IncrementalCurvature::recomputed_vertices() const { return state_->recomputed; }

const CurvatureField& IncrementalCurvature::update(const MeshTopology& mesh, const std::vector<std::uint32_t>& vertex_id,
                                                   const std::vector<std::uint32_t>& face_id) {
    State& s = *state_;
    // (last_* hold the last mesh's values; this mesh's are written into the others, then swapped)
    s.vertex_id.assign(vertex_id.begin(), vertex_id.end());
    s.face_id.assign(face_id.begin(), face_id.end());
    s.recomputed = 0;
    s.map_and_mark(mesh);
    s.spread_levels(mesh);
    const std::size_t reached = std::size_t(std::count_if(s.level.begin(), s.level.end(), [](std::uint8_t l) { return l > 0; }));
    if (10 * reached > 9 * mesh.vertex_count()) {
        // Nearly everything changed: the whole estimate (faster than the restricted phases), its
        // vertices' doubles kept for the next mesh.
        Estimator est(mesh);
        est.run_all();
        est.write(s.field);
        s.field.feature_size = median_edge_length(mesh);
        s.vert.normal.swap(est.normal), s.vert.dir.swap(est.dir_u), s.vert.k1.swap(est.k1), s.vert.k2.swap(est.k2);
        s.vert.point_area.swap(est.point_area), s.vert.usable_faces.swap(est.usable_faces), s.vert.valid.swap(est.valid);
        s.recomputed = mesh.vertex_count();
    } else {
        s.vert.resize(mesh.vertex_count());
        for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v)
            if (s.last_slot[v] != kNone) s.vert.copy(v, s.last_vert, s.last_slot[v]);
        s.faces_pass(mesh);
        s.fit_curvature(mesh);
        s.fit_dcurv(mesh);
        s.write(mesh);
    }
    s.remember(mesh);
    std::swap(s.field, s.last_field);
    std::swap(s.vert, s.last_vert);
    std::swap(s.vertex_id, s.last_vertex_id);
    std::swap(s.face_id, s.last_face_id);
    return s.last_field;
}

}  // namespace inkline
