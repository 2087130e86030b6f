// Large arrays in transparent huge pages, for inkline's executables (the command line, the window,
// the benchmarks): the global operator new and delete of the program this object is linked into.
//
// The per-frame loops on a large model read arrays of tens of megabytes at scattered places (the
// mesh's positions, faces, edges and facing planes; a view's vertex images): with 4 KB pages most
// of those reads also miss the TLB. Blocks of kLarge bytes and more are therefore mapped on their
// own (mmap), 2 MB-aligned, rounded up to 2 MB and marked MADV_HUGEPAGE before their first use, so
// that the kernel backs them with 2 MB pages where transparent huge pages are enabled ("always" or
// "madvise"; elsewhere madvise does nothing), and unmapped when freed (no heap growth, no reuse of
// heap pages already mapped small). A header just before such a block says so: delete tells them
// from malloc's blocks by their alignment and a size no malloc chunk can have.
//
// Mid-size blocks (kMid up to kLarge) come from one HugeArena (app/huge_arena.hpp): in huge pages
// too, and kept when freed for the next block, where malloc would map each on its own and unmap it
// when freed (or trim its heap), so that every stage of a load faulted its arrays' 4 KB pages in
// again (7 600 faults in a render of armadillo, 690 with the arena; docs/loading.md, "Memory").
// A request the arena cannot meet goes to malloc. Everything smaller comes from malloc.
// glibc does much the same for every block under GLIBC_TUNABLES=glibc.malloc.hugetlb=1 with
// higher mmap and trim thresholds; this makes it the programs' default without setting malloc's
// thresholds (fixing malloc's mmap threshold made it fail under valgrind, past valgrind's brk
// limit). Measured on armadillo@2 (832 k triangles): bench/results/visibility.md, docs/memory.md.
//
// Not in the library: a library must not choose its host program's allocator. Not under
// AddressSanitizer or ThreadSanitizer, which replace operator new themselves (the arena's own
// tests run there, on arenas of their own).
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

#include "app/huge_arena.hpp"

namespace {

constexpr std::size_t kHuge = std::size_t(2) << 20;   // the x86-64 huge page
constexpr std::size_t kLarge = std::size_t(4) << 20;  // blocks from this size on
constexpr std::size_t kMid = std::size_t(16) << 10;   // blocks from this size to kLarge: the arena
// Address space for the mid-size blocks (no memory until used): 4 GB, a thousand live blocks of
// nearly 4 MB; past it, malloc.
constexpr std::size_t kArenaReserve = std::size_t(4) << 30;

// The arena, never destroyed: other static objects' destructors free blocks after main returns.
union MidBlocks {
    inkline::HugeArena arena;
    constexpr MidBlocks() : arena(kArenaReserve) {}
    ~MidBlocks() {}
};
constinit MidBlocks mid_blocks;
// Just before a mapped block: its rounded size, and a mark where a malloc block has its chunk's
// size (less than 2^63, so never equal to the mark).
struct Header {
    std::size_t rounded;
    std::uint64_t mark;
};
constexpr std::uint64_t kMark = 0xffffffffffffff06u;

std::size_t page_size() noexcept { return std::size_t(sysconf(_SC_PAGESIZE)); }

// A block of n >= kLarge bytes on its own mapping: the first 2 MB boundary at least a page into a
// mapping of the rounded size plus 2 MB, the page before it (the header's) and the block kept.
void* map_large(std::size_t n) noexcept {
    if (n > SIZE_MAX - 2 * kHuge) return nullptr;
    const std::size_t rounded = (n + kHuge - 1) & ~(kHuge - 1), length = rounded + kHuge, page = page_size();
    void* m = mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) return nullptr;
    const auto base = reinterpret_cast<std::uintptr_t>(m);
    const std::uintptr_t p = (base + page + kHuge - 1) & ~std::uintptr_t(kHuge - 1);
    if (p - page > base) munmap(m, p - page - base);
    if (p + rounded < base + length) munmap(reinterpret_cast<void*>(p + rounded), base + length - (p + rounded));
    *(reinterpret_cast<Header*>(p) - 1) = {rounded, kMark};
    madvise(reinterpret_cast<void*>(p), rounded, MADV_HUGEPAGE);  // advice: without it, 4 KB pages
    return reinterpret_cast<void*>(p);
}

void* allocate(std::size_t n) noexcept {
    if (n >= kLarge) return map_large(n);
    if (n >= kMid)
        if (void* p = mid_blocks.arena.allocate(n)) return p;
    return std::malloc(n == 0 ? 1 : n);
}

void release(void* p) noexcept {
    if (mid_blocks.arena.owns(p)) {
        mid_blocks.arena.release(p);
        return;
    }
    const auto a = reinterpret_cast<std::uintptr_t>(p);
    if (p && (a & (kHuge - 1)) == 0 && (reinterpret_cast<const Header*>(p) - 1)->mark == kMark) {
        const std::size_t page = page_size();
        munmap(reinterpret_cast<void*>(a - page), page + (reinterpret_cast<const Header*>(p) - 1)->rounded);
    } else {
        std::free(p);
    }
}

void* allocate_or_throw(std::size_t n) {
    while (true) {
        if (void* p = allocate(n)) return p;
        std::new_handler handler = std::get_new_handler();
        if (!handler) throw std::bad_alloc();
        handler();
    }
}

}  // namespace

void* operator new(std::size_t n) { return allocate_or_throw(n); }
void* operator new[](std::size_t n) { return allocate_or_throw(n); }
// (The nothrow forms as the standard describes them: the throwing form's result, or null.)
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
    try {
        return allocate_or_throw(n);
    } catch (...) {
        return nullptr;
    }
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
// (The aligned forms of new and delete keep libstdc++'s definitions: aligned_alloc and free.)
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }

#endif
