// One comparison of two self-intersection searches' results, for the tests that check a faster
// search (threads, skipped patches, the pm frame's moving faces) against the plain one.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "model/self_intersections.hpp"

namespace inkline::test {

enum class PairOrder { kSame, kAnyOrder };

inline void expect_same_self_intersections(const SelfIntersections& got, const SelfIntersections& want,
                                           const std::string& what, PairOrder order = PairOrder::kSame) {
    EXPECT_EQ(got.faces, want.faces) << what;
    EXPECT_EQ(got.flagged, want.flagged) << what;
    ASSERT_EQ(got.cuts.size(), want.cuts.size()) << what;
    for (std::size_t k = 0; k < want.cuts.size(); ++k) {
        EXPECT_EQ(got.cuts[k].edge, want.cuts[k].edge) << what << " cut " << k;
        EXPECT_EQ(got.cuts[k].s, want.cuts[k].s) << what << " cut " << k;
    }
    if (order == PairOrder::kSame) {
        EXPECT_EQ(got.pairs, want.pairs) << what;
        return;
    }
    auto sorted = [](std::vector<std::array<std::uint32_t, 2>> p) {
        for (auto& q : p) q = {std::min(q[0], q[1]), std::max(q[0], q[1])};
        std::sort(p.begin(), p.end());
        return p;
    };
    EXPECT_EQ(sorted(got.pairs), sorted(want.pairs)) << what;
}

}  // namespace inkline::test
