// Rows of an image split among threads (the tone stage's passes are independent per row).
#pragma once

#include <algorithm>
#include <thread>
#include <vector>

namespace inkline::tone {

// Calls fn(row_begin, row_end) on `threads` contiguous bands of [0, rows), the first band on the
// calling thread; returns when all are done.
template <class Fn>
void for_row_bands(int threads, int rows, Fn&& fn) {
    threads = std::clamp(threads, 1, std::max(1, rows));
    if (threads == 1) {
        fn(0, rows);
        return;
    }
    std::vector<std::thread> pool;
    const auto band = [&](int k) { return int(long(rows) * k / threads); };
    for (int k = 1; k < threads; ++k) pool.emplace_back([&, k] { fn(band(k), band(k + 1)); });
    fn(0, band(1));
    for (auto& t : pool) t.join();
}

}  // namespace inkline::tone
