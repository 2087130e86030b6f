#include "style/offsets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/error.hpp"
#include "core/files.hpp"
#include "style/strokes.hpp"

namespace inkline {

namespace {

bool parse_double(const std::string& s, double& v) {
    char* end = nullptr;
    v = std::strtod(s.c_str(), &end);
    return !s.empty() && *end == '\0' && std::isfinite(v);
}

}  // namespace

OffsetTable parse_offset_table(const std::string& text, const std::string& file) {
    OffsetTable t;
    std::istringstream in(text);
    std::string line;
    int number = 0;
    bool pending_break = false, trailing_break = false;
    const auto fail = [&](const std::string& what) -> Error {
        return Error(file + ":" + std::to_string(number), what);
    };
    while (std::getline(in, line)) {
        ++number;
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        std::istringstream words(line);
        std::vector<std::string> w;
        for (std::string s; words >> s;) w.push_back(s);
        if (w.empty()) continue;
        if (w[0] == "period") {
            double p = 0;
            if (w.size() != 2 || !parse_double(w[1], p) || !(p >= 0.1))
                throw fail("'period' expects one number of px, at least 0.1");
            if (t.period > 0) throw fail("'period' given twice");
            t.period = p;
        } else if (w[0] == "break") {
            if (w.size() != 1) throw fail("'break' takes no value");
            pending_break = true;
        } else {
            OffsetTable::Vertex v;
            if (w.size() != 3 || !parse_double(w[0], v.t) || !parse_double(w[1], v.vx) || !parse_double(w[2], v.vy))
                throw fail("expected 't vx vy' (three numbers), 'period P' or 'break', got '" + line + "'");
            if (v.t < 0 || v.t > 1) throw fail("t must be in [0, 1], got " + w[0]);
            if (std::abs(v.vx) > kMaxOffsetPx || std::abs(v.vy) > kMaxOffsetPx)
                throw fail("offsets must be within +-1000 px, got '" + line + "'");
            if (t.vertices.size() == kMaxOffsetVertices) throw fail("more than 1000 vertices");
            if (!t.vertices.empty() && v.t < t.vertices.back().t)
                throw fail("t must not decrease (" + w[0] + " after " + std::to_string(t.vertices.back().t) + ")");
            v.break_before = pending_break;
            pending_break = false;
            t.vertices.push_back(v);
        }
        trailing_break = pending_break;
    }
    if (!(t.period > 0)) throw Error(file, "no 'period' line (expected 'period P', P >= 0.1 px)");
    if (t.vertices.size() < 2) throw Error(file, "an offset table needs at least two vertices 't vx vy'");
    if (double(t.vertices.size()) > kMaxOffsetVerticesPerPx * t.period)
        throw Error(file, std::to_string(t.vertices.size()) + " vertices in a period of " + std::to_string(t.period) +
                              " px (at most 100 per px of period)");
    // A break after the last vertex leaves repetitions unconnected, as one before the first does.
    if (trailing_break) t.vertices.front().break_before = true;
    const auto slash = file.find_last_of('/');
    t.name = slash == std::string::npos ? file : file.substr(slash + 1);
    if (const auto dot = t.name.find_last_of('.'); dot != std::string::npos && dot > 0) t.name.erase(dot);
    return t;
}

OffsetTable load_offset_table(const std::string& path) {
    return parse_offset_table(read_whole_file(path, "offset table"), path);
}

std::vector<OffsetRun> apply_offsets(const ArcPolyline& spine, const OffsetTable& table, double scale,
                                     double period, double spacing) {
    std::vector<OffsetRun> runs;
    const double L = spine.length();
    if (spine.size() < 2 || table.vertices.size() < 2) return runs;
    if (!(period > 0)) period = table.period;
    if (!(spacing > 0)) spacing = period / 8;
    const auto emit = [&](double s, double vx, double vy, bool new_run) {
        const glm::dvec2 p = spine.at(s), T = spine.tangent(s), N(-T.y, T.x);
        const glm::dvec2 q = p + scale * (vx * T + vy * N);
        if (new_run || runs.empty()) runs.emplace_back();
        runs.back().points.push_back(q);
        runs.back().arc.push_back(std::min(s, L));
    };
    const auto& V = table.vertices;
    bool have_prev = false;
    double ps = 0, pvx = 0, pvy = 0;  // previous vertex emitted
    [&] {  // returns at the end of the spine
    for (long rep = 0;; ++rep) {
        const double base = double(rep) * period;
        if (base > L) return;
        for (std::size_t i = 0; i < V.size(); ++i) {
            double s = base + V[i].t * period, vx = V[i].vx, vy = V[i].vy;
            const bool broken = V[i].break_before || !have_prev;
            if (s > L) {
                // Cut the last segment at the end of the spine.
                if (!broken && s > ps) {
                    const double f = (L - ps) / (s - ps);
                    vx = pvx + f * (vx - pvx);
                    vy = pvy + f * (vy - pvy);
                    const int n = int(std::ceil((L - ps) / spacing));
                    for (int k = 1; k <= n; ++k) {
                        const double g = double(k) / n;
                        emit(ps + g * (L - ps), pvx + g * (vx - pvx), pvy + g * (vy - pvy), false);
                    }
                }
                return;
            }
            if (broken) {
                emit(s, vx, vy, true);
            } else if (s == ps && vx == pvx && vy == pvy) {
                continue;  // the seam of a table ending where it starts
            } else {
                const int n = std::max(1, int(std::ceil((s - ps) / spacing)));
                for (int k = 1; k <= n; ++k) {
                    const double g = double(k) / n;
                    emit(ps + g * (s - ps), pvx + g * (vx - pvx), pvy + g * (vy - pvy), false);
                }
            }
            have_prev = true;
            ps = s;
            pvx = vx;
            pvy = vy;
        }
    }
    }();
    // A repetition that starts exactly at the end of the spine leaves a lone point.
    runs.erase(std::remove_if(runs.begin(), runs.end(), [](const OffsetRun& r) { return r.points.size() < 2; }),
               runs.end());
    return runs;
}

}  // namespace inkline
