// Every facing kernel this CPU runs (features/facing_kernels.hpp: scalar, AVX2 + BMI2, AVX-512
// VBMI) against the scalar kernel, the reference on every machine, on real meshes seen from many
// random cameras, grazing ones among them (the eye in or next to a face's plane, so that the
// filters leave faces undecided): the same states, ranges, band rows, bits, checks and
// candidates, bit for bit. On a CPU without AVX2 only the scalar table runs (and is compared
// with itself), so the test still runs, and the kernel table chosen at start-up is among them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "features/facing_kernels.hpp"
#include "features/features.hpp"
#include "pipeline.hpp"

namespace inkline {
namespace {

const Model& mesh_model(const std::string& name) {
    static std::map<std::string, Model> cache;
    auto it = cache.find(name);
    if (it == cache.end()) {
        const std::string path = std::string(INKLINE_DATA_DIR) + "/meshes/" + name + ".off";
        if (!std::filesystem::exists(path)) throw std::runtime_error(path + " missing: run scripts/setup.sh");
        it = cache.emplace(name, Model::load(path)).first;
    }
    return it->second;
}

// The tables this CPU runs, the scalar one first.
std::vector<const FacingKernels*> runnable_tables() {
    std::vector<const FacingKernels*> out;
    for (FacingIsa isa : {FacingIsa::Scalar, FacingIsa::Avx2, FacingIsa::Avx512})
        if (const FacingKernels* k = facing_kernels_for(isa)) out.push_back(k);
    return out;
}

// Random cameras about the mesh: perspective from 1.2 to 4 half diagonals, orthographic, and
// grazing: the eye in the plane of a random face (or 1e-9 of the scale beside it), looking
// along it.
std::vector<Camera> random_cameras(const MeshTopology& mesh, std::mt19937_64& rng, int count) {
    const glm::dvec3 c = mesh.bounds.center();
    const double r = mesh.bounds.half_diagonal();
    std::uniform_real_distribution<double> unit(-1.0, 1.0), dist(1.2, 4.0);
    auto direction = [&] {
        while (true) {
            const glm::dvec3 v(unit(rng), unit(rng), unit(rng));
            const double l = glm::length(v);
            if (l > 0.1 && l <= 1.0) return v / l;
        }
    };
    auto up_for = [&](const glm::dvec3& forward) {
        const glm::dvec3 up = direction();
        return std::abs(glm::dot(up, forward)) < 0.9 ? up : glm::normalize(glm::cross(forward, up));
    };
    std::vector<Camera> out;
    for (int i = 0; i < count; ++i) {
        const glm::dvec3 target = c + 0.2 * r * glm::dvec3(unit(rng), unit(rng), unit(rng));
        switch (i % 4) {
            case 0:
            case 1: {
                const glm::dvec3 eye = target + dist(rng) * r * direction();
                out.push_back(Camera::perspective(eye, target, up_for(glm::normalize(target - eye)), 35, 800, 600));
                break;
            }
            case 2: {
                const glm::dvec3 d = direction();
                out.push_back(Camera::orthographic(target + 3.0 * r * d, target, up_for(-d), 2.2 * r, 640, 640));
                break;
            }
            default: {  // grazing: the eye in the plane of face f, beside it
                const auto f = std::uint32_t(rng() % mesh.face_count());
                const auto& v = mesh.faces[f];
                const glm::dvec3 a = mesh.positions[v[0]], b = mesh.positions[v[1]], p = mesh.positions[v[2]];
                const glm::dvec3 n = glm::cross(b - a, p - a);
                if (!(glm::length(n) > 0.0)) {
                    --i;
                    continue;
                }
                const glm::dvec3 along = glm::normalize(b - a);
                const double off = (i % 8 == 3) ? 0.0 : 1e-9 * r;
                const glm::dvec3 eye = a + dist(rng) * r * along + off * glm::normalize(n);
                out.push_back(Camera::perspective(eye, a, up_for(glm::normalize(a - eye)), 35, 800, 600));
            }
        }
    }
    return out;
}

// One mesh through every kernel of every runnable table, against the scalar table.
void compare_on(const std::string& name, int cameras, std::uint64_t seed, std::size_t& undecided) {
    SCOPED_TRACE(name);
    const MeshTopology& mesh = mesh_model(name).topology();
    const std::vector<const FacingKernels*> tables = runnable_tables();
    ASSERT_FALSE(tables.empty());
    const FacingKernels& ref = *tables[0];
    ASSERT_STREQ(ref.name, "scalar");
    const std::uint32_t nf = std::uint32_t(mesh.face_count()), ne = std::uint32_t(mesh.edge_count());
    const std::size_t nb = (nf + FaceBlocks::kFaces - 1) / FaceBlocks::kFaces;
    const MeshTopology::FacingPlane* planes = mesh.facing.data();
    std::mt19937_64 rng(seed);
    BlockEdges edges;
    ASSERT_TRUE(edges.build(mesh));

    // Plane ranges of the blocks (view-independent).
    std::vector<float> ref_bounds(8 * nb);
    ref.block_ranges(planes, nf, 0, nb, ref_bounds.data());
    for (const FacingKernels* k : tables) {
        std::vector<float> bounds(8 * nb);
        k->block_ranges(planes, nf, 0, nb, bounds.data());
        for (std::size_t b = 0; b < nb; ++b) {
            const float* x = &bounds[8 * b];
            const float* y = &ref_bounds[8 * b];
            ASSERT_EQ(std::isnan(x[0]), std::isnan(y[0])) << k->name << " block " << b;
            if (std::isnan(y[0])) continue;  // (a block never decided whole: the rest is not read)
            for (int i = 0; i < 8; ++i) ASSERT_EQ(x[i], y[i]) << k->name << " block " << b << " value " << i;
        }
    }

    Camera before = Camera::framing(mesh.bounds, 800, 600);
    for (const Camera& camera : random_cameras(mesh, rng, cameras)) {
        FacingFilter filter, old;
        filter.bind(mesh, camera);
        old.bind(mesh, before);
        const double scale = double(filter.bound);

        // The facing pass, from a block start and from an odd face (the tails).
        std::vector<std::uint8_t> ref_states(nf);
        ref.facing_states(planes, nf, filter, ref_states.data());
        undecided += std::size_t(std::count(ref_states.begin(), ref_states.end(), FaceFacing::kUnknown));
        const std::uint32_t odd = std::min<std::uint32_t>(nf, 13);

        // The full view's states as the scans read them (padded with the sentinel), with 2 % of
        // the faces made undecided so that every undecided path is taken.
        std::vector<std::uint8_t> st(nf + FaceFacing::kPad, FaceFacing::kSentinel);
        std::copy(ref_states.begin(), ref_states.end(), st.begin());
        for (std::uint32_t f = 0; f < nf; ++f)
            if (rng() % 50 == 0) st[f] = FaceFacing::kUnknown;

        // The band at a few limits, with its rows and front bits.
        const float limits[] = {0.0f, float(scale), float(64.0 * scale), float(1e-3 * mesh.facing_radius)};
        const std::uint64_t pattern = rng();
        const std::uint32_t f0 = std::uint32_t(64 * (rng() % (nb / 2 + 1)));
        const std::uint32_t f1 = std::min(nf, f0 + std::uint32_t(rng() % nf) + 1);

        for (const FacingKernels* k : tables) {
            SCOPED_TRACE(k->name);
            std::vector<std::uint8_t> states(nf);
            k->facing_states(planes, nf, filter, states.data());
            ASSERT_EQ(states, ref_states);
            std::vector<std::uint8_t> tail(nf, 9), ref_tail(nf, 9);
            k->facing_states(planes + odd, nf - odd, filter, tail.data());
            ref.facing_states(planes + odd, nf - odd, filter, ref_tail.data());
            ASSERT_EQ(tail, ref_tail);

            // Block states, at the filter's bound and at wider limits, from block 0 and block 3.
            for (double limit : {double(filter.bound), 8.0 * scale, 1e-2 * mesh.facing_radius}) {
                for (std::size_t b0 : {std::size_t(0), std::min<std::size_t>(3, nb)}) {
                    std::vector<std::uint8_t> cls(nb - b0, 9), ref_cls(nb - b0, 9);
                    k->classify_blocks(ref_bounds.data() + 8 * b0, nb - b0, filter, limit, cls.data());
                    ref.classify_blocks(ref_bounds.data() + 8 * b0, nb - b0, filter, limit, ref_cls.data());
                    ASSERT_EQ(cls, ref_cls) << "limit " << limit << " from block " << b0;
                }
            }

            // The exhaustive scan's candidate edges, in chunks as the finder reads them.
            std::vector<std::uint32_t> cand(ne + 8), ref_cand(ne + 8);
            for (std::uint32_t e0 = 0; e0 < ne; e0 += 4093) {
                const std::uint32_t e1 = std::min(ne, e0 + 4093);
                const std::uint32_t n = k->edge_candidates(mesh.edge_face.data(), st.data(), nf, e0, e1, cand.data());
                const std::uint32_t rn = ref.edge_candidates(mesh.edge_face.data(), st.data(), nf, e0, e1, ref_cand.data());
                ASSERT_EQ(n, rn) << "edges from " << e0;
                ASSERT_TRUE(std::equal(cand.begin(), cand.begin() + n, ref_cand.begin())) << "edges from " << e0;
            }

            // BlockEdges' escapes, block masks and edge ids, over all blocks and a middle range.
            const auto none = [](std::uint32_t) { return false; };
            for (std::uint32_t b0 : {0u, std::uint32_t(edges.size() / 3)}) {
                std::vector<std::uint32_t> got, want;
                const std::size_t r = edges.scan(st.data(), b0, std::uint32_t(edges.size()), none, got, *k);
                const std::size_t rr = edges.scan(st.data(), b0, std::uint32_t(edges.size()), none, want, ref);
                ASSERT_EQ(r, rr);
                ASSERT_EQ(got, want) << "from block " << b0;
            }

            for (float limit : limits) {
                SCOPED_TRACE(limit);
                // The band's rows and front bits over faces [f0, f1).
                const std::size_t cap = f1 - f0 + 8;
                std::vector<std::uint32_t> ids(cap), ref_ids(cap);
                std::vector<float> rows(4 * cap), ref_rows(4 * cap);
                std::vector<std::uint64_t> front(nf / 64 + 1, pattern), ref_front(nf / 64 + 1, pattern);
                BandRowsOut out{ids.data(), &rows[0], &rows[cap], &rows[2 * cap], &rows[3 * cap], 0};
                BandRowsOut ref_out{ref_ids.data(), &ref_rows[0], &ref_rows[cap], &ref_rows[2 * cap], &ref_rows[3 * cap], 0};
                k->band_rows(planes, f0, f1, filter, limit, out, front.data());
                ref.band_rows(planes, f0, f1, filter, limit, ref_out, ref_front.data());
                ASSERT_EQ(out.n, ref_out.n);
                ASSERT_EQ(front, ref_front);
                const std::size_t n = out.n;
                ASSERT_TRUE(std::equal(ids.begin(), ids.begin() + n, ref_ids.begin()));
                for (int row = 0; row < 4; ++row)
                    ASSERT_EQ(0, std::memcmp(&rows[row * cap], &ref_rows[row * cap], n * sizeof(float))) << "row " << row;

                // The band's states between the previous camera and this one (and between this
                // one and itself: only the faces it leaves undecided are checked), and its bits.
                std::vector<std::uint8_t> bits8(n / 8 + 17, 0), ref_bits8(n / 8 + 17, 0);
                for (const FacingFilter* was : {&filter, &old}) {
                    std::vector<std::uint32_t> check(n + 1), ref_check(n + 1);
                    const std::size_t m =
                        k->band_states(out.nx, out.ny, out.nz, out.d, n, filter, *was, bits8.data(), check.data());
                    const std::size_t rm = ref.band_states(ref_out.nx, ref_out.ny, ref_out.nz, ref_out.d, n, filter,
                                                           *was, ref_bits8.data(), ref_check.data());
                    ASSERT_EQ(m, rm);
                    ASSERT_TRUE(std::equal(check.begin(), check.begin() + m, ref_check.begin()));
                    ASSERT_TRUE(
                        std::equal(ref_bits8.begin(), ref_bits8.begin() + std::ptrdiff_t((n + 7) / 8), bits8.begin()));
                }
                std::vector<std::uint32_t> words;
                std::vector<std::uint64_t> masks;
                for (std::size_t i = 0; i < n; ++i) {
                    const std::uint32_t f = ids[i];
                    if (words.empty() || words.back() != f >> 6) words.push_back(f >> 6), masks.push_back(0);
                    masks.back() |= std::uint64_t(1) << (f & 63);
                }
                std::vector<std::uint64_t> set(nf / 64 + 1, ~pattern), ref_set(nf / 64 + 1, ~pattern);
                k->band_words(words.data(), masks.data(), words.size(), ref_bits8.data(), set.data());
                ref.band_words(words.data(), masks.data(), words.size(), ref_bits8.data(), ref_set.data());
                ASSERT_EQ(set, ref_set);
            }

            // The band through FacingBand, the faces of blocks beyond the limit skipped.
            FaceBlocks blocks;
            blocks.build(mesh);
            FacingBand band, ref_band;
            std::vector<std::uint64_t> front(nf / 64 + 1, pattern), ref_front(nf / 64 + 1, pattern);
            const float limit = float(16.0 * scale);
            const std::size_t read = band.select(mesh, filter, limit, &blocks, front.data(), *k);
            ASSERT_EQ(read, ref_band.select(mesh, filter, limit, &blocks, ref_front.data(), ref));
            ASSERT_EQ(band.size(), ref_band.size());
            for (std::size_t i = 0; i < band.size(); ++i) ASSERT_EQ(band.face(i), ref_band.face(i));
            ASSERT_EQ(front, ref_front);
            std::vector<std::uint32_t> check, ref_check;
            band.states(filter, old, front.data(), check, *k);
            ref_band.states(filter, old, ref_front.data(), ref_check, ref);
            ASSERT_EQ(check, ref_check);
            ASSERT_EQ(front, ref_front);
        }
        before = camera;
    }
}

TEST(FacingKernels, StartUpTableIsRunnable) {
    const std::vector<const FacingKernels*> tables = runnable_tables();
    EXPECT_NE(std::find(tables.begin(), tables.end(), &facing_kernels()), tables.end());
    EXPECT_EQ(&facing_kernels(false), facing_kernels_for(FacingIsa::Scalar));
    EXPECT_STREQ(facing_kernels(false).name, "scalar");
}

TEST(FacingKernels, SameAsScalarOnMeshes) {
    std::size_t undecided = 0;  // faces the float filter left to the exact test, over all views
    compare_on("fandisk", 48, 1, undecided);
    compare_on("bunny00", 40, 2, undecided);
    compare_on("armadillo", 24, 3, undecided);
    // The grazing cameras leave faces undecided: the comparisons covered those paths.
    EXPECT_GT(undecided, 0u);
}

}  // namespace
}  // namespace inkline
