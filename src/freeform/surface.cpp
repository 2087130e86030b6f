#include "freeform/surface.hpp"

#include <array>
#include <cmath>
#include <sstream>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/files.hpp"

namespace inkline::freeform {
namespace {

// Second-order forward-mode jet in two variables (u, v): value, gradient and Hessian, exact to
// rounding for the operations below (chain rule applied symbolically).
struct Jet {
    double f = 0, u = 0, v = 0, uu = 0, uv = 0, vv = 0;
};
Jet constant(double c) { return {c, 0, 0, 0, 0, 0}; }
Jet operator+(Jet a, Jet b) { return {a.f + b.f, a.u + b.u, a.v + b.v, a.uu + b.uu, a.uv + b.uv, a.vv + b.vv}; }
Jet operator*(Jet a, Jet b) {
    return {a.f * b.f,
            a.u * b.f + a.f * b.u,
            a.v * b.f + a.f * b.v,
            a.uu * b.f + 2 * a.u * b.u + a.f * b.uu,
            a.uv * b.f + a.u * b.v + a.v * b.u + a.f * b.uv,
            a.vv * b.f + 2 * a.v * b.v + a.f * b.vv};
}
Jet operator*(double c, Jet a) { return {c * a.f, c * a.u, c * a.v, c * a.uu, c * a.uv, c * a.vv}; }
// g(a) with g' = d1, g'' = d2 at a.f.
Jet apply(Jet a, double g, double d1, double d2) {
    return {g, d1 * a.u, d1 * a.v, d2 * a.u * a.u + d1 * a.uu, d2 * a.u * a.v + d1 * a.uv, d2 * a.v * a.v + d1 * a.vv};
}
Jet sin(Jet a) { return apply(a, std::sin(a.f), std::cos(a.f), -std::sin(a.f)); }
Jet cos(Jet a) { return apply(a, std::cos(a.f), -std::sin(a.f), -std::cos(a.f)); }

SurfacePoint from_jets(const Jet& x, const Jet& y, const Jet& z) {
    SurfacePoint s;
    s.p = {x.f, y.f, z.f};
    s.su = {x.u, y.u, z.u};
    s.sv = {x.v, y.v, z.v};
    s.suu = {x.uu, y.uu, z.uu};
    s.suv = {x.uv, y.uv, z.uv};
    s.svv = {x.vv, y.vv, z.vv};
    return s;
}

// Bernstein basis of degree n at t with first and second derivatives.
void bernstein(int n, double t, double* b, double* d1, double* d2) {
    auto basis = [&](int deg, int i) -> double {
        if (i < 0 || i > deg) return 0.0;
        double c = 1.0;
        for (int k = 1; k <= i; ++k) c = c * (deg - i + k) / k;
        return c * std::pow(t, i) * std::pow(1.0 - t, deg - i);
    };
    for (int i = 0; i <= n; ++i) {
        b[i] = basis(n, i);
        d1[i] = n >= 1 ? n * (basis(n - 1, i - 1) - basis(n - 1, i)) : 0.0;
        d2[i] = n >= 2 ? n * (n - 1) * (basis(n - 2, i - 2) - 2 * basis(n - 2, i - 1) + basis(n - 2, i)) : 0.0;
    }
}

std::string lower_ext(const std::string& path) {
    const auto dot = path.find_last_of('.');
    const auto slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string e = path.substr(dot + 1);
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

void check_finite(const glm::dvec3& p, const std::string& where, const std::string& what) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw Error(where, what + " has a NaN or infinite coordinate");
}

}  // namespace

glm::dvec3 unit_normal(const SurfacePoint& s, double sign) {
    const glm::dvec3 n = glm::cross(s.su, s.sv);
    const double l = glm::length(n);
    return l > 0.0 ? (sign / l) * n : glm::dvec3(0.0);
}

Curvature curvature_of(const SurfacePoint& s, double sign) {
    Curvature c;
    const glm::dvec3 cr = glm::cross(s.su, s.sv);
    const double E = glm::dot(s.su, s.su), F = glm::dot(s.su, s.sv), G = glm::dot(s.sv, s.sv);
    const double det = E * G - F * F;
    const double len = glm::length(cr);
    if (!(len > 1e-14 * std::max(E, G)) || !(det > 0.0)) return c;
    c.n = (sign / len) * cr;
    const double L = glm::dot(s.suu, c.n), M = glm::dot(s.suv, c.n), N = glm::dot(s.svv, c.n);
    // Shape operator W = I^-1 II; its eigenvalues from the half-difference of the diagonal (no
    // cancellation near umbilics, unlike sqrt(H^2 - K)).
    const double W11 = (G * L - F * M) / det, W12 = (G * M - F * N) / det;
    const double W21 = (E * M - F * L) / det, W22 = (E * N - F * M) / det;
    const double H = 0.5 * (W11 + W22), h = 0.5 * (W11 - W22);
    const double disc = std::sqrt(std::max(0.0, h * h + W12 * W21));
    c.k1 = H + disc;
    c.k2 = H - disc;
    // Eigenvector of (II - k I): the longer of the two rows' null vectors.
    const double k = c.k1;
    glm::dvec2 a(-(M - k * F), L - k * E), b(N - k * G, -(M - k * F));
    glm::dvec2 x = glm::dot(a, a) >= glm::dot(b, b) ? a : b;
    glm::dvec3 d1 = x.x * s.su + x.y * s.sv;
    if (!(glm::length(d1) > 1e-12 * std::sqrt(E + G)))  // umbilic: every direction is principal
        d1 = s.su;
    c.d1 = glm::normalize(d1);
    c.d2 = glm::cross(c.n, c.d1);
    // Back to (u, v): solve [su sv] x = d in the least-squares sense (exact for tangent d).
    auto to_uv = [&](const glm::dvec3& d) {
        const double a1 = glm::dot(s.su, d), a2 = glm::dot(s.sv, d);
        return glm::dvec2((G * a1 - F * a2) / det, (E * a2 - F * a1) / det);
    };
    c.uv1 = to_uv(c.d1);
    c.uv2 = to_uv(c.d2);
    c.valid = true;
    return c;
}

glm::dvec3 Surface::normal(double u, double v) const { return unit_normal(eval(u, v), sign); }
Curvature Surface::curvature(double u, double v) const { return curvature_of(eval(u, v), sign); }

BezierPatch::BezierPatch(int degree_u, int degree_v, std::vector<glm::dvec3> control_points)
    : nu_(degree_u), nv_(degree_v), cp_(std::move(control_points)) {
    if (nu_ < 1 || nv_ < 1 || nu_ > 15 || nv_ > 15 || cp_.size() != std::size_t((nu_ + 1) * (nv_ + 1)))
        throw Error("bezier patch", "degrees must be 1..15 with (nu+1)(nv+1) control points");
}

SurfacePoint BezierPatch::eval(double u, double v) const {
    double bu[16], du[16], ddu[16], bv[16], dv[16], ddv[16];
    bernstein(nu_, u, bu, du, ddu);
    bernstein(nv_, v, bv, dv, ddv);
    SurfacePoint s;
    for (int i = 0; i <= nu_; ++i)
        for (int j = 0; j <= nv_; ++j) {
            const glm::dvec3& q = cp_[std::size_t(i * (nv_ + 1) + j)];
            s.p += bu[i] * bv[j] * q;
            s.su += du[i] * bv[j] * q;
            s.sv += bu[i] * dv[j] * q;
            s.suu += ddu[i] * bv[j] * q;
            s.suv += du[i] * dv[j] * q;
            s.svv += bu[i] * ddv[j] * q;
        }
    return s;
}

namespace {
// Values, first and second derivatives of the n B-spline basis functions of degree p at t.
// The last knot span is closed so that t = the domain's end evaluates.
void bspline_basis(const std::vector<double>& K, int p, int n, double t, std::vector<double>& N0,
                   std::vector<double>& N1, std::vector<double>& N2) {
    const int m = int(K.size());
    // Degree-0 functions over all m - 1 spans.
    std::vector<std::vector<double>> N(std::size_t(p + 1), std::vector<double>(std::size_t(m - 1), 0.0));
    int last = -1;  // last non-empty span (for t at the end of the domain)
    for (int i = 0; i + 1 < m; ++i)
        if (K[std::size_t(i)] < K[std::size_t(i + 1)] && i >= p && i < n) last = i;
    for (int i = 0; i + 1 < m; ++i)
        N[0][std::size_t(i)] = (K[std::size_t(i)] <= t && t < K[std::size_t(i + 1)]) ? 1.0 : 0.0;
    if (t >= K[std::size_t(n)] && last >= 0) {
        std::fill(N[0].begin(), N[0].end(), 0.0);
        N[0][std::size_t(last)] = 1.0;
    }
    auto ratio = [](double a, double b) { return b != 0.0 ? a / b : 0.0; };
    for (int d = 1; d <= p; ++d)
        for (int i = 0; i + d + 1 < m; ++i) {
            const std::size_t I = std::size_t(i);
            N[std::size_t(d)][I] = ratio(t - K[I], K[I + std::size_t(d)] - K[I]) * N[std::size_t(d - 1)][I] +
                                   ratio(K[I + std::size_t(d) + 1] - t, K[I + std::size_t(d) + 1] - K[I + 1]) *
                                       N[std::size_t(d - 1)][I + 1];
        }
    // Derivatives: N'_{i,p} = p (N_{i,p-1} / (K[i+p] - K[i]) - N_{i+1,p-1} / (K[i+p+1] - K[i+1])),
    // and the same rule applied to N'_{., p-1} for the second derivative.
    auto deriv = [&](const std::vector<double>& lower, int d, int i) {
        const std::size_t I = std::size_t(i);
        return d * (ratio(lower[I], K[I + std::size_t(d)] - K[I]) -
                    ratio(lower[I + 1], K[I + std::size_t(d) + 1] - K[I + 1]));
    };
    N0.assign(std::size_t(n), 0.0);
    N1.assign(std::size_t(n), 0.0);
    N2.assign(std::size_t(n), 0.0);
    std::vector<double> d1_lower(std::size_t(m - 1), 0.0);  // first derivatives at degree p - 1
    if (p >= 2)
        for (int i = 0; i + p < m; ++i) d1_lower[std::size_t(i)] = deriv(N[std::size_t(p - 2)], p - 1, i);
    for (int i = 0; i < n; ++i) {
        N0[std::size_t(i)] = N[std::size_t(p)][std::size_t(i)];
        if (p >= 1) N1[std::size_t(i)] = deriv(N[std::size_t(p - 1)], p, i);
        if (p >= 2) N2[std::size_t(i)] = deriv(d1_lower, p, i);
    }
}
}  // namespace

NurbsSurface::NurbsSurface(int p, int q, std::vector<double> U, std::vector<double> V, int nu, int nv,
                           std::vector<glm::dvec3> P, std::vector<double> W)
    : p_(p), q_(q), nu_(nu), nv_(nv), U_(std::move(U)), V_(std::move(V)), P_(std::move(P)), W_(std::move(W)) {
    if (p < 1 || q < 1 || p > 15 || q > 15) throw Error("nurbs", "degrees must be 1..15");
    if (nu <= p || nv <= q) throw Error("nurbs", "need more control points than the degree in each direction");
    if (U_.size() != std::size_t(nu + p + 1) || V_.size() != std::size_t(nv + q + 1))
        throw Error("nurbs", "knot vectors must hold count + degree + 1 values");
    if (P_.size() != std::size_t(nu) * std::size_t(nv) || W_.size() != P_.size())
        throw Error("nurbs", "need count_u x count_v control points and weights");
    for (const auto* K : {&U_, &V_})
        for (std::size_t i = 0; i < K->size(); ++i)
            if (!std::isfinite((*K)[i]) || (i > 0 && (*K)[i] < (*K)[i - 1])) throw Error("nurbs", "knots must be finite and non-decreasing");
    for (double w : W_)
        if (!(w > 0.0) || !std::isfinite(w)) throw Error("nurbs", "weights must be positive");
    u_range = {U_[std::size_t(p)], U_[std::size_t(nu)]};
    v_range = {V_[std::size_t(q)], V_[std::size_t(nv)]};
    if (!(u_range[1] > u_range[0]) || !(v_range[1] > v_range[0])) throw Error("nurbs", "empty parameter domain");
}

namespace {
int spans(const std::vector<double>& K, int p, int n) {
    int c = 0;
    for (int i = p; i < n; ++i) c += K[std::size_t(i)] < K[std::size_t(i + 1)];
    return c;
}
}  // namespace
int NurbsSurface::spans_u() const { return spans(U_, p_, nu_); }
int NurbsSurface::spans_v() const { return spans(V_, q_, nv_); }

SurfacePoint NurbsSurface::eval(double u, double v) const {
    std::vector<double> a0, a1, a2, b0, b1, b2;
    bspline_basis(U_, p_, nu_, u, a0, a1, a2);
    bspline_basis(V_, q_, nv_, v, b0, b1, b2);
    // Homogeneous sums A = sum N M w P and w = sum N M w, with their partials.
    glm::dvec3 A(0.0), Au(0.0), Av(0.0), Auu(0.0), Auv(0.0), Avv(0.0);
    double w = 0, wu = 0, wv = 0, wuu = 0, wuv = 0, wvv = 0;
    for (int i = 0; i < nu_; ++i) {
        const std::size_t I = std::size_t(i);
        if (a0[I] == 0.0 && a1[I] == 0.0 && a2[I] == 0.0) continue;
        for (int j = 0; j < nv_; ++j) {
            const std::size_t J = std::size_t(j);
            const std::size_t k = I * std::size_t(nv_) + J;
            const double wk = W_[k];
            const glm::dvec3 hp = wk * P_[k];
            const double c[6] = {a0[I] * b0[J], a1[I] * b0[J], a0[I] * b1[J], a2[I] * b0[J], a1[I] * b1[J], a0[I] * b2[J]};
            A += c[0] * hp, Au += c[1] * hp, Av += c[2] * hp, Auu += c[3] * hp, Auv += c[4] * hp, Avv += c[5] * hp;
            w += c[0] * wk, wu += c[1] * wk, wv += c[2] * wk, wuu += c[3] * wk, wuv += c[4] * wk, wvv += c[5] * wk;
        }
    }
    SurfacePoint s;
    s.p = A / w;
    s.su = (Au - wu * s.p) / w;
    s.sv = (Av - wv * s.p) / w;
    s.suu = (Auu - 2.0 * wu * s.su - wuu * s.p) / w;
    s.suv = (Auv - wu * s.sv - wv * s.su - wuv * s.p) / w;
    s.svv = (Avv - 2.0 * wv * s.sv - wvv * s.p) / w;
    return s;
}

Sphere::Sphere(glm::dvec3 c, double r) : center(c), radius(r) {
    if (!(r > 0.0) || !std::isfinite(r)) throw Error("sphere", "radius must be positive");
    u_range = {0.0, M_PI};
    v_range = {0.0, 2.0 * M_PI};
    periodic_v = true;
}

SurfacePoint Sphere::eval(double u, double v) const {
    const Jet U{u, 1, 0, 0, 0, 0}, V{v, 0, 1, 0, 0, 0};
    const Jet su = sin(U);
    SurfacePoint s = from_jets(radius * (su * cos(V)), radius * (su * sin(V)), radius * cos(U));
    s.p += center;
    return s;
}

Torus::Torus(glm::dvec3 c, double R_, double r_, double a, int k) : center(c), R(R_), r(r_), amplitude(a), waves(k) {
    if (!(r_ > 0.0) || !(R_ > r_ * (1.0 + std::abs(a))) || !std::isfinite(R_) || !(std::abs(a) < 1.0))
        throw Error(name(), "need 0 < r (1 + |amplitude|) < R and |amplitude| < 1");
    u_range = {0.0, 2.0 * M_PI};
    v_range = {0.0, 2.0 * M_PI};
    periodic_u = periodic_v = true;
}

SurfacePoint Torus::eval(double u, double v) const {
    const Jet U{u, 1, 0, 0, 0, 0}, V{v, 0, 1, 0, 0, 0};
    const Jet rho = r * (constant(1.0) + amplitude * sin(double(waves) * U));
    const Jet ring = constant(R) + rho * cos(V);
    SurfacePoint s = from_jets(ring * cos(U), ring * sin(U), rho * sin(V));
    s.p += center;
    return s;
}

SurfaceList parse_bpt(const std::string& text, const std::string& where) {
    std::istringstream in(text);
    long long count = 0;
    if (!(in >> count)) throw Error(where, "expected the number of patches on the first line");
    if (count <= 0 || count > 1000000) throw Error(where, "bad number of patches " + std::to_string(count));
    SurfaceList out;
    for (long long k = 0; k < count; ++k) {
        const std::string pw = "patch " + std::to_string(k + 1);
        long long nu = 0, nv = 0;
        if (!(in >> nu >> nv)) throw Error(where, pw + ": expected degrees 'nu nv' (file ends or is malformed)");
        if (nu < 1 || nv < 1 || nu > 15 || nv > 15)
            throw Error(where, pw + ": degrees must be between 1 and 15, got " + std::to_string(nu) + " " + std::to_string(nv));
        std::vector<glm::dvec3> cp(std::size_t((nu + 1) * (nv + 1)));
        for (std::size_t i = 0; i < cp.size(); ++i) {
            std::string xs, ys, zs;
            if (!(in >> xs >> ys >> zs))
                throw Error(where, pw + ": expected " + std::to_string(cp.size()) + " control points, got " + std::to_string(i));
            try {
                std::size_t px = 0, py = 0, pz = 0;
                cp[i] = {std::stod(xs, &px), std::stod(ys, &py), std::stod(zs, &pz)};
                if (px != xs.size() || py != ys.size() || pz != zs.size()) throw std::invalid_argument("trailing");
            } catch (const std::exception&) {
                throw Error(where, pw + ": control point " + std::to_string(i + 1) + " is not three numbers");
            }
            check_finite(cp[i], where, pw + " control point " + std::to_string(i + 1));
        }
        out.push_back(std::make_unique<BezierPatch>(int(nu), int(nv), std::move(cp)));
    }
    std::string rest;
    if (in >> rest) throw Error(where, "unexpected data after " + std::to_string(count) + " patches: '" + rest + "'");
    return out;
}

SurfaceList load_bpt(const std::string& path) { return parse_bpt(read_whole_file(path, "file"), path); }

SurfaceList parse_surfaces_json(const std::string& text, const std::string& where) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const std::exception& e) {
        throw Error(where, std::string("invalid JSON: ") + e.what());
    }
    auto vec3 = [&](const nlohmann::json& a, const std::string& what) {
        if (!a.is_array() || a.size() != 3 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number())
            throw Error(where, what + ": expected [x, y, z]");
        const glm::dvec3 p(a[0].get<double>(), a[1].get<double>(), a[2].get<double>());
        check_finite(p, where, what);
        return p;
    };
    auto number = [&](const nlohmann::json& s, const char* key, const std::string& what, double def, bool required) {
        if (!s.contains(key)) {
            if (required) throw Error(where, what + ": missing \"" + key + "\"");
            return def;
        }
        if (!s[key].is_number()) throw Error(where, what + ": \"" + key + "\" must be a number");
        return s[key].get<double>();
    };
    if (!j.is_object() || !j.contains("surfaces") || !j["surfaces"].is_array() || j["surfaces"].empty())
        throw Error(where, "expected an object with a non-empty \"surfaces\" array");
    SurfaceList out;
    for (std::size_t k = 0; k < j["surfaces"].size(); ++k) {
        const auto& s = j["surfaces"][k];
        const std::string what = "surface " + std::to_string(k);
        if (!s.is_object() || !s.contains("type") || !s["type"].is_string())
            throw Error(where, what + ": expected an object with a \"type\"");
        const std::string type = s["type"].get<std::string>();
        const glm::dvec3 c = s.contains("center") ? vec3(s["center"], what + " center") : glm::dvec3(0.0);
        try {
            if (type == "bezier") {
                if (!s.contains("degree") || !s["degree"].is_array() || s["degree"].size() != 2 ||
                    !s["degree"][0].is_number_integer() || !s["degree"][1].is_number_integer())
                    throw Error(where, what + ": \"degree\" must be [nu, nv]");
                const int nu = s["degree"][0].get<int>(), nv = s["degree"][1].get<int>();
                if (nu < 1 || nv < 1 || nu > 15 || nv > 15) throw Error(where, what + ": degrees must be 1..15");
                if (!s.contains("points") || !s["points"].is_array() || s["points"].size() != std::size_t((nu + 1) * (nv + 1)))
                    throw Error(where, what + ": \"points\" must hold (nu+1)(nv+1) control points");
                std::vector<glm::dvec3> cp;
                for (std::size_t i = 0; i < s["points"].size(); ++i)
                    cp.push_back(vec3(s["points"][i], what + " point " + std::to_string(i)));
                out.push_back(std::make_unique<BezierPatch>(nu, nv, std::move(cp)));
            } else if (type == "nurbs") {
                auto ints = [&](const char* key) {
                    if (!s.contains(key) || !s[key].is_array() || s[key].size() != 2 || !s[key][0].is_number_integer() ||
                        !s[key][1].is_number_integer())
                        throw Error(where, what + ": \"" + key + "\" must be two integers");
                    return std::array<int, 2>{s[key][0].get<int>(), s[key][1].get<int>()};
                };
                auto numbers = [&](const char* key) {
                    if (!s.contains(key) || !s[key].is_array()) throw Error(where, what + ": \"" + key + "\" must be an array");
                    std::vector<double> k;
                    for (const auto& x : s[key]) {
                        if (!x.is_number()) throw Error(where, what + ": \"" + key + "\" must hold numbers");
                        k.push_back(x.get<double>());
                    }
                    return k;
                };
                const auto deg = ints("degree"), count = ints("count");
                if (count[0] < 2 || count[1] < 2 || count[0] > 10000 || count[1] > 10000 ||
                    std::size_t(count[0]) * std::size_t(count[1]) > 4000000)
                    throw Error(where, what + ": bad \"count\"");
                if (!s.contains("points") || !s["points"].is_array() ||
                    s["points"].size() != std::size_t(count[0]) * std::size_t(count[1]))
                    throw Error(where, what + ": \"points\" must hold count[0] x count[1] control points");
                std::vector<glm::dvec3> pts;
                std::vector<double> wts;
                for (std::size_t i = 0; i < s["points"].size(); ++i) {
                    const auto& q = s["points"][i];
                    const std::string pw = what + " point " + std::to_string(i);
                    if (q.is_array() && q.size() == 4) {
                        if (!q[3].is_number()) throw Error(where, pw + ": the weight must be a number");
                        pts.push_back(vec3(nlohmann::json::array({q[0], q[1], q[2]}), pw));
                        wts.push_back(q[3].get<double>());
                    } else {
                        pts.push_back(vec3(q, pw));
                        wts.push_back(1.0);
                    }
                }
                out.push_back(std::make_unique<NurbsSurface>(deg[0], deg[1], numbers("knots_u"), numbers("knots_v"), count[0],
                                                             count[1], std::move(pts), std::move(wts)));
            } else if (type == "sphere") {
                out.push_back(std::make_unique<Sphere>(c, number(s, "radius", what, 1.0, true)));
            } else if (type == "torus" || type == "wavy_torus") {
                const bool wavy = type == "wavy_torus";
                const double a = wavy ? number(s, "amplitude", what, 0.3, false) : 0.0;
                const double w = wavy ? number(s, "waves", what, 6, false) : 0.0;
                if (w < 0 || w > 1000 || w != std::floor(w)) throw Error(where, what + ": \"waves\" must be an integer 0..1000");
                out.push_back(std::make_unique<Torus>(c, number(s, "R", what, 1.0, true), number(s, "r", what, 0.3, true), a, int(w)));
            } else {
                throw Error(where, what + ": unknown type '" + type + "' (expected bezier, nurbs, sphere, torus, wavy_torus)");
            }
        } catch (const Error& e) {
            const std::string m = e.what();
            if (m.rfind(where + ":", 0) == 0) throw;
            throw Error(where, what + ": " + m);
        }
    }
    if (j.contains("transparent")) {
        if (!j["transparent"].is_array()) throw Error(where, "\"transparent\" must be an array of surface indices");
        for (const auto& t : j["transparent"]) {
            if (!t.is_number_integer() || t.get<long long>() < 0 || t.get<long long>() >= (long long)out.size())
                throw Error(where, "\"transparent\": bad surface index");
            out[t.get<std::size_t>()]->transparent = true;
        }
    }
    return out;
}

SurfaceList load_surfaces_json(const std::string& path) { return parse_surfaces_json(read_whole_file(path, "file"), path); }

bool is_freeform_path(const std::string& path) {
    const std::string e = lower_ext(path);
    return e == "bpt" || e == "json";
}

SurfaceList load_surfaces(const std::string& path) {
    const std::string e = lower_ext(path);
    if (e == "bpt") return load_bpt(path);
    if (e == "json") return load_surfaces_json(path);
    throw Error(path, "unknown surface format (expected .bpt or .json)");
}

}  // namespace inkline::freeform
