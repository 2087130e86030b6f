#include "style/strokes.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include <glm/geometric.hpp>

namespace inkline {

ArcPolyline::ArcPolyline(std::vector<glm::dvec2> points) {
    p_.reserve(points.size());
    s_.reserve(points.size());
    for (const glm::dvec2& q : points) {
        if (!p_.empty() && q == p_.back()) continue;
        s_.push_back(p_.empty() ? 0.0 : s_.back() + glm::distance(p_.back(), q));
        p_.push_back(q);
    }
}

std::size_t ArcPolyline::segment(double s) const {
    if (p_.size() < 2) return 0;
    const auto it = std::upper_bound(s_.begin(), s_.end(), s);
    const std::size_t i = std::size_t(std::max<std::ptrdiff_t>(1, it - s_.begin()));
    return std::min(i, p_.size() - 1) - 1;
}

glm::dvec2 ArcPolyline::at(double s) const {
    if (p_.empty()) return glm::dvec2(0.0);
    if (p_.size() == 1 || s <= 0.0) return p_.front();
    if (s >= s_.back()) return p_.back();
    const std::size_t i = segment(s);
    const double t = (s - s_[i]) / (s_[i + 1] - s_[i]);
    return p_[i] + t * (p_[i + 1] - p_[i]);
}

glm::dvec2 ArcPolyline::tangent(double s) const {
    if (p_.size() < 2) return glm::dvec2(0.0);
    const std::size_t i = segment(s);
    const glm::dvec2 d = glm::normalize(p_[i + 1] - p_[i]);
    // At an interior vertex (within a tiny fraction of a pixel), average with the previous segment.
    if (i > 0 && std::abs(s - s_[i]) < 1e-9) {
        const glm::dvec2 sum = d + glm::normalize(p_[i] - p_[i - 1]);
        if (glm::length(sum) > 1e-12) return glm::normalize(sum);
    }
    return d;
}

std::vector<glm::dvec2> ArcPolyline::resample(double spacing) const {
    if (p_.size() < 2 || !(spacing > 0.0)) return p_;
    const double L = length();
    const std::size_t n = std::size_t(std::ceil(L / spacing - 1e-9));
    std::vector<glm::dvec2> out;
    out.reserve(n + 1);
    std::size_t i = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const double s = double(k) * spacing;
        while (i + 2 < p_.size() && s_[i + 1] <= s) ++i;
        const double t = (s - s_[i]) / (s_[i + 1] - s_[i]);
        out.push_back(p_[i] + std::clamp(t, 0.0, 1.0) * (p_[i + 1] - p_[i]));
    }
    out.push_back(p_.back());
    return out;
}

namespace {

bool usable(const Piece& p, bool hidden) {
    if (p.points.size() < 2 || p.qi < 0 || (p.qi > 0 && !hidden)) return false;
    return std::all_of(p.points.begin(), p.points.end(),
                       [](const glm::dvec2& q) { return std::isfinite(q.x) && std::isfinite(q.y); });
}

double polyline_length(const std::vector<glm::dvec2>& p) {
    double l = 0.0;
    for (std::size_t k = 1; k < p.size(); ++k) l += glm::distance(p[k - 1], p[k]);
    return l;
}

// Direction of travel leaving piece p through its start (end = 0) or its end (end = 1): from the
// point `look` px along it (or its far end) to the tip, so that a tiny last segment, as cuts at
// crossings leave, does not decide the turn. (0, 0) if the piece has zero length.
glm::dvec2 out_direction(const Piece& p, int end, double look = 2.0) {
    const std::size_t n = p.points.size();
    const auto at = [&](std::size_t k) -> const glm::dvec2& { return end ? p.points[n - 1 - k] : p.points[k]; };
    const glm::dvec2 tip = at(0);
    double s = 0.0;
    glm::dvec2 q = tip;
    for (std::size_t k = 1; k < n && s < look; ++k) {
        const double len = glm::distance(at(k - 1), at(k));
        q = s + len > look ? at(k - 1) + (look - s) / len * (at(k) - at(k - 1)) : at(k);
        s += len;
    }
    return q != tip ? glm::normalize(tip - q) : glm::dvec2(0.0);
}

// Endpoint e = 2 * piece + end. Returns partner[e]: the endpoint it is joined to, or -1. Joins
// pair ends that nearly coincide, of one kind, QI and object, best first: the same curve (any
// turn, smallest first), then the smallest turn up to the limit, then specks to whatever is left.
std::vector<long long> pair_ends(const Drawing& d, const std::vector<std::uint32_t>& used,
                                 const std::vector<double>& length, const ChainOptions& o) {
    std::vector<long long> partner(2 * d.pieces.size(), -1);
    const auto tip = [&](std::size_t e) -> const glm::dvec2& {
        const Piece& p = d.pieces[e / 2];
        return e % 2 ? p.points.back() : p.points.front();
    };
    // Ends sorted by x; a sweep pairs those within the join distance (they nearly coincide).
    std::vector<std::pair<double, std::size_t>> ends;
    ends.reserve(2 * used.size());
    for (std::uint32_t i : used)
        for (int end = 0; end < 2; ++end) ends.emplace_back(tip(2 * i + end).x, 2 * i + end);
    std::sort(ends.begin(), ends.end());
    const double max_turn = o.max_turn_degrees * M_PI / 180.0;
    std::vector<std::tuple<int, double, std::size_t, std::size_t>> cand;  // (class, turn, a, b)
    for (std::size_t i = 0; i < ends.size(); ++i) {
        for (std::size_t j = i + 1; j < ends.size() && ends[j].first - ends[i].first <= o.join_distance; ++j) {
            const std::size_t a = std::min(ends[i].second, ends[j].second), b = std::max(ends[i].second, ends[j].second);
            const Piece &pa = d.pieces[a / 2], &pb = d.pieces[b / 2];
            if (pa.kind != pb.kind || pa.qi != pb.qi || pa.object != pb.object) continue;
            if (glm::distance(tip(a), tip(b)) > o.join_distance) continue;
            // Leaving a, entering b: travel direction inside b is -out(b).
            const glm::dvec2 u = out_direction(pa, int(a % 2)), v = -out_direction(pb, int(b % 2));
            const double turn = std::acos(std::clamp(glm::dot(u, v), -1.0, 1.0));
            const bool speck = length[a / 2] < o.speck_length || length[b / 2] < o.speck_length;
            const int cls = pa.curve == pb.curve ? 0 : turn <= max_turn ? 1 : speck ? 2 : -1;
            if (cls >= 0) cand.emplace_back(cls, turn, a, b);
        }
    }
    std::sort(cand.begin(), cand.end());
    for (const auto& [cls, turn, a, b] : cand) {
        if (partner[a] >= 0 || partner[b] >= 0) continue;
        partner[a] = (long long)b;
        partner[b] = (long long)a;
    }
    return partner;
}

}  // namespace

std::vector<Stroke> chain_strokes(const Drawing& d, const ChainOptions& o, const PointAttributes* attr,
                                  ChainStats* stats) {
    const std::size_t n = d.pieces.size();
    std::vector<std::uint32_t> used;
    std::vector<double> length(n, 0.0);
    for (std::uint32_t i = 0; i < n; ++i)
        if (usable(d.pieces[i], o.hidden)) used.push_back(i), length[i] = polyline_length(d.pieces[i].points);
    const std::vector<long long> partner = o.join ? pair_ends(d, used, length, o) : std::vector<long long>(2 * n, -1);
    ChainStats st;

    std::vector<char> done(n, 0);
    std::vector<Stroke> out;
    for (std::uint32_t i : used) {
        if (done[i]) continue;
        // Walk back from piece i's start to the first piece of its chain (or once around a loop).
        std::size_t first = i;
        int first_end = 0;  // the endpoint of `first` where the stroke starts
        bool closed = false;
        for (;;) {
            const long long q = partner[2 * first + first_end];
            if (q < 0) break;
            const std::size_t p = std::size_t(q) / 2;
            first_end = 1 - int(q % 2);  // we enter p through q, so its other end is further back
            first = p;
            if (first == i && first_end == 0) {
                closed = true;
                break;
            }
        }
        Stroke s;
        s.kind = d.pieces[i].kind;
        s.qi = d.pieces[i].qi;
        s.object = d.pieces[i].object;
        s.closed = closed;
        std::vector<glm::dvec2> pts;
        std::vector<double> depth, tone;
        bool with_attr = attr != nullptr;
        std::size_t cur = first;
        int start_end = first_end;
        for (;;) {
            done[cur] = 1;
            s.pieces.push_back(std::uint32_t(cur));
            const auto& P = d.pieces[cur].points;
            const std::size_t skip = pts.empty() ? 0 : 1;
            if (start_end == 0)
                pts.insert(pts.end(), P.begin() + skip, P.end());
            else
                pts.insert(pts.end(), P.rbegin() + skip, P.rend());
            with_attr = with_attr && cur < attr->depth.size() && attr->depth[cur].size() == P.size() &&
                        cur < attr->tone.size() && attr->tone[cur].size() == P.size();
            if (with_attr) {
                const auto& D = attr->depth[cur];
                const auto& L = attr->tone[cur];
                if (start_end == 0) {
                    depth.insert(depth.end(), D.begin() + skip, D.end());
                    tone.insert(tone.end(), L.begin() + skip, L.end());
                } else {
                    depth.insert(depth.end(), D.rbegin() + skip, D.rend());
                    tone.insert(tone.end(), L.rbegin() + skip, L.rend());
                }
            }
            const long long q = partner[2 * cur + (1 - start_end)];
            if (q < 0) break;
            const std::size_t next = std::size_t(q) / 2;
            if (done[next]) break;  // came around a loop
            cur = next;
            start_end = int(q % 2);
        }
        if (closed && !pts.empty()) pts.back() = pts.front();
        if (with_attr) {
            // Drop consecutive duplicates here, with their attributes, so the path keeps every point.
            std::size_t k = 0;
            for (std::size_t i = 0; i < pts.size(); ++i) {
                if (k > 0 && pts[i] == pts[k - 1]) continue;
                pts[k] = pts[i];
                depth[k] = depth[i];
                tone[k] = tone[i];
                ++k;
            }
            pts.resize(k);
            depth.resize(k);
            tone.resize(k);
            s.depth = std::move(depth);
            s.tone = std::move(tone);
        }
        s.path = ArcPolyline(std::move(pts));
        if (!o.keep_specks && s.path.length() < o.speck_length) {
            st.specks_dropped += s.pieces.size();
            continue;
        }
        out.push_back(std::move(s));
    }
    if (stats) *stats = st;
    return out;
}

}  // namespace inkline
