// Matching two lists of ids that both increase (a progressive mesh's adapted meshes list their
// vertices and faces in input order): where each id of one list sits in the other, by one merge,
// so that carrying state from one mesh to the next needs no map sized by the input.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace inkline {

inline constexpr std::uint32_t kNoMatch = UINT32_MAX;

// a_in_b[i]: the index of a[i] in b (kNoMatch when absent), b_in_a likewise (either may be null).
// Throws std::invalid_argument when a list does not strictly increase.
inline void match_increasing_ids(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b,
                                 std::vector<std::uint32_t>* a_in_b, std::vector<std::uint32_t>* b_in_a) {
    for (const auto* ids : {&a, &b})
        for (std::size_t i = 1; i < ids->size(); ++i)
            if (!((*ids)[i - 1] < (*ids)[i])) throw std::invalid_argument("match_increasing_ids: ids do not increase");
    if (a_in_b) a_in_b->assign(a.size(), kNoMatch);
    if (b_in_a) b_in_a->assign(b.size(), kNoMatch);
    for (std::size_t i = 0, j = 0; i < a.size() && j < b.size();) {
        if (a[i] < b[j]) {
            ++i;
        } else if (b[j] < a[i]) {
            ++j;
        } else {
            if (a_in_b) (*a_in_b)[i] = std::uint32_t(j);
            if (b_in_a) (*b_in_a)[j] = std::uint32_t(i);
            ++i, ++j;
        }
    }
}

}  // namespace inkline
