#include "model/reorder.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <exception>
#include <functional>
#include <numeric>
#include <random>
#include <system_error>
#include <thread>
#include <utility>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>
#include <glm/common.hpp>

namespace inkline {
namespace {
constexpr int kKeyBits = 21;  // per axis: 63-bit keys

// Skilling's transform from axes to the transposed Hilbert index, without branches (so that the
// loop over a block of points vectorizes): per level, invert or exchange the lower bits, then
// Gray-encode.
inline void axes_to_transpose(std::uint32_t& x0, std::uint32_t& x1, std::uint32_t& x2) {
    for (std::uint32_t q = 1u << (kKeyBits - 1); q > 1; q >>= 1) {
        const std::uint32_t p = q - 1;
        x0 ^= (0u - std::uint32_t((x0 & q) != 0)) & p;
        const std::uint32_t m1 = 0u - std::uint32_t((x1 & q) != 0);
        const std::uint32_t t1 = (x0 ^ x1) & p & ~m1;
        x0 ^= (p & m1) | t1, x1 ^= t1;
        const std::uint32_t m2 = 0u - std::uint32_t((x2 & q) != 0);
        const std::uint32_t t2 = (x0 ^ x2) & p & ~m2;
        x0 ^= (p & m2) | t2, x2 ^= t2;
    }
    x1 ^= x0, x2 ^= x1;
    // t = XOR of (q - 1) over the set bits q > 1 of x2: bit j of t is the parity of x2's bits
    // above j (and above bit 0).
    std::uint32_t t = x2 & ~1u;
    t ^= t >> 1, t ^= t >> 2, t ^= t >> 4, t ^= t >> 8, t ^= t >> 16;
    t >>= 1;
    x0 ^= t, x1 ^= t, x2 ^= t;
}

// Bit i of v (i < 21) to bit 3i.
inline std::uint64_t spread_by_3(std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

struct Keyed {
    std::uint64_t key;
    std::uint32_t index;
};

// Keys of points point(0) .. point(n - 1), in blocks: the transform runs over a block's
// coordinates in arrays (vectorized), then the bits are interleaved.
template <class PointOf>
std::vector<Keyed> hilbert_keys(std::size_t n, const HilbertGrid& grid, PointOf point) {
    constexpr std::size_t kBlock = 256;
    std::vector<Keyed> out(n);
    std::uint32_t x[kBlock], y[kBlock], z[kBlock];
    for (std::size_t b = 0; b < n; b += kBlock) {
        const std::size_t m = std::min(kBlock, n - b);
        for (std::size_t j = 0; j < m; ++j) {
            const glm::dvec3 p = point(b + j);
            x[j] = grid.cell(p, 0), y[j] = grid.cell(p, 1), z[j] = grid.cell(p, 2);
        }
        for (std::size_t j = 0; j < m; ++j) axes_to_transpose(x[j], y[j], z[j]);
        for (std::size_t j = 0; j < m; ++j)
            out[b + j] = {spread_by_3(x[j]) << 2 | spread_by_3(y[j]) << 1 | spread_by_3(z[j]), std::uint32_t(b + j)};
    }
    return out;
}

// Stable least-significant-digit radix sort by key, 11 bits a pass (6 passes cover 63 bits; a
// pass whose digit is the same for every key is skipped). Stable, so equal keys keep the input
// order.
void radix_sort(std::vector<Keyed>& items) {
    constexpr int kDigitBits = 11, kPasses = 6;
    constexpr std::size_t kBuckets = std::size_t(1) << kDigitBits;
    std::vector<std::uint32_t> count(kPasses * kBuckets, 0);
    for (const Keyed& k : items)
        for (int pass = 0; pass < kPasses; ++pass) ++count[pass * kBuckets + ((k.key >> (pass * kDigitBits)) & (kBuckets - 1))];
    std::vector<Keyed> scratch(items.size());
    for (int pass = 0; pass < kPasses; ++pass) {
        std::uint32_t* c = &count[pass * kBuckets];
        if (std::find(c, c + kBuckets, std::uint32_t(items.size())) != c + kBuckets) continue;
        std::uint32_t sum = 0;
        for (std::size_t d = 0; d < kBuckets; ++d) sum += std::exchange(c[d], sum);
        const int shift = pass * kDigitBits;
        for (const Keyed& k : items) scratch[c[(k.key >> shift) & (kBuckets - 1)]++] = k;
        items.swap(scratch);
    }
}

std::vector<std::uint32_t> key_order(std::vector<Keyed> items) {
    radix_sort(items);
    std::vector<std::uint32_t> order(items.size());
    for (std::size_t i = 0; i < items.size(); ++i) order[i] = items[i].index;
    return order;
}

glm::dvec3 centroid(const TriangleMesh& mesh, std::size_t f) {
    const auto& t = mesh.triangles[f];
    return (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
}

// The mesh renumbered: vertex i of the result is vertex_at[i] of the input, face i face_at[i].
// With threads > 1 (and faces enough) the corners' pairing is renumbered on a thread of its own,
// beside the positions and triangles.
TriangleMesh renumbered(TriangleMesh mesh, const std::vector<std::uint32_t>& vertex_at,
                        const std::vector<std::uint32_t>& face_at, int threads = 1) {
    const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
    // The corners' pairing, renumbered with the faces (corner k of a face stays corner k); empty
    // when it is not that of the triangles.
    std::vector<std::uint32_t> mates;
    bool mates_made = false;
    const auto renumber_mates = [&] {
        if (mesh.corner_mates.size() != 3 * nf || mesh.corner_mates_of != triangles_key(mesh.triangles)) return;
        mates_made = true;
        std::vector<std::uint32_t> new_face(nf);
        for (std::uint32_t i = 0; i < nf; ++i) new_face[face_at[i]] = i;
        mates.resize(3 * nf);
        for (std::uint32_t i = 0; i < nf; ++i)
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::uint32_t m = mesh.corner_mates[3 * face_at[i] + k];
                mates[3 * i + k] = m == kNoCorner ? m : 3 * new_face[m / 3] + m % 3;
            }
    };
    std::thread mates_thread;
    struct Joined {  // (waited for however this function ends)
        std::thread& t;
        ~Joined() {
            if (t.joinable()) t.join();
        }
    } joined{mates_thread};
    std::exception_ptr mates_failure;
    if (threads > 1 && nf >= 16384) {
        try {
            mates_thread = std::thread([&] {
                try {
                    renumber_mates();
                } catch (...) {
                    mates_failure = std::current_exception();
                }
            });
        } catch (const std::system_error&) {
            // No thread: this one does it below.
        }
    }
    std::vector<std::uint32_t> new_index(nv);
    std::vector<glm::dvec3> positions(nv);
    for (std::uint32_t i = 0; i < nv; ++i) {
        new_index[vertex_at[i]] = i;
        positions[i] = mesh.positions[vertex_at[i]];
    }
    std::vector<std::array<std::uint32_t, 3>> triangles(nf);
    std::vector<std::uint32_t> face_object(mesh.face_object.empty() ? 0 : nf);
    for (std::size_t i = 0; i < nf; ++i) {
        const auto& t = mesh.triangles[face_at[i]];
        triangles[i] = {new_index[t[0]], new_index[t[1]], new_index[t[2]]};
        if (!face_object.empty()) face_object[i] = mesh.face_object[face_at[i]];
    }
    if (mates_thread.joinable()) mates_thread.join();
    else renumber_mates();
    if (mates_failure) std::rethrow_exception(mates_failure);
    if (mates_made) {
        mesh.corner_mates = std::move(mates);
        mesh.corner_mates_of = triangles_key(triangles);
    } else {
        mesh.corner_mates.clear();
    }
    mesh.positions = std::move(positions);
    mesh.triangles = std::move(triangles);
    mesh.face_object = std::move(face_object);
    return mesh;
}

// CGAL's median-policy order of points (with their indices beside them, not through an index map).
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Item = std::pair<K::Point_3, std::uint32_t>;
std::vector<std::uint32_t> median_order(std::size_t n, const std::function<glm::dvec3(std::size_t)>& point) {
    std::vector<Item> items;
    items.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        const glm::dvec3 p = point(i);
        items.emplace_back(K::Point_3(p.x, p.y, p.z), i);
    }
    using Traits = CGAL::Spatial_sort_traits_adapter_3<K, CGAL::First_of_pair_property_map<Item>>;
    CGAL::hilbert_sort(items.begin(), items.end(), Traits(), CGAL::Hilbert_sort_median_policy());
    std::vector<std::uint32_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = items[i].second;
    return order;
}
}  // namespace

HilbertGrid::HilbertGrid(const glm::dvec3& lo, const glm::dvec3& hi) : lo_(lo) {
    for (int a = 0; a < 3; ++a) scale_[a] = hi[a] > lo[a] ? double(1u << kKeyBits) / (hi[a] - lo[a]) : 0.0;
}

HilbertGrid::HilbertGrid(const glm::dvec3* points, std::size_t count) {
    if (count == 0) return;
    glm::dvec3 lo = points[0], hi = points[0];
    for (std::size_t i = 0; i < count; ++i) lo = glm::min(lo, points[i]), hi = glm::max(hi, points[i]);
    *this = HilbertGrid(lo, hi);
}

void HilbertGrid::keys(const glm::dvec3* points, std::size_t count, std::uint64_t* keys) const {
    const std::vector<Keyed> keyed = hilbert_keys(count, *this, [points](std::size_t i) { return points[i]; });
    for (std::size_t i = 0; i < count; ++i) keys[i] = keyed[i].key;
}

std::uint32_t HilbertGrid::cell(const glm::dvec3& p, int axis) const {
    // (clamped: a centroid may round past the box, and the box's top maps to 2^21)
    return std::uint32_t(std::clamp((p[axis] - lo_[axis]) * scale_[axis], 0.0, double((1u << kKeyBits) - 1)));
}

std::uint64_t HilbertGrid::key(const glm::dvec3& p) const { return hilbert_key(cell(p, 0), cell(p, 1), cell(p, 2)); }

std::uint64_t hilbert_key(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    axes_to_transpose(x, y, z);
    return spread_by_3(x) << 2 | spread_by_3(y) << 1 | spread_by_3(z);
}

TriangleMesh hilbert_ordered(TriangleMesh mesh, int threads) {
    // The vertices' and the faces' keys and sorts are independent: with a second thread they run
    // side by side, the same orders either way. Below this many faces a thread's start costs
    // about what it saves.
    constexpr std::size_t kFacesForThread = 16384;
    const HilbertGrid grid(mesh.positions.data(), mesh.positions.size());
    std::vector<std::uint32_t> vertex_at;
    std::exception_ptr vertex_failure;
    std::thread vertex_thread;
    const auto sort_vertices = [&] {
        try {
            vertex_at = key_order(hilbert_keys(mesh.positions.size(), grid, [&](std::size_t i) { return mesh.positions[i]; }));
        } catch (...) {
            vertex_failure = std::current_exception();
        }
    };
    if (threads > 1 && mesh.triangles.size() >= kFacesForThread) {
        try {
            vertex_thread = std::thread(sort_vertices);
        } catch (const std::system_error&) {
            // No thread to be had: this one sorts both.
        }
    }
    const std::vector<std::uint32_t> face_at =
        key_order(hilbert_keys(mesh.triangles.size(), grid, [&](std::size_t f) { return centroid(mesh, f); }));
    if (vertex_thread.joinable()) vertex_thread.join();
    else sort_vertices();
    if (vertex_failure) std::rethrow_exception(vertex_failure);
    return renumbered(std::move(mesh), vertex_at, face_at, threads);
}

TriangleMesh hilbert_ordered(TriangleMesh mesh, const HilbertOrders& known, int threads) {
    return renumbered(std::move(mesh), known.vertex_at, known.face_at, threads);
}

struct HilbertOrderAhead::Impl {
    std::thread thread;
    std::mutex mutex;
    std::condition_variable read_cv;
    bool read = false;     // the thread is done reading the mesh
    bool changed = false;  // the owner announced a change: the orders are of another mesh
    HilbertOrders orders;
    std::exception_ptr failure;
    // The faces' keys, sorted by whichever thread claims them first: the owner, when take() finds
    // them unsorted, sorts them itself rather than waiting (the thread sorts the vertices' first).
    std::vector<Keyed> face_keys;
    std::atomic<bool> face_sort_claimed{false};

    void run(const glm::dvec3* positions, std::size_t nv, const std::array<std::uint32_t, 3>* triangles,
             std::size_t nf) {
        std::vector<Keyed> vertex_keys;
        try {
            // The same keys as hilbert_ordered's (its grid, its centroids).
            const HilbertGrid grid(positions, nv);
            vertex_keys = hilbert_keys(nv, grid, [&](std::size_t i) { return positions[i]; });
            face_keys = hilbert_keys(nf, grid, [&](std::size_t f) {
                const auto& t = triangles[f];
                return (positions[t[0]] + positions[t[1]] + positions[t[2]]) / 3.0;
            });
        } catch (...) {
            failure = std::current_exception();
        }
        {
            std::lock_guard<std::mutex> lock(mutex);
            read = true;
            if (changed || failure) {
                read_cv.notify_all();
                return;
            }
        }
        read_cv.notify_all();
        try {
            orders.vertex_at = key_order(std::move(vertex_keys));
            if (!face_sort_claimed.exchange(true)) orders.face_at = key_order(std::move(face_keys));
        } catch (...) {
            failure = std::current_exception();
        }
    }
};

HilbertOrderAhead::HilbertOrderAhead() : impl_(std::make_unique<Impl>()) {}

HilbertOrderAhead::~HilbertOrderAhead() {
    if (impl_->thread.joinable()) impl_->thread.join();
}

void HilbertOrderAhead::start(const TriangleMesh& mesh) {
    // Below this many faces the keys take about what a thread's start costs.
    constexpr std::size_t kFacesForThread = 16384;
    if (impl_->thread.joinable() || impl_->read || mesh.triangles.size() < kFacesForThread) return;
    try {
        impl_->thread = std::thread(&Impl::run, impl_.get(), mesh.positions.data(), mesh.positions.size(),
                                    mesh.triangles.data(), mesh.triangles.size());
    } catch (const std::system_error&) {
        impl_->read = impl_->changed = true;  // no thread: nothing made, nothing to wait for
    }
}

void HilbertOrderAhead::before_change() {
    std::unique_lock<std::mutex> lock(impl_->mutex);
    impl_->changed = true;
    if (impl_->thread.joinable()) impl_->read_cv.wait(lock, [this] { return impl_->read; });
}

std::optional<HilbertOrders> HilbertOrderAhead::take() {
    Impl& im = *impl_;
    if (!im.thread.joinable()) return std::nullopt;
    bool keys_made = false;
    {
        std::unique_lock<std::mutex> lock(im.mutex);
        im.read_cv.wait(lock, [&im] { return im.read; });
        keys_made = !im.changed && !im.failure;
    }
    std::exception_ptr own_failure;
    if (keys_made && !im.face_sort_claimed.exchange(true)) {
        try {
            std::vector<std::uint32_t> face_at = key_order(std::move(im.face_keys));
            im.thread.join();  // (the thread writes orders.vertex_at only)
            im.orders.face_at = std::move(face_at);
        } catch (...) {
            own_failure = std::current_exception();
        }
    }
    if (im.thread.joinable()) im.thread.join();
    if (im.changed || im.failure || own_failure) return std::nullopt;  // (a failure: hilbert_ordered meets it again)
    return std::move(im.orders);
}

TriangleMesh hilbert_ordered_median(TriangleMesh mesh) {
    const std::vector<std::uint32_t> vertex_at =
        median_order(mesh.positions.size(), [&](std::size_t i) { return mesh.positions[i]; });
    const std::vector<std::uint32_t> face_at =
        median_order(mesh.triangles.size(), [&](std::size_t f) { return centroid(mesh, f); });
    return renumbered(std::move(mesh), vertex_at, face_at);
}

TriangleMesh shuffled_numbering(TriangleMesh mesh, std::uint32_t seed) {
    std::mt19937 rng(seed);
    const std::size_t nv = mesh.positions.size(), nf = mesh.triangles.size();
    std::vector<std::uint32_t> vertex_at(nv), face_at(nf), new_index(nv);
    std::iota(vertex_at.begin(), vertex_at.end(), 0u);
    std::iota(face_at.begin(), face_at.end(), 0u);
    std::shuffle(vertex_at.begin(), vertex_at.end(), rng);
    std::shuffle(face_at.begin(), face_at.end(), rng);
    std::vector<glm::dvec3> positions(nv);
    for (std::uint32_t i = 0; i < nv; ++i) new_index[vertex_at[i]] = i, positions[i] = mesh.positions[vertex_at[i]];
    std::vector<std::array<std::uint32_t, 3>> triangles(nf);
    std::vector<std::uint32_t> face_object(mesh.face_object.empty() ? 0 : nf);
    for (std::size_t i = 0; i < nf; ++i) {
        const auto& t = mesh.triangles[face_at[i]];
        const unsigned r = rng() % 3;
        triangles[i] = {new_index[t[r]], new_index[t[(r + 1) % 3]], new_index[t[(r + 2) % 3]]};
        if (!face_object.empty()) face_object[i] = mesh.face_object[face_at[i]];
    }
    mesh.positions = std::move(positions);
    mesh.triangles = std::move(triangles);
    mesh.face_object = std::move(face_object);
    mesh.corner_mates.clear();
    return mesh;
}

}  // namespace inkline
