// Freeform surfaces (Elber 99, section 2.1): exact evaluation of point, first and second partial
// derivatives, unit normal, principal curvatures and directions, for tensor-product Bezier patches
// (read from the classic `.bpt` format or from a small JSON description) and parametric primitives
// (sphere, torus, the "wavy torus"). Takes parameters (u, v) in a surface's domain; gives
// SurfacePoint and Curvature. Primitives are differentiated exactly by second-order forward-mode
// automatic differentiation (no finite differences); Bezier patches through Bernstein derivatives.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace inkline::freeform {

// Position and partial derivatives at (u, v).
struct SurfacePoint {
    glm::dvec3 p{0.0}, su{0.0}, sv{0.0}, suu{0.0}, suv{0.0}, svv{0.0};
};

// Principal curvatures k1 >= k2 (signed w.r.t. the unit normal n: a sphere of radius r with its
// outward normal has k1 = k2 = -1/r) and their directions, in 3D (unit, tangent) and in (u, v).
struct Curvature {
    glm::dvec3 n{0.0};
    double k1 = 0.0, k2 = 0.0;
    glm::dvec3 d1{0.0}, d2{0.0};
    glm::dvec2 uv1{0.0}, uv2{0.0};
    bool valid = false;  // false where S_u x S_v vanishes (poles, collapsed patch edges)
};

class Surface {
public:
    virtual ~Surface() = default;
    virtual SurfacePoint eval(double u, double v) const = 0;
    virtual std::string name() const = 0;
    // Parameter domain [u0, u1] x [v0, v1]; periodic directions wrap instead of ending.
    glm::dvec2 u_range{0.0, 1.0}, v_range{0.0, 1.0};
    bool periodic_u = false, periodic_v = false;
    // Normal orientation: the unit normal is sign * normalize(S_u x S_v) (tessellation sets it
    // so that normals of closed parts point outward).
    double sign = 1.0;
    // Strokes are drawn on a transparent surface, but it hides nothing (paper, section 2.3).
    bool transparent = false;

    glm::dvec3 normal(double u, double v) const;
    Curvature curvature(double u, double v) const;
};

// Differential geometry of an evaluated point (normal sign +1 or -1).
glm::dvec3 unit_normal(const SurfacePoint& s, double sign);
Curvature curvature_of(const SurfacePoint& s, double sign);

// Tensor-product Bezier patch of degree (nu, nv): control point (i, j) at cp[i * (nv + 1) + j],
// i along u. Domain [0, 1]^2.
class BezierPatch final : public Surface {
public:
    BezierPatch(int degree_u, int degree_v, std::vector<glm::dvec3> control_points);
    SurfacePoint eval(double u, double v) const override;
    std::string name() const override { return "bezier"; }
    int degree_u() const { return nu_; }
    int degree_v() const { return nv_; }
    const std::vector<glm::dvec3>& control_points() const { return cp_; }

private:
    int nu_, nv_;
    std::vector<glm::dvec3> cp_;
};

// Rational B-spline (NURBS) surface of degree (p, q) with knot vectors U (nu + p + 1 values) and
// V (nv + q + 1), nu x nv control points (i along u) with positive weights. Domain
// [U[p], U[nu]] x [V[q], V[nv]]. Derivatives exact: B-spline basis derivatives (Cox-de Boor) and the
// quotient rule on the homogeneous sums.
class NurbsSurface final : public Surface {
public:
    NurbsSurface(int degree_u, int degree_v, std::vector<double> knots_u, std::vector<double> knots_v, int count_u,
                 int count_v, std::vector<glm::dvec3> points, std::vector<double> weights);
    SurfacePoint eval(double u, double v) const override;
    std::string name() const override { return "nurbs"; }
    int spans_u() const;  // non-empty knot spans in the domain
    int spans_v() const;

private:
    int p_, q_, nu_, nv_;
    std::vector<double> U_, V_;
    std::vector<glm::dvec3> P_;
    std::vector<double> W_;
};

// Sphere: u in [0, pi] the colatitude from +z, v in [0, 2 pi) the longitude (periodic).
class Sphere final : public Surface {
public:
    Sphere(glm::dvec3 center, double radius);
    SurfacePoint eval(double u, double v) const override;
    std::string name() const override { return "sphere"; }
    glm::dvec3 center;
    double radius;
};

// Torus around +z: ((R + rho cos v) cos u, (R + rho cos v) sin u, rho sin v) + center, both
// parameters periodic in [0, 2 pi). For the torus rho = r; for the wavy torus (our reading of the
// paper's Figure 4 model) the tube radius waves along the ring: rho(u) = r (1 + a sin(k u)).
class Torus final : public Surface {
public:
    Torus(glm::dvec3 center, double R, double r, double wave_amplitude = 0.0, int waves = 0);
    SurfacePoint eval(double u, double v) const override;
    std::string name() const override { return amplitude == 0.0 ? "torus" : "wavy_torus"; }
    glm::dvec3 center;
    double R, r, amplitude;
    int waves;
};

using SurfaceList = std::vector<std::unique_ptr<Surface>>;

// `.bpt`: the number of patches, then per patch a line "nu nv" and (nu+1)(nv+1) lines "x y z",
// control points row by row. Throws inkline::Error("<path>: <problem>") on malformed input.
SurfaceList load_bpt(const std::string& path);
SurfaceList parse_bpt(const std::string& text, const std::string& where);

// JSON (documented in src/freeform/README.md):
// {"surfaces": [{"type": "bezier", "degree": [3, 3], "points": [[x, y, z], ...]},
//               {"type": "sphere", "center": [x, y, z], "radius": r},
//               {"type": "torus", "center": [..], "R": 1, "r": 0.3},
//               {"type": "wavy_torus", "center": [..], "R": 1, "r": 0.3, "amplitude": 0.3, "waves": 6},
//               {"type": "nurbs", "degree": [p, q], "knots_u": [..], "knots_v": [..], "count": [nu, nv],
//                "points": [[x, y, z] or [x, y, z, weight], ...]}],
//  "transparent": [indices of transparent surfaces] (optional)}
SurfaceList load_surfaces_json(const std::string& path);
SurfaceList parse_surfaces_json(const std::string& text, const std::string& where);

// By extension: .bpt or .json.
SurfaceList load_surfaces(const std::string& path);
// True for paths load_surfaces reads (.bpt, .json).
bool is_freeform_path(const std::string& path);

}  // namespace inkline::freeform
