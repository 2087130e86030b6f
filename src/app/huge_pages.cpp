// Large arrays in transparent huge pages, for inkline's executables (the command line, the window,
// the benchmarks): the global operator new and delete of the program this object is linked into.
//
// The per-frame loops on a large model read arrays of tens of megabytes at scattered places (the
// mesh's positions, faces, edges and facing planes; a view's vertex images): with 4 KB pages most
// of those reads also miss the TLB. Blocks of kLarge bytes and more are therefore aligned to 2 MB,
// rounded up to it, and marked MADV_HUGEPAGE, so that the kernel backs them with 2 MB pages where
// transparent huge pages are enabled ("always" or "madvise"; elsewhere madvise does nothing) and
// the pages are not yet mapped: malloc serves such blocks from fresh mappings (above its mmap
// threshold) or from new heap. glibc does the same for every block under
// GLIBC_TUNABLES=glibc.malloc.hugetlb=1; this makes it the programs' default. Measured on
// armadillo@2 (832 k triangles): bench/results/visibility.md. (malloc's mmap threshold is left to
// malloc: fixing it made glibc's malloc fail under valgrind, whose brk limit it then could not
// fall back from.)
//
// Not in the library: a library must not choose its host program's allocator. Not under
// AddressSanitizer, which replaces operator new itself.
#if !defined(__SANITIZE_ADDRESS__)

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

namespace {

constexpr std::size_t kHuge = std::size_t(2) << 20;   // the x86-64 huge page
constexpr std::size_t kLarge = std::size_t(4) << 20;  // blocks from this size on

void* allocate(std::size_t n) noexcept {
    if (n >= kLarge && n <= SIZE_MAX - kHuge) {
        const std::size_t rounded = (n + kHuge - 1) & ~(kHuge - 1);
        // (posix_memalign: tools that replace malloc, valgrind's memcheck among them, replace it.)
        void* p = nullptr;
        if (posix_memalign(&p, kHuge, rounded) != 0) return nullptr;
        madvise(p, rounded, MADV_HUGEPAGE);  // advice: without huge pages the block is as before
        return p;
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
// Every block above comes from malloc or posix_memalign: free releases either. (The aligned forms
// of new and delete keep libstdc++'s definitions, which use aligned_alloc and free as well.)
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

#endif
