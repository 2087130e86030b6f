#include "features/facing.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/predicates.hpp"
#include "features/facing_kernels.hpp"

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
    const glm::dvec3 v = ortho ? -camera.forward() : camera.eye() - mesh.facing_origin;
    const double e[3] = {v.x, v.y, v.z};
    bind(mesh, e, ortho ? 0.0 : 1.0);
}

void FacingFilter::bind(const MeshTopology& mesh, const double e[3], double wv) {
    const bool ortho = wv == 0.0;
    ex = float(e[0]);
    ey = float(e[1]);
    ez = float(e[2]);
    w = ortho ? 0.0f : 1.0f;
    const double l1 = std::abs(e[0]) + std::abs(e[1]) + std::abs(e[2]);
    bound = float(0x1p-18 * (l1 + (ortho ? 0.0 : mesh.facing_radius)) + 1e-36);
    if (!std::isfinite(ex) || !std::isfinite(ey) || !std::isfinite(ez) || !std::isfinite(bound))
        bound = INFINITY;  // out of float range: every face goes to the exact test
}

void FaceFacing::bind(const MeshTopology& mesh, const Camera& camera) {
    ++generation_;
    mesh_ = &mesh;
    camera_ = camera;
    exact_ = 0;
    filter_.bind(mesh, camera);
}

void FaceFacing::begin_lazy(const MeshTopology& mesh, const Camera& camera) {
    const std::size_t nf = mesh.face_count();
    if (full_ || state_.size() != nf + kPad || mesh_ != &mesh) {
        state_.assign(nf + kPad, kSentinel);
        std::fill(state_.begin(), state_.begin() + std::ptrdiff_t(nf), kUnknown);
    } else {
        for (std::uint32_t f : touched_) state_[f] = kUnknown;
    }
    touched_.clear();
    full_ = false;
    bind(mesh, camera);
}


void FaceBlocks::build(const MeshTopology& mesh) {
    start(mesh);
    build_range(0, bounds_.size());
}

void FaceBlocks::start(const MeshTopology& mesh) {
    mesh_ = &mesh;
    edges_tried_ = false;
    nf_ = mesh.face_count();
    bounds_.assign((nf_ + kFaces - 1) / kFaces, Bounds{});
    edge_begin_.clear();
    nbr_begin_.clear();
    nbr_.clear();
}

void FaceBlocks::build_range(std::size_t b0, std::size_t b1) {
    static_assert(sizeof(Bounds) == 8 * sizeof(float));  // lo[4], hi[4]: the kernels' layout
    if (b0 < b1) facing_kernels().block_ranges(mesh_->facing.data(), nf_, b0, b1, bounds_[b0].lo);
}

void FaceBlocks::build_edges() {
    // Edges are numbered in the order of their first face (topology.cpp); anything else: no
    // edge ranges.
    const MeshTopology& mesh = *mesh_;
    const std::size_t ne = mesh.edge_count(), nb = bounds_.size();
    edges_tried_ = true;
    edge_begin_.assign(nb + 1, std::uint32_t(ne));
    nbr_begin_.assign(nb + 1, 0);
    std::vector<std::uint32_t> list, seen(nb, UINT32_MAX);  // seen[k]: last block that listed k
    std::size_t e = 0;
    std::uint32_t last = 0;
    for (std::size_t b = 0; b < nb; ++b) {
        edge_begin_[b] = std::uint32_t(e);
        nbr_begin_[b] = std::uint32_t(nbr_.size());
        list.clear();
        bool border = false;
        const std::uint32_t end = std::uint32_t(std::min(nf_, (b + 1) * kFaces));
        for (; e < ne; ++e) {
            const auto& ef = mesh.edge_face[e];
            if (ef[0] >= end) break;
            if (ef[0] < last) {  // not numbered by first face
                edge_begin_.clear();
                nbr_begin_.clear();
                nbr_.clear();
                return;
            }
            last = ef[0];
            if (ef[1] == kNoFace) {
                if (!border) list.push_back(kBorderBlock), border = true;
                continue;
            }
            const std::uint32_t nbk = ef[1] / kFaces;
            if (nbk != b && seen[nbk] != b) seen[nbk] = std::uint32_t(b), list.push_back(nbk);
        }
        nbr_.insert(nbr_.end(), list.begin(), list.end());
    }
    if (e != ne) {  // edges whose first face is out of range
        edge_begin_.clear();
        nbr_begin_.clear();
        nbr_.clear();
        return;
    }
    nbr_begin_[nb] = std::uint32_t(nbr_.size());
    nbr_.shrink_to_fit();
}

std::size_t FaceBlocks::bytes() const {
    return bounds_.capacity() * sizeof(Bounds) +
           (edge_begin_.capacity() + nbr_begin_.capacity() + nbr_.capacity()) * sizeof(std::uint32_t);
}

// The filter's float distance is fl(fl(fl(nx ex) + fl(ny ey)) + fl(nz ez)) - fl(w d); its real
// value over the block lies in the interval sum of the four products' ranges (computed in double:
// the products of two floats are exact, the sums err by 2^-52 relative), and the float
// evaluation errs from it by at most 4 * 2^-24 * (|nx ex| + |ny ey| + |nz ez| + |w d|); the range
// is widened by 2^-20 times that sum's bound.
void FaceBlocks::distance_range(const float* bounds, const FacingFilter& f, double& lo, double& hi) {
    const double e[4] = {f.ex, f.ey, f.ez, -double(f.w)};
    double l = 0.0, h = 0.0, mag = 0.0;
    for (int i = 0; i < 4; ++i) {
        const double a = double(bounds[i]) * e[i], c = double(bounds[4 + i]) * e[i];
        l += std::min(a, c);
        h += std::max(a, c);
        mag += std::max(std::abs(a), std::abs(c));
    }
    const double slack = mag * 0x1p-20;
    if (std::isnan(l) || std::isnan(h) || std::isnan(slack)) {
        lo = hi = NAN;
        return;
    }
    lo = l - slack;
    hi = h + slack;
}

void FaceBlocks::distance_range(std::size_t b, const FacingFilter& f, double& lo, double& hi) const {
    distance_range(bounds_[b].lo, f, lo, hi);
}

std::uint8_t FaceBlocks::classify(std::size_t b, const FacingFilter& f) const {
    double lo, hi;
    distance_range(b, f, lo, hi);
    if (lo > double(f.bound)) return FaceFacing::kFront;  // every det > bound
    if (hi < -double(f.bound)) return FaceFacing::kBack;  // every det < -bound
    return FaceFacing::kUnknown;                          // (also NaN)
}

bool BlockEdges::build(const MeshTopology& mesh) {
    mesh_ = &mesh;
    nf_ = mesh.face_count();
    const std::size_t ne = mesh.edge_count(), nb = (nf_ + kFaces - 1) / kFaces;
    auto fail = [&] {
        index_.clear(), owned_.clear(), edge_begin_.clear(), base2_.clear(), esc_begin_.clear();
        esc_self_.clear(), esc_far_.clear(), esc_corner_.clear();
        return false;
    };
    if (ne >= kCheck || nf_ >= kCheck) return fail();
    index_.resize(nb * 3 * kFaces);
    for (std::size_t b = 0; b < nb; ++b)
        for (std::uint32_t k = 0; k < 3; ++k)
            for (std::uint32_t j = 0; j < kFaces; ++j) index_[(3 * b + k) * kFaces + j] = std::uint8_t(j);
    owned_.assign(3 * nb, 0);
    edge_begin_.assign(nb + 1, std::uint32_t(ne));
    base2_.assign(nb, 0);
    esc_begin_.assign(nb + 1, 0);
    esc_self_.clear(), esc_far_.clear(), esc_corner_.clear();
    struct Far {
        std::uint32_t face, corner;  // neighbour, k * 64 + j
    };
    std::vector<Far> far;
    std::size_t e = 0;
    std::uint64_t last_corner = 0;
    for (std::size_t b = 0; b < nb; ++b) {
        const std::uint32_t base = std::uint32_t(b * kFaces), end = std::uint32_t(std::min(nf_, b * kFaces + kFaces));
        edge_begin_[b] = std::uint32_t(e);
        esc_begin_[b] = std::uint32_t(esc_self_.size());
        far.clear();
        for (; e < ne; ++e) {
            const auto [f, n] = mesh.edge_face[e];
            if (f >= end) break;
            if (f < base) return fail();
            // The corner that numbers e: the first corner of f on it; edge order must be corner order.
            const auto& fe = mesh.face_edges[f].edge;
            const std::uint32_t k = fe[0] == e ? 0 : fe[1] == e ? 1 : fe[2] == e ? 2 : 3;
            const std::uint64_t corner = 3 * std::uint64_t(f) + k;
            if (k == 3 || (e > 0 && corner <= last_corner)) return fail();
            last_corner = corner;
            const std::uint32_t j = f - base, bit = 3 * j + k;
            owned_[3 * b + bit / 64] |= std::uint64_t(1) << (bit % 64);
            if (n == kNoFace) continue;  // borders: never a silhouette
            if (n > f && n < base + 128) index_[(3 * b + k) * kFaces + j] = std::uint8_t(n - base);
            else far.push_back({n, k * kFaces + j});
        }
        // The second window: the 128 faces from a far neighbour that hold the most of them.
        std::sort(far.begin(), far.end(), [](const Far& a, const Far& c) { return a.face < c.face; });
        std::size_t best = 0, at = 0;
        for (std::size_t i = 0, i1 = 0; i < far.size(); ++i) {
            while (i1 < far.size() && far[i1].face < std::uint64_t(far[i].face) + 128) ++i1;
            if (i1 - i > best) best = i1 - i, at = i;
        }
        const std::uint32_t b2 = far.empty() ? base : std::min(far[at].face, std::uint32_t(nf_ - 1));
        base2_[b] = b2;
        std::sort(far.begin(), far.end(), [](const Far& a, const Far& c) { return a.corner < c.corner; });
        for (const Far& x : far) {
            const std::uint32_t j = x.corner % kFaces, k = x.corner / kFaces;
            if (x.face > base + j && x.face >= b2 && x.face < std::uint64_t(b2) + 128) {
                index_[(3 * b + k) * kFaces + j] = std::uint8_t(128 + (x.face - b2));
            } else {  // (also a neighbour that is the face itself: only its exact test differs)
                esc_self_.push_back(base + j);
                esc_far_.push_back(x.face);
                esc_corner_.push_back(std::uint8_t(x.corner));
            }
        }
    }
    if (e != ne) return fail();
    esc_begin_[nb] = std::uint32_t(esc_self_.size());
    esc_self_.shrink_to_fit(), esc_far_.shrink_to_fit(), esc_corner_.shrink_to_fit();
    return true;
}

std::size_t BlockEdges::bytes() const {
    return index_.capacity() + esc_corner_.capacity() + owned_.capacity() * 8 +
           (edge_begin_.capacity() + base2_.capacity() + esc_begin_.capacity() + esc_self_.capacity() +
            esc_far_.capacity()) * 4;
}

bool BlockEdges::has_simd() { return facing_kernels_for(FacingIsa::Avx2) != nullptr; }

void BlockEdges::escape_bits(const std::uint8_t* st, std::uint32_t b0, std::uint32_t b1, std::vector<std::uint16_t>& bits,
                             const FacingKernels& kernels) const {
    const std::size_t i0 = esc_begin_[b0], n = esc_begin_[b1] - i0;
    bits.assign((n + 15) / 16, 0);
    kernels.escape_bits(st, esc_self_.data() + i0, esc_far_.data() + i0, n, bits.data());
}

bool BlockEdges::scan_block(const std::uint8_t* st, std::uint32_t b, const std::uint16_t* esc, std::uint32_t esc0,
                            std::vector<std::uint32_t>& out, const FacingKernels& kernels) const {
    const std::uint32_t base = b * kFaces;
    const std::uint8_t* index = index_.data() + std::size_t(b) * 3 * kFaces;
    std::uint64_t sure[3], check[3], undecided;
    if (b + 8 < base2_.size()) {  // the second window is elsewhere in the states: fetch it ahead
        __builtin_prefetch(st + base2_[b + 8]);
        __builtin_prefetch(st + base2_[b + 8] + 64);
        __builtin_prefetch(st + base2_[b + 8] + 127);
        for (int i = 0; i < 3; ++i) __builtin_prefetch(index + 8 * 3 * kFaces + 64 * i);
    }
    const bool read = kernels.block_masks(st, base, base2_[b], index, sure, check, undecided);
    // Escapes: the rare candidates among them set their corner's bit.
    for (std::uint32_t i = esc_begin_[b]; i < esc_begin_[b + 1]; ++i) {
        const std::uint32_t r = i - esc0;
        if (!((esc[r / 16] >> (r % 16)) & 1)) continue;
        const std::uint32_t c = esc_corner_[i], k = c / kFaces, j = c % kFaces;
        ((st[esc_far_[i]] & FaceFacing::kUnknown) ? check : sure)[k] |= std::uint64_t(1) << j;
    }
    // Undecided faces (past the last face: the sentinel, not a face): every interior edge they
    // number is checked.
    const std::uint32_t live = std::uint32_t(std::min<std::size_t>(kFaces, nf_ - base));
    if (live < 64) undecided &= (std::uint64_t(1) << live) - 1;
    for (std::uint64_t u = undecided; u; u &= u - 1) {
        const std::uint32_t j = std::uint32_t(__builtin_ctzll(u));
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t bit = 3 * j + k;
            if (!((owned_[3 * b + bit / 64] >> (bit % 64)) & 1)) continue;
            if (mesh_->face_edges[base + j].face[k] == kNoFace) continue;
            check[k] |= std::uint64_t(1) << j;
        }
    }
    if (!((sure[0] | sure[1] | sure[2] | check[0] | check[1] | check[2]))) return read;
    // Corner order (bit 3 j + k), then the owned corners' ranks: edge ids.
    std::uint32_t ids[3 * kFaces];
    const std::uint32_t n = kernels.block_edges(sure, check, owned_.data() + 3 * std::size_t(b), edge_begin_[b], ids);
    out.insert(out.end(), ids, ids + n);
    return read;
}

void FaceBlocks::classify(std::size_t b0, std::size_t b1, const FacingFilter& f, std::uint8_t* out) const {
    classify_within(b0, b1, f, double(f.bound), out);
}

void FaceBlocks::classify_within(std::size_t b0, std::size_t b1, const FacingFilter& f, double limit,
                                 std::uint8_t* out) const {
    if (b0 < b1) facing_kernels().classify_blocks(bounds_[b0].lo, b1 - b0, f, limit, out);
}

void FacingBand::assign(const MeshTopology& mesh, const std::vector<std::uint32_t>& faces) {
    n_ = faces.size();
    ids_ = faces;
    for (auto* row : {&nx_, &ny_, &nz_, &d_}) row->resize(n_);
    for (std::size_t i = 0; i < n_; ++i) {
        const MeshTopology::FacingPlane& p = mesh.facing[faces[i]];
        nx_[i] = p.nx, ny_[i] = p.ny, nz_[i] = p.nz, d_[i] = p.d;
    }
    finish();
}

std::size_t FacingBand::select(const MeshTopology& mesh, const FacingFilter& filter, float limit, const FaceBlocks* blocks,
                               std::uint64_t* front, bool simd) {
    return select(mesh, filter, limit, blocks, front, facing_kernels(simd));
}

std::size_t FacingBand::select(const MeshTopology& mesh, const FacingFilter& filter, float limit, const FaceBlocks* blocks,
                               std::uint64_t* front, const FacingKernels& kernels) {
    std::size_t rows_n = 0;
    // Faces [f0, f1) (f0 a multiple of 64) through the kernel, in chunks of whole words of front
    // bits, each with room made for all its faces and a vector group more.
    auto run = [&](std::uint32_t f0, std::uint32_t f1) {
        constexpr std::uint32_t kChunk = 4096;
        for (std::uint32_t a = f0; a < f1;) {
            const std::uint32_t b = f1 - a > kChunk ? a + kChunk : f1;
            room(rows_n + (b - a) + 8);
            BandRowsOut rows{ids_.data(), nx_.data(), ny_.data(), nz_.data(), d_.data(), rows_n};
            kernels.band_rows(mesh.facing.data(), a, b, filter, limit, rows, front);
            rows_n = rows.n;
            a = b;
        }
    };
    const std::uint32_t nf = std::uint32_t(mesh.face_count());
    if (!blocks || !blocks->built_for(mesh)) {
        run(0, nf);
        n_ = rows_n;
        finish();
        return nf;
    }
    // Blocks whose every float distance is beyond +-limit hold no face of the band; runs of the
    // other blocks are streamed as before (so the same faces, in order). A skipped block's faces
    // are all front (every distance above limit) or all back (every one below -limit).
    static_assert(FaceBlocks::kFaces == 64);  // a block's front bits are one word
    // The blocks are classified a chunk at a time (four a step), and the planes of blocks to
    // read are fetched a few blocks ahead (the runs between skipped blocks are short).
    std::size_t read = 0;
    std::uint32_t open = UINT32_MAX;  // first face of the current run of blocks to read
    const std::size_t nb = blocks->size();
    constexpr std::size_t kChunk = 256, kPrefetch = 8;
    std::uint8_t cls[kChunk + kPrefetch];
    std::size_t c0 = 0, c1 = 0;  // cls[i]: the state of block c0 + i, for blocks [c0, c1)
    for (std::size_t b = 0; b <= nb; ++b) {
        bool skip = true;
        if (b < nb) {
            if (b + kPrefetch >= c1 && c1 < nb) {  // the next chunk, keeping the blocks ahead
                const std::size_t keep = c1 - std::min(c1, b);
                std::memmove(cls, cls + (b - c0), keep);
                c0 = b;
                const std::size_t n1 = std::min(nb, c1 + kChunk);
                blocks->classify_within(c1, n1, filter, double(limit), cls + keep);
                c1 = n1;
            }
            const std::size_t a = b + kPrefetch;
            if (a < c1 && cls[a - c0] == FaceFacing::kUnknown) {
                const char* q = reinterpret_cast<const char*>(mesh.facing.data() + a * FaceBlocks::kFaces);
                for (std::size_t i = 0; i < FaceBlocks::kFaces * sizeof(MeshTopology::FacingPlane); i += 64)
                    __builtin_prefetch(q + i);
            }
            const std::uint8_t st = cls[b - c0];
            skip = st != FaceFacing::kUnknown;
            if (skip && front) front[b] = st == FaceFacing::kFront ? ~std::uint64_t(0) : 0;
        }
        const std::uint32_t f = std::uint32_t(std::min<std::size_t>(b * FaceBlocks::kFaces, nf));
        if (!skip && open == UINT32_MAX) open = f;
        if (skip && open != UINT32_MAX) {
            run(open, f);
            read += f - open;
            open = UINT32_MAX;
        }
    }
    n_ = rows_n;
    finish();
    return read;
}

void FacingBand::finish() {
    words_.clear();
    masks_.clear();
    for (std::size_t i = 0; i < n_; ++i) {
        const std::uint32_t f = ids_[i];
        if (words_.empty() || words_.back() != f >> 6) words_.push_back(f >> 6), masks_.push_back(0);
        masks_.back() |= std::uint64_t(1) << (f & 63);
    }
    front_.assign((n_ + 7) / 8 + 16, 0);  // (+16: the word loop reads 16 bytes from any position)
    if (check_scratch_.size() < n_) check_scratch_.resize(n_);
}

void FacingBand::states(const FacingFilter& now, const FacingFilter& before, std::uint64_t* front_bits,
                        std::vector<std::uint32_t>& check, bool simd) {
    states(now, before, front_bits, check, facing_kernels(simd));
}

void FacingBand::states(const FacingFilter& now, const FacingFilter& before, std::uint64_t* front_bits,
                        std::vector<std::uint32_t>& check, const FacingKernels& kernels) {
    std::uint8_t* front = front_.data();
    const std::size_t n = kernels.band_states(nx_.data(), ny_.data(), nz_.data(), d_.data(), n_, now, before, front,
                                              check_scratch_.data());
    check.insert(check.end(), check_scratch_.data(), check_scratch_.data() + n);
    if (front_bits) kernels.band_words(words_.data(), masks_.data(), words_.size(), front, front_bits);
}

void FacingBand::room(std::size_t len) {
    if (len <= ids_.size()) return;
    const std::size_t grown = std::max<std::size_t>(2 * ids_.size(), len + 1024);
    ids_.resize(grown);
    for (auto* row : {&nx_, &ny_, &nz_, &d_}) row->resize(grown);
}

// Faces [lo, hi) of a full view (lo a block start): with blocks, blocks decided as a whole are
// filled with their state (block_state_), runs of the others streamed. Returns the faces whose
// planes were read.
std::size_t FaceFacing::decide(std::size_t lo, std::size_t hi, const FaceBlocks* blocks) {
    const MeshTopology& mesh = *mesh_;
    constexpr std::size_t kPrefetch = 8;  // blocks
    const FacingKernels& kernels = facing_kernels();
    auto run = [&](std::size_t a, std::size_t b) {
        kernels.facing_states(mesh.facing.data() + a, b - a, filter_, state_.data() + a);
    };
    if (!blocks) {
        run(lo, hi);
        return hi - lo;
    }
    constexpr std::size_t kB = FaceBlocks::kFaces;
    std::size_t read = 0, open = SIZE_MAX;
    const std::size_t bend = (hi + kB - 1) / kB;
    blocks->classify(lo / kB, bend, filter_, block_state_.data() + lo / kB);
    for (std::size_t b = lo / kB; b * kB < hi; ++b) {
        // The planes of undecided blocks ahead are fetched now: the runs between decided blocks
        // are short, too short for the hardware to see a stream (a full view after other work
        // finds them in memory).
        if (b + kPrefetch < bend && block_state_[b + kPrefetch] == kUnknown) {
            const char* q = reinterpret_cast<const char*>(mesh.facing.data() + (b + kPrefetch) * kB);
            for (std::size_t i = 0; i < kB * sizeof(MeshTopology::FacingPlane); i += 64) __builtin_prefetch(q + i);
        }
        const std::uint8_t s = block_state_[b];
        const std::size_t f0 = b * kB, f1 = std::min(hi, f0 + kB);
        if (s == kUnknown) {
            if (open == SIZE_MAX) open = f0;
            continue;
        }
        if (open != SIZE_MAX) run(open, f0), read += f0 - open, open = SIZE_MAX;
        std::memset(state_.data() + f0, s, f1 - f0);
    }
    if (open != SIZE_MAX) run(open, hi), read += hi - open;
    return read;
}

void FaceFacing::start_full(const MeshTopology& mesh, const Camera& camera) {
    bind(mesh, camera);
    const std::size_t nf = mesh.face_count();
    state_.resize(nf + kPad);
    std::fill(state_.begin() + std::ptrdiff_t(nf), state_.end(), kSentinel);
    touched_.clear();
    full_ = true;
    block_state_.clear();
    planes_read_ = nf;
}

void FaceFacing::begin_full(const MeshTopology& mesh, const Camera& camera, int threads, const FaceBlocks* blocks,
                            WorkerTeam* team) {
    start_full(mesh, camera);
    const std::size_t nf = mesh.face_count();
    if (blocks && !blocks->built_for(mesh)) blocks = nullptr;
    if (blocks) block_state_.resize(blocks->size());
    const std::size_t parts = std::size_t(std::clamp(threads, 1, 64));
    if (parts == 1 || nf < 65536) {
        planes_read_ = decide(0, nf, blocks);
        return;
    }
    std::vector<std::size_t> part_read(parts, 0);
    const std::size_t step = (nf / parts + 63) & ~std::size_t(63);  // cache-line (and block) aligned parts
    const int used = int(std::min(parts, (nf + step - 1) / step));
    WorkerTeam own;  // (threads for this call only, when no team is kept)
    (team ? *team : own).run(used, [&](int i) {
        const std::size_t k = std::size_t(i);
        part_read[k] = decide(k * step, std::min(nf, (k + 1) * step), blocks);
    });
    planes_read_ = 0;
    for (std::size_t r : part_read) planes_read_ += r;
}

void FaceFacing::begin_full_building(const MeshTopology& mesh, const Camera& camera, FaceBlocks& blocks) {
    start_full(mesh, camera);
    const std::size_t nf = mesh.face_count();
    blocks.start(mesh);
    block_state_.resize(blocks.size());
    // Chunks of blocks small enough that their planes, read by the ranges, are still in the
    // cache when the states are decided.
    constexpr std::size_t kChunk = 64;
    planes_read_ = 0;
    for (std::size_t b = 0; b < blocks.size(); b += kChunk) {
        const std::size_t b1 = std::min(blocks.size(), b + kChunk);
        blocks.build_range(b, b1);
        planes_read_ += decide(b * FaceBlocks::kFaces, std::min(nf, b1 * FaceBlocks::kFaces), &blocks);
    }
}

void FaceFacing::carry(const Camera& camera, const std::uint32_t* turned, std::size_t n) {
    bind(*mesh_, camera);
    block_state_.clear();
    planes_read_ = 0;
    std::uint8_t* st = state_.data();
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t s = st[turned[i]];
        st[turned[i]] = s == kUnknown ? kUnknown : std::uint8_t(kFront - s);
    }
}

float FaceFacing::signed_distance(std::uint32_t f) const { return filter_.signed_distance(mesh_->facing[f]); }

std::uint8_t FaceFacing::filter(std::uint32_t f) const { return filter_(mesh_->facing[f]); }

std::uint8_t FaceFacing::resolve(std::uint32_t f) const {
    std::uint8_t s = full_ ? kUnknown : filter(f);
    if (s == kUnknown) {
        const MeshTopology& m = *mesh_;
        const auto& v = m.faces[f];
        if (!shared_) ++exact_;
        s = orient_eye(camera_, m.positions[v[0]], m.positions[v[1]], m.positions[v[2]]) > 0 ? kFront : kBack;
    }
    if (shared_) return s;  // (read by several threads: nothing written)
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
