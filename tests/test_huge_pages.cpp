// The programs' allocator (src/app/huge_pages.cpp, linked into this test as into inkline): large
// blocks 2 MB-aligned and advised for transparent huge pages, small ones as malloc gives them,
// and the failure behaviour operator new promises.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <new>
#include <sstream>
#include <string>
#include <vector>

namespace {

constexpr std::size_t kHuge = std::size_t(2) << 20;

bool sanitized() {
#if defined(__SANITIZE_ADDRESS__)
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
