// A heap for the programs' mid-size blocks (src/app/huge_pages.cpp uses one for every block from
// 16 kB up to its 4 MB huge-page blocks), kept in transparent huge pages and reused from one stage
// to the next.
//
// Why: glibc maps each block above its mmap threshold on its own and unmaps it when freed, and
// trims its heaps, so the next stage's arrays fault their 4 KB pages in again (about 7 600 faults,
// 13 ms, in an SVG render of the 52 k-triangle armadillo). Here freed blocks keep their pages, and
// new pages come 2 MB at a time where the kernel gives huge pages ("always" or "madvise").
//
// Takes: requests of any size, from any thread. Gives: blocks aligned to kAlign bytes, or null
// when the request does not fit in what is left of the reserved address space (the caller then
// asks malloc). One mutex guards everything: these blocks are few (about a hundred a render)
// and each is written over many pages, so the lock costs nothing that shows.
//
// How: one range of address space reserved at the first request (PROT_NONE: no memory, no
// commit charge), made writable 2 MB at a time from its bottom as blocks are carved there. Each
// block starts with a kAlign-byte tag (its size and the size of the block just below it), so a
// freed block merges with free neighbours at once; free blocks sit in lists by size class and a
// request takes the best fit among them, else a new block from the top. Free blocks that reach
// the top join it, and a free top longer than the trim threshold goes back to the kernel
// (MADV_DONTNEED), so a program keeps at most that much of a past peak. Under AddressSanitizer
// the bytes of free blocks are poisoned, so a use after release is reported.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>

namespace inkline {

class HugeArena {
public:
    static constexpr std::size_t kAlign = 64;                   // blocks' alignment, and their tags' size
    static constexpr std::size_t kHugePage = std::size_t(2) << 20;  // the x86-64 huge page
    static constexpr std::size_t kDefaultTrim = std::size_t(64) << 20;

    // Maps nothing yet: the first allocate reserves `reserve_bytes` (rounded up to 2 MB) of address
    // space. constexpr, so a global arena is ready before any other static initializer runs.
    constexpr explicit HugeArena(std::size_t reserve_bytes, std::size_t trim_bytes = kDefaultTrim) noexcept
        : reserve_bytes_(reserve_bytes > (std::size_t(1) << 62) ? reserve_bytes  // (mmap refuses it)
                                                                : (reserve_bytes + kHugePage - 1) & ~(kHugePage - 1)),
          trim_bytes_(trim_bytes) {}
    ~HugeArena();
    HugeArena(const HugeArena&) = delete;
    HugeArena& operator=(const HugeArena&) = delete;

    // A block of at least n bytes, or null if it does not fit (or the reservation failed).
    void* allocate(std::size_t n) noexcept;
    // Gives back a block allocate returned (not null).
    void release(void* p) noexcept;
    // Whether p points into this arena's range: without the lock, so that delete can ask it of
    // every pointer (a pointer of ours reached the caller after its reservation was published).
    bool owns(const void* p) const noexcept {
        return reinterpret_cast<std::uintptr_t>(p) - base_.load(std::memory_order_relaxed) <
               size_.load(std::memory_order_relaxed);
    }

    struct Stats {
        std::size_t reserved = 0;     // address space
        std::size_t writable = 0;     // made writable from the bottom (touched at most this)
        std::size_t top = 0;          // bytes below the first never-used or trimmed byte
        std::size_t in_use = 0;       // bytes of live blocks, tags included
        std::size_t free_blocks = 0;  // free blocks below the top
        std::size_t largest_free = 0; // the largest of them, tag included
    };
    Stats stats() const;

private:
    struct Tag;
    static constexpr std::size_t kBins = 256;

    bool reserve() noexcept;
    Tag* best_fit(std::size_t size) noexcept;
    Tag* carve_top(std::size_t size) noexcept;
    void split(Tag* t, std::size_t size) noexcept;
    void link(Tag* t) noexcept;
    void unlink(Tag* t) noexcept;
    void lower_top(Tag* t) noexcept;
    void trim() noexcept;

    const std::size_t reserve_bytes_;
    const std::size_t trim_bytes_;
    mutable std::mutex mutex_;
    std::atomic<std::uintptr_t> base_{0};  // published once, with size_ after it
    std::atomic<std::size_t> size_{0};
    bool tried_ = false;           // reserve() was called (and failed if size_ is 0)
    std::size_t writable_ = 0;     // bytes from base_ made writable
    std::size_t top_ = 0;          // offset of the top: blocks lie below, never-used memory above
    std::size_t top_below_ = 0;    // size of the block just below the top (0 if top_ is 0)
    std::size_t in_use_ = 0;
    Tag* bins_[kBins] = {};        // free blocks by size class
};

}  // namespace inkline
