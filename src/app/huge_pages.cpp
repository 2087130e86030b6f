// Large arrays in transparent huge pages, for inkline's executables (the command line, the window,
// the benchmarks): the global operator new and delete of the program this object is linked into.
//
// The per-frame loops on a large model read arrays of tens of megabytes at scattered places (the
// mesh's positions, faces, edges and facing planes; a view's vertex images): with 4 KB pages most
// of those reads also miss the TLB. Blocks of kLarge bytes and more are therefore allocated from
// fresh mappings (malloc's mmap threshold is fixed at kLarge: no reuse of heap pages already
// mapped small), aligned to 2 MB and rounded up to it, and marked MADV_HUGEPAGE before their first
// use, so that the kernel backs them with 2 MB pages where transparent huge pages are enabled
// ("always" or "madvise"; elsewhere madvise does nothing). glibc does the same for every block
// under GLIBC_TUNABLES=glibc.malloc.hugetlb=1; this makes it the programs' default. Measured on
// armadillo@2 (832 k triangles): bench/results/visibility.md.
//
// Not in the library: a library must not choose its host program's allocator. Not under
// AddressSanitizer, which replaces operator new itself.
#if !defined(__SANITIZE_ADDRESS__)

#include <malloc.h>
#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

namespace {

constexpr std::size_t kHuge = std::size_t(2) << 20;   // the x86-64 huge page
constexpr std::size_t kLarge = std::size_t(4) << 20;  // blocks from this size on

// At static initialization (allocations made before it take malloc's defaults): a fixed threshold
// also stops malloc from raising it after a large block is freed.
struct Threshold {
    Threshold() { mallopt(M_MMAP_THRESHOLD, int(kLarge)); }
} threshold;

void* allocate(std::size_t n) noexcept {
    if (n >= kLarge && n <= SIZE_MAX - kHuge) {
        const std::size_t rounded = (n + kHuge - 1) & ~(kHuge - 1);
        if (void* p = std::aligned_alloc(kHuge, rounded)) {
            madvise(p, rounded, MADV_HUGEPAGE);  // advice: without huge pages the block is as before
            return p;
        }
        return nullptr;
    }
    return std::malloc(n == 0 ? 1 : n);
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
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return allocate(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return allocate(n); }
// Every block above comes from malloc or aligned_alloc: free releases either. (The aligned forms
// of new and delete keep libstdc++'s definitions, which use aligned_alloc and free as well.)
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

#endif
