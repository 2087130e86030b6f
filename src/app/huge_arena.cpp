#include "app/huge_arena.hpp"

#include <sys/mman.h>

#include <bit>
#include <cstring>

#if defined(__SANITIZE_ADDRESS__)
#define INKLINE_ARENA_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define INKLINE_ARENA_ASAN 1
#endif
#endif
#if defined(INKLINE_ARENA_ASAN)
#include <sanitizer/asan_interface.h>
#endif

namespace inkline {

namespace {

void poison(const void* p, std::size_t n) noexcept {
#if defined(INKLINE_ARENA_ASAN)
    ASAN_POISON_MEMORY_REGION(p, n);
#else
    (void)p, (void)n;
#endif
}

void unpoison(const void* p, std::size_t n) noexcept {
#if defined(INKLINE_ARENA_ASAN)
    ASAN_UNPOISON_MEMORY_REGION(p, n);
#else
    (void)p, (void)n;
#endif
}

// Size classes: the power of two at or below the size, cut in four (bins of at most 25 % spread,
// so the first non-empty class above a request's holds only blocks that fit it).
std::size_t bin_of(std::size_t size) noexcept {
    const int high = std::bit_width(size) - 1;  // size >= kAlign, so high >= 6
    return std::size_t(high) * 4 + ((size >> (high - 2)) & 3);
}

}  // namespace

// At the start of every block, used or free. The links are meaningful only while it is free.
struct alignas(HugeArena::kAlign) HugeArena::Tag {
    std::size_t size;   // this block's bytes, its tag included: a multiple of kAlign
    std::size_t below;  // the size of the block just below it (0: it is the first)
    Tag* next;
    Tag* prev;
    bool free;

    std::byte* bytes() noexcept { return reinterpret_cast<std::byte*>(this); }
    Tag* above() noexcept { return reinterpret_cast<Tag*>(bytes() + size); }
    Tag* beneath() noexcept { return below ? reinterpret_cast<Tag*>(bytes() - below) : nullptr; }
    void* data() noexcept { return bytes() + kAlign; }
};

HugeArena::~HugeArena() {
    if (const std::size_t size = size_.load()) munmap(reinterpret_cast<void*>(base_.load()), size);
}

bool HugeArena::reserve() noexcept {
    tried_ = true;
    if (reserve_bytes_ == 0 || reserve_bytes_ > SIZE_MAX - kHugePage) return false;
    const std::size_t length = reserve_bytes_ + kHugePage;
    void* m = mmap(nullptr, length, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (m == MAP_FAILED) return false;
    // The range 2 MB-aligned, so that every 2 MB of it can be one huge page.
    const auto start = reinterpret_cast<std::uintptr_t>(m);
    const std::uintptr_t base = (start + kHugePage - 1) & ~std::uintptr_t(kHugePage - 1);
    if (base > start) munmap(m, base - start);
    if (base + reserve_bytes_ < start + length)
        munmap(reinterpret_cast<void*>(base + reserve_bytes_), start + length - base - reserve_bytes_);
    madvise(reinterpret_cast<void*>(base), reserve_bytes_, MADV_HUGEPAGE);  // advice: may do nothing
    base_.store(base, std::memory_order_relaxed);
    size_.store(reserve_bytes_, std::memory_order_release);
    return true;
}

void* HugeArena::allocate(std::size_t n) noexcept {
    static_assert(sizeof(Tag) == kAlign);
    if (n > reserve_bytes_) return nullptr;  // (also keeps the sum below from overflowing)
    const std::size_t size = (n + 2 * kAlign - 1) & ~(kAlign - 1);  // the tag and n, rounded up
    std::lock_guard<std::mutex> lock(mutex_);
    if (!tried_) reserve();
    if (size_.load(std::memory_order_relaxed) == 0) return nullptr;
    Tag* t = best_fit(size);
    if (t) {
        unlink(t);
        split(t, size);
    } else if (!(t = carve_top(size))) {
        return nullptr;
    }
    t->free = false;
    in_use_ += t->size;
    unpoison(t->data(), n);
    return t->data();
}

void HugeArena::release(void* p) noexcept {
    Tag* t = reinterpret_cast<Tag*>(static_cast<std::byte*>(p) - kAlign);
    std::lock_guard<std::mutex> lock(mutex_);
    in_use_ -= t->size;
    poison(t->data(), t->size - kAlign);
    const auto base = reinterpret_cast<std::byte*>(base_.load(std::memory_order_relaxed));
    if (t->above()->bytes() == base + top_) {
        lower_top(t);
        return;
    }
    // A free block never lies beside another free block or the top: merge with both neighbours.
    if (Tag* above = t->above(); above->free) {
        unlink(above);
        t->size += above->size;
        poison(above, kAlign);
    }
    if (Tag* beneath = t->beneath(); beneath && beneath->free) {
        unlink(beneath);
        beneath->size += t->size;
        poison(t, kAlign);
        t = beneath;
    }
    t->above()->below = t->size;
    link(t);
}

// t, freed, lies just below the top: it joins the top, with the free block below it if any.
void HugeArena::lower_top(Tag* t) noexcept {
    if (Tag* beneath = t->beneath(); beneath && beneath->free) {
        unlink(beneath);
        poison(t, kAlign);
        t = beneath;
    }
    const auto base = reinterpret_cast<std::byte*>(base_.load(std::memory_order_relaxed));
    top_ = std::size_t(t->bytes() - base);
    top_below_ = t->below;
    poison(t, kAlign);
    if (writable_ - top_ > trim_bytes_) trim();
}

// Gives the pages of a long free top back to the kernel and makes them inaccessible again.
void HugeArena::trim() noexcept {
    const std::size_t keep = (top_ + kHugePage - 1) & ~(kHugePage - 1);
    if (keep >= writable_) return;
    auto* from = reinterpret_cast<std::byte*>(base_.load(std::memory_order_relaxed)) + keep;
    madvise(from, writable_ - keep, MADV_DONTNEED);
    mprotect(from, writable_ - keep, PROT_NONE);
    writable_ = keep;
}

HugeArena::Tag* HugeArena::best_fit(std::size_t size) noexcept {
    Tag* best = nullptr;
    for (std::size_t b = bin_of(size); b < kBins && !best; ++b)
        for (Tag* t = bins_[b]; t; t = t->next)
            if (t->size >= size && (!best || t->size < best->size)) best = t;
    return best;
}

HugeArena::Tag* HugeArena::carve_top(std::size_t size) noexcept {
    const std::size_t reserved = size_.load(std::memory_order_relaxed);
    if (size > reserved - top_) return nullptr;
    const auto base = reinterpret_cast<std::byte*>(base_.load(std::memory_order_relaxed));
    if (top_ + size > writable_) {
        const std::size_t grown = (top_ + size + kHugePage - 1) & ~(kHugePage - 1);
        if (mprotect(base + writable_, grown - writable_, PROT_READ | PROT_WRITE) != 0) return nullptr;
        poison(base + writable_, grown - writable_);
        writable_ = grown;
    }
    Tag* t = reinterpret_cast<Tag*>(base + top_);
    unpoison(t, kAlign);
    t->size = size;
    t->below = top_below_;
    top_ += size;
    top_below_ = size;
    return t;
}

// t, just taken from its list, keeps `size` bytes; the rest (if any) becomes a free block.
void HugeArena::split(Tag* t, std::size_t size) noexcept {
    const std::size_t rest = t->size - size;
    if (rest == 0) return;
    t->size = size;
    Tag* r = t->above();
    unpoison(r, kAlign);
    r->size = rest;
    r->below = size;
    r->above()->below = rest;  // a used block: free blocks never lie beside free ones or the top
    link(r);
}

void HugeArena::link(Tag* t) noexcept {
    Tag*& head = bins_[bin_of(t->size)];
    t->free = true;
    t->prev = nullptr;
    t->next = head;
    if (head) head->prev = t;
    head = t;
}

void HugeArena::unlink(Tag* t) noexcept {
    if (t->prev) {
        t->prev->next = t->next;
    } else {
        bins_[bin_of(t->size)] = t->next;
    }
    if (t->next) t->next->prev = t->prev;
    t->free = false;
}

HugeArena::Stats HugeArena::stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    Stats s;
    s.reserved = size_.load(std::memory_order_relaxed);
    s.writable = writable_;
    s.top = top_;
    s.in_use = in_use_;
    for (Tag* head : bins_)
        for (Tag* t = head; t; t = t->next) {
            ++s.free_blocks;
            if (t->size > s.largest_free) s.largest_free = t->size;
        }
    return s;
}

}  // namespace inkline
