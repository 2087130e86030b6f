#include "detail/moving_self_intersections.hpp"

#include <algorithm>
#include <array>
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
        // At most about two cells a box: moving faces scattered over the whole model would
        // otherwise ask for a million cells, whose zeroing and prefix sum cost more than the pairs.
        const double most_cells = 2.0 * double(boxes_.size());
        double cells = 1.0;
        for (int k = 0; k < 3; ++k) cells *= size > 0.0 ? std::clamp(std::ceil(extent[k] / size), 1.0, 128.0) : 1.0;
        if (cells > most_cells) size *= std::cbrt(cells / most_cells);
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

    // fn(i) for each box i that meets b, once each: in the one cell that holds the lower corner of
    // the two boxes' overlap (it lies in both boxes, so both are listed there).
    template <class Fn>
    void for_each_meeting(const Box& b, Fn&& fn) const {
        if (!b.meets(all_)) return;
        const auto [lo, hi] = cell_range(b);
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) {
                    const std::size_t c = cell(x, y, z);
                    for (std::uint32_t k = begin_[c]; k < begin_[c + 1]; ++k) {
                        const Box& o = boxes_[items_[k]];
                        if (!b.meets(o)) continue;
                        const glm::dvec3 corner = glm::max(b.lo, o.lo);
                        if (clamp_cell(corner.x, 0) == x && clamp_cell(corner.y, 1) == y && clamp_cell(corner.z, 2) == z)
                            fn(items_[k]);
                    }
                }
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

// The moving faces (with a moved corner), and each pair of a moving face and a face whose box
// meets its own, once (two moving faces: listed when the lower one is streamed).
void candidate_pairs(const MeshTopology& mesh, const std::vector<std::uint8_t>& moved_vertex, std::vector<std::uint32_t>& moving,
                     std::vector<std::array<std::uint32_t, 2>>& pairs) {
    const std::size_t nf = mesh.face_count();
    std::vector<std::uint8_t> is_moving(nf, 0);
    std::vector<Box> boxes;
    for (std::uint32_t f = 0; f < nf; ++f) {
        const auto& t = mesh.faces[f];
        if (moved_vertex[t[0]] || moved_vertex[t[1]] || moved_vertex[t[2]]) {
            is_moving[f] = 1;
            moving.push_back(f);
            boxes.push_back(face_box(mesh, f));
        }
    }
    if (moving.empty()) return;
    const MovingGrid grid(std::move(boxes));
    for (std::uint32_t g = 0; g < nf; ++g)
        grid.for_each_meeting(face_box(mesh, g), [&](std::uint32_t i) {
            const std::uint32_t f = moving[i];
            if (f != g && (!is_moving[g] || g < f)) pairs.push_back({f, g});
        });
}

}  // namespace

SelfIntersections self_intersections_of_moving(const MeshTopology& mesh, const std::vector<std::uint8_t>& moved_vertex,
                                               MovingSearchStats* stats) {
    std::vector<std::uint32_t> moving;
    std::vector<std::array<std::uint32_t, 2>> pairs;
    candidate_pairs(mesh, moved_vertex, moving, pairs);
    if (stats) {
        std::vector<std::uint8_t> met(mesh.face_count(), 0);
        for (const auto& [f, g] : pairs) met[f] = met[g] = 1;
        for (const std::uint32_t f : moving) met[f] = 1;
        *stats = {moving.size(), std::size_t(std::count(met.begin(), met.end(), std::uint8_t(1))), pairs.size()};
    }
    return self_intersections_among(mesh, moving, pairs);
}

}  // namespace inkline
