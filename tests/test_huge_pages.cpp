// The programs' allocator (src/app/huge_pages.cpp, linked into this test as into inkline): large
// blocks 2 MB-aligned and advised for transparent huge pages, mid-size ones from a HugeArena that
// keeps them in huge pages and reuses them, small ones as malloc gives them, and the failure
// behaviour operator new promises. The HugeArena tests use arenas of their own, so they also run
// under the sanitizers (where the global operator new is the sanitizer's).
#include <gtest/gtest.h>

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/huge_arena.hpp"

namespace {

constexpr std::size_t kHuge = std::size_t(2) << 20;

bool sanitized() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    return true;
#else
    return false;
#endif
}

// The host's transparent huge page mode ("always", "madvise", "never"; empty if unknown).
std::string thp_mode() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string s;
    std::getline(in, s);
    const auto a = s.find('['), b = s.find(']');
    return a == std::string::npos || b == std::string::npos ? "" : s.substr(a + 1, b - a - 1);
}

// From /proc/self/smaps: the VmFlags line of the mapping holding p ("" if none is found).
std::string vm_flags(std::uintptr_t addr) {
    std::ifstream in("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(in, line)) {
        std::uintptr_t lo = 0, hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-' && line.find(' ') != std::string::npos &&
            line.find(':') > line.find(' ')) {
            inside = lo <= addr && addr < hi;
            continue;
        }
        if (inside && line.rfind("VmFlags:", 0) == 0) return line;
    }
    return "";
}

TEST(HugePages, LargeBlocksAreAlignedAdvisedAndUsable) {
    if (sanitized()) GTEST_SKIP() << "AddressSanitizer allocates (huge_pages.cpp defines nothing there)";
    const std::size_t n = 5 * kHuge + 123;  // not a multiple of the huge page
    std::vector<std::uint32_t> v(n / 4);
    const auto addr = reinterpret_cast<std::uintptr_t>(v.data());
    // malloc alone puts a large block 16 bytes past a page boundary, never on a 2 MB one.
    EXPECT_EQ(addr % kHuge, 0u);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::uint32_t(i * 2654435761u);
    for (std::size_t i = 0; i < v.size(); i += 4099) ASSERT_EQ(v[i], std::uint32_t(i * 2654435761u));
    const std::string mode = thp_mode();
    if (mode == "always" || mode == "madvise") {
        // "hg": the mapping was advised MADV_HUGEPAGE.
        EXPECT_NE(vm_flags(addr).find(" hg"), std::string::npos) << vm_flags(addr);
    }
    // Freed, its mapping is gone (given back at once, not kept in malloc's heap).
    std::vector<std::uint32_t>().swap(v);
    EXPECT_EQ(vm_flags(addr), "");
}

TEST(HugePages, SmallBlocksAndArraysAreOrdinary) {
    if (sanitized()) GTEST_SKIP() << "AddressSanitizer allocates";
    std::vector<std::unique_ptr<char[]>> blocks;
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(100), std::size_t(1) << 20, (std::size_t(4) << 20) - 1}) {
        blocks.emplace_back(new char[n + 1]);
        std::memset(blocks.back().get(), 0x5a, n + 1);
    }
    auto big = std::make_unique<double[]>((std::size_t(8) << 20) / sizeof(double));
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(big.get()) % kHuge, 0u);
    big[0] = 1.0;
    big[(std::size_t(8) << 20) / sizeof(double) - 1] = 2.0;
    EXPECT_EQ(big[0] + big[(std::size_t(8) << 20) / sizeof(double) - 1], 3.0);
    // Over-aligned types take libstdc++'s aligned operator new, freed by its aligned delete.
    struct alignas(64) Line {
        char bytes[64];
    };
    std::vector<Line> lines(1 << 17);  // 8 MB
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(lines.data()) % 64, 0u);
}

TEST(HugePages, ImpossibleRequestsFailAsOperatorNewPromises) {
    if (sanitized()) GTEST_SKIP() << "AddressSanitizer allocates";
    const std::size_t absurd = SIZE_MAX / 2;
    EXPECT_EQ(::operator new(absurd, std::nothrow), nullptr);
    EXPECT_THROW((void)::operator new(absurd), std::bad_alloc);
    // A new handler is called until it gives up (here: by removing itself).
    static int calls = 0;
    calls = 0;
    std::set_new_handler([] {
        if (++calls == 3) std::set_new_handler(nullptr);
    });
    EXPECT_THROW((void)::operator new(absurd), std::bad_alloc);
    EXPECT_EQ(calls, 3);
    // The nothrow form calls it too, then gives null.
    calls = 0;
    std::set_new_handler([] {
        if (++calls == 2) std::set_new_handler(nullptr);
    });
    EXPECT_EQ(::operator new[](absurd, std::nothrow), nullptr);
    EXPECT_EQ(calls, 2);
    std::set_new_handler(nullptr);
}

}  // namespace

namespace {

using inkline::HugeArena;
constexpr std::size_t kKB = 1024, kMB = kKB * kKB;
constexpr std::size_t kTag = HugeArena::kAlign;  // each block's tag, just below its bytes

std::byte* bytes(void* p) { return static_cast<std::byte*>(p); }

bool thp_advised() {
    const std::string mode = thp_mode();
    return mode == "always" || mode == "madvise";
}

TEST(HugeArena, BlocksAreAlignedDisjointAndInAdvisedHugePages) {
    HugeArena arena(64 * kMB);
    const std::vector<std::size_t> sizes = {1, 100, 64 * kKB, 64 * kKB + 1, kMB, 3 * kMB + 5};
    std::vector<std::byte*> blocks;
    for (std::size_t n : sizes) {
        blocks.push_back(bytes(arena.allocate(n)));
        ASSERT_NE(blocks.back(), nullptr);
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(blocks.back()) % HugeArena::kAlign, 0u) << n;
        std::memset(blocks.back(), int(n & 0xff), n);
        EXPECT_TRUE(arena.owns(blocks.back()));
        EXPECT_TRUE(arena.owns(blocks.back() + n - 1));
    }
    // The range starts on a huge page; the first block just after its tag, each next one just
    // after the last (tag and bytes rounded up to 64).
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(blocks[0]) % HugeArena::kHugePage, kTag);
    for (std::size_t i = 1; i < sizes.size(); ++i)
        EXPECT_EQ(blocks[i] - blocks[i - 1], std::ptrdiff_t((sizes[i - 1] + 2 * kTag - 1) / kTag * kTag)) << i;
    for (std::size_t i = 0; i < sizes.size(); ++i)
        EXPECT_EQ(blocks[i][sizes[i] - 1], std::byte(sizes[i] & 0xff)) << i;  // nothing overwritten
    EXPECT_FALSE(arena.owns(blocks[0] - kTag - 1));
    int local = 0;
    EXPECT_FALSE(arena.owns(&local));
    EXPECT_FALSE(arena.owns(nullptr));
    if (thp_advised()) {
        EXPECT_NE(vm_flags(reinterpret_cast<std::uintptr_t>(blocks[0])).find(" hg"), std::string::npos);
    }
    for (std::byte* p : blocks) arena.release(p);
    EXPECT_EQ(arena.stats().in_use, 0u);
}

TEST(HugeArena, FreedBlocksAreReusedWithoutGrowing) {
    HugeArena arena(256 * kMB);
    void* a = arena.allocate(kMB);
    void* b = arena.allocate(kMB);
    void* c = arena.allocate(kMB);
    arena.release(b);
    EXPECT_EQ(arena.allocate(kMB), b);  // the hole, not the top
    arena.release(a), arena.release(b), arena.release(c);
    HugeArena::Stats s = arena.stats();
    EXPECT_EQ(s.top, 0u);  // all merged back into the top
    EXPECT_EQ(s.free_blocks, 0u);
    EXPECT_EQ(s.in_use, 0u);
    // Stage after stage of arrays of varied sizes, freed in varied orders: after the first
    // round, no new memory.
    const std::vector<std::size_t> sizes = {64 * kKB, 3 * kMB, 200 * kKB, kMB + 17, 640 * kKB, 2 * kMB, 96 * kKB, 1500 * kKB};
    std::size_t writable_after_first = 0;
    for (int round = 0; round < 50; ++round) {
        std::vector<void*> live;
        for (std::size_t i = 0; i < sizes.size(); ++i) {
            live.push_back(arena.allocate(sizes[(i + round) % sizes.size()]));
            ASSERT_NE(live.back(), nullptr);
            std::memset(live.back(), round, sizes[(i + round) % sizes.size()]);
        }
        for (std::size_t i = 0; i < live.size(); ++i) arena.release(live[(i * 3 + round) % live.size()]);
        if (round == 0) writable_after_first = arena.stats().writable;
    }
    s = arena.stats();
    EXPECT_EQ(s.writable, writable_after_first);
    EXPECT_EQ(s.top, 0u);
    EXPECT_EQ(s.free_blocks, 0u);
    EXPECT_EQ(s.in_use, 0u);
}

TEST(HugeArena, NeighboursMergeAndTheBestFitIsTaken) {
    HugeArena arena(64 * kMB);
    std::byte* a = bytes(arena.allocate(300 * kKB));
    std::byte* b = bytes(arena.allocate(100 * kKB));
    std::byte* c = bytes(arena.allocate(200 * kKB));
    std::byte* d = bytes(arena.allocate(100 * kKB));
    arena.release(a);
    arena.release(c);
    EXPECT_EQ(arena.stats().free_blocks, 2u);
    // 180 kB fits both holes; the 200 kB one fits best. Its 20 kB left over stay free.
    std::byte* e = bytes(arena.allocate(180 * kKB));
    EXPECT_EQ(e, c);
    EXPECT_EQ(arena.stats().free_blocks, 2u);
    // Freed, b joins a below it: 400 kB and two tags, where neither hole alone had room.
    arena.release(b);
    EXPECT_EQ(arena.stats().free_blocks, 2u);
    EXPECT_EQ(arena.stats().largest_free, 400 * kKB + 2 * kTag);
    EXPECT_EQ(bytes(arena.allocate(400 * kKB + kTag)), a);  // all of it (one tag is a's own)
    // e freed joins its 20 kB rest above it; d freed then joins them and the top.
    arena.release(e);
    EXPECT_EQ(arena.stats().free_blocks, 1u);
    EXPECT_EQ(arena.stats().largest_free, 200 * kKB + kTag);
    arena.release(d);
    EXPECT_EQ(arena.stats().free_blocks, 0u);
    EXPECT_EQ(arena.stats().top, 400 * kKB + 2 * kTag);  // the merged block at a is all that is left
    arena.release(a);
    EXPECT_EQ(arena.stats().top, 0u);
}

TEST(HugeArena, ManyThreadsShareOne) {
    HugeArena arena(512 * kMB);
    constexpr int kThreads = 4, kRounds = 40000;
    // Every eighth block passes to another thread through this list, to be freed there, as the
    // self-intersection helper's blocks are freed by the loading thread.
    std::mutex handover_mutex;
    std::vector<std::pair<std::uint32_t*, std::size_t>> handover;
    // A block's first and last words hold its length in words; its neighbours' tags lie right
    // beside them, so a block given twice or overlapping another shows here.
    auto intact = [](const std::pair<std::uint32_t*, std::size_t>& b) {
        return b.first[0] == std::uint32_t(b.second) && b.first[b.second - 1] == std::uint32_t(b.second);
    };
    std::vector<int> damaged(kThreads, 0);
    auto work = [&](int id) {
        std::uint32_t rng = 12345u + 977u * std::uint32_t(id);
        std::vector<std::pair<std::uint32_t*, std::size_t>> mine;
        for (int round = 0; round < kRounds; ++round) {
            rng = rng * 1664525u + 1013904223u;
            const std::size_t words = 1 + (rng >> 8) % (((rng >> 28) & 1) ? 300 * kKB : 4 * kKB);
            auto* p = static_cast<std::uint32_t*>(arena.allocate(words * 4));
            if (!p) {
                ++damaged[id];
                continue;
            }
            p[0] = p[words - 1] = std::uint32_t(words);
            mine.emplace_back(p, words);
            if (mine.size() < 6) continue;
            auto out = mine[rng % mine.size()];
            mine.erase(std::find(mine.begin(), mine.end(), out));
            if (round % 8 == 0) {
                std::lock_guard<std::mutex> lock(handover_mutex);
                handover.push_back(out);
                out = handover[(rng >> 4) % handover.size()];
                handover.erase(std::find(handover.begin(), handover.end(), out));
            }
            if (!intact(out)) ++damaged[id];
            arena.release(out.first);
        }
        for (const auto& b : mine) {
            if (!intact(b)) ++damaged[id];
            arena.release(b.first);
        }
    };
    std::vector<std::thread> threads;
    for (int id = 0; id < kThreads; ++id) threads.emplace_back(work, id);
    for (std::thread& t : threads) t.join();
    for (const auto& b : handover) {
        EXPECT_TRUE(intact(b));
        arena.release(b.first);
    }
    for (int id = 0; id < kThreads; ++id) EXPECT_EQ(damaged[id], 0) << "thread " << id;
    const HugeArena::Stats s = arena.stats();  // every block back, every neighbour merged
    EXPECT_EQ(s.in_use, 0u);
    EXPECT_EQ(s.top, 0u);
    EXPECT_EQ(s.free_blocks, 0u);
}

TEST(HugeArena, RequestsThatDoNotFitGiveNullAndLeaveItUsable) {
    HugeArena arena(8 * kMB);
    EXPECT_EQ(arena.allocate(9 * kMB), nullptr);
    EXPECT_EQ(arena.allocate(SIZE_MAX), nullptr);  // no overflow in the rounding
    void* a = arena.allocate(3 * kMB);
    void* b = arena.allocate(3 * kMB);
    ASSERT_NE(a, nullptr);
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(arena.allocate(3 * kMB), nullptr);  // 2 MB left, tags included
    void* c = arena.allocate(2 * kMB - 3 * kTag);  // what is left, to the byte
    EXPECT_NE(c, nullptr);
    EXPECT_EQ(arena.allocate(1), nullptr);
    arena.release(a);
    EXPECT_EQ(arena.allocate(3 * kMB), a);
    EXPECT_EQ(arena.stats().in_use, 8 * kMB);
    arena.release(a), arena.release(b), arena.release(c);

    // Address space it cannot have: no reservation, every request null, no pointer its own.
    HugeArena impossible(std::size_t(1) << 62);
    EXPECT_EQ(impossible.allocate(100 * kKB), nullptr);
    EXPECT_EQ(impossible.allocate(1), nullptr);
    EXPECT_FALSE(impossible.owns(a));
    EXPECT_EQ(impossible.stats().reserved, 0u);
    HugeArena empty(0);
    EXPECT_EQ(empty.allocate(1), nullptr);
}

TEST(HugeArena, ALongFreeTopIsGivenBack) {
    HugeArena arena(64 * kMB, 8 * kMB);  // a free top above 8 MB is trimmed
    std::vector<void*> blocks;
    for (int i = 0; i < 5; ++i) {
        blocks.push_back(arena.allocate(3 * kMB));
        std::memset(blocks.back(), 0x77, 3 * kMB);
    }
    EXPECT_EQ(arena.stats().writable, 16 * kMB);  // 15 MB and 5 tags, in 2 MB pages
    arena.release(blocks[4]);
    arena.release(blocks[3]);
    EXPECT_EQ(arena.stats().writable, 16 * kMB);  // 7 MB free on top: kept
    arena.release(blocks[2]);                     // 10 MB: trimmed down to the 2 MB page of the top
    EXPECT_EQ(arena.stats().top, 6 * kMB + 2 * kTag);
    EXPECT_EQ(arena.stats().writable, 8 * kMB);
    // The pages above it were given back: not resident, and zero when used again.
    const long page = sysconf(_SC_PAGESIZE);
    auto* probe = static_cast<std::byte*>(blocks[4]);
    auto* page_start = reinterpret_cast<void*>(reinterpret_cast<std::uintptr_t>(probe) & ~std::uintptr_t(page - 1));
    unsigned char resident = 1;
    ASSERT_EQ(mincore(page_start, std::size_t(page), &resident), 0);
    EXPECT_EQ(resident & 1, 0);
    void* again = arena.allocate(9 * kMB);
    EXPECT_EQ(again, blocks[2]);
    EXPECT_EQ(static_cast<unsigned char*>(again)[9 * kMB - 1], 0);
    arena.release(again);  // 10 MB free on top again: trimmed
    EXPECT_EQ(arena.stats().writable, 8 * kMB);
    arena.release(blocks[1]);
    arena.release(blocks[0]);
    EXPECT_EQ(arena.stats().top, 0u);
    EXPECT_EQ(arena.stats().writable, 8 * kMB);  // 8 MB free, not more than the threshold: kept
}

#if defined(__SANITIZE_ADDRESS__)
TEST(HugeArena, UseAfterReleaseIsReportedUnderAddressSanitizer) {
    HugeArena arena(16 * kMB);
    auto* p = static_cast<volatile char*>(arena.allocate(100 * kKB));
    p[100 * kKB - 1] = 1;
    arena.release(const_cast<char*>(p));
    EXPECT_DEATH(p[50] = 2, "use-after-poison");
    auto* q = static_cast<volatile char*>(arena.allocate(1000));
    EXPECT_DEATH(q[1000] = 3, "use-after-poison");  // past its end, inside its rounded block
    arena.release(const_cast<char*>(q));
}
#endif

// The program's operator new: mid-size blocks from its arena.
TEST(HugePages, MidSizeBlocksShareOneHugePageRangeAndAreReused) {
    if (sanitized()) GTEST_SKIP() << "the sanitizer allocates (huge_pages.cpp defines nothing there)";
    auto small = std::make_unique<char[]>(1000);
    auto mid = std::make_unique<char[]>(100 * kKB);
    auto upper = std::make_unique<char[]>(4 * kMB - 1);
    const auto at = [](const auto& p) { return reinterpret_cast<std::uintptr_t>(p.get()); };
    EXPECT_EQ(at(mid) % HugeArena::kAlign, 0u);
    EXPECT_EQ(at(upper) % HugeArena::kAlign, 0u);
    // The same mapping (malloc maps a block this large on its own), advised for huge pages.
    const std::string flags = vm_flags(at(mid));
    EXPECT_EQ(flags, vm_flags(at(upper)));
    if (thp_advised()) {
        EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
        EXPECT_EQ(vm_flags(at(small)).find(" hg"), std::string::npos);  // malloc's heap
    }
    std::memset(upper.get(), 1, 4 * kMB - 1);
    const std::uintptr_t upper_at = at(upper);
    upper.reset();
    auto next = std::make_unique<char[]>(3 * kMB);  // the next stage's array: the same pages
    EXPECT_EQ(at(next), upper_at);
}

TEST(HugePages, ThreadsAllocateAndFreeEachOthersMidSizeBlocks) {
    std::vector<std::vector<std::uint64_t>> made(8);
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&made, t] {
            for (int round = 0; round < 200; ++round) {
                std::vector<std::uint64_t> v(16 * 1024 + std::size_t(round * 997 + t * 4099) % (300 * 1024), std::uint64_t(round));
                std::vector<std::uint64_t>& slot = made[std::size_t(t * 2 + round % 2)];
                if (!slot.empty() && slot.back() != slot.front()) throw std::runtime_error("damaged");
                slot.swap(v);  // the old block freed here, by whichever thread
            }
        });
    for (std::thread& t : threads) t.join();
    for (std::size_t i = 0; i < made.size(); ++i) {
        ASSERT_FALSE(made[i].empty());
        EXPECT_EQ(made[i].front(), std::uint64_t(198 + i % 2)) << i;
        EXPECT_EQ(std::count(made[i].begin(), made[i].end(), made[i].front()), std::ptrdiff_t(made[i].size())) << i;
    }
}

}  // namespace
