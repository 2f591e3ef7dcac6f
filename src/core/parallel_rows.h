// Rows of a large table built in parallel at load time (environment maps: 4096 rows of 8192
// texels), with a result that does not depend on the number of threads: each row is computed
// by one call of `row(y)` that writes only that row's outputs, and whatever is summed over
// rows is summed afterwards in row order by the caller. Rows are handed out in increasing
// order, a few at a time, to the threads as they finish.
//
// Errors: a row that throws stops the handing out of later rows; the exception rethrown is
// the one of the lowest row that threw (every lower row has run by then), so a bad input is
// reported as a single-threaded scan in row order would report it.
//
// The thread count: load_threads(), which the program sets to the render's thread count
// (--threads) before it loads a scene; until then the hardware's.
#pragma once
#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace spt {

namespace parallel_detail {
inline std::atomic<int>& load_threads_setting() {
    static std::atomic<int> threads{0};
    return threads;
}
}  // namespace parallel_detail

/// Threads for building scene data (at least 1).
inline int load_threads() {
    const int t = parallel_detail::load_threads_setting().load(std::memory_order_relaxed);
    return t > 0 ? t : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}
/// Sets load_threads() (≤ 0: the hardware's thread count).
inline void set_load_threads(int threads) {
    parallel_detail::load_threads_setting().store(threads, std::memory_order_relaxed);
}

/// Calls row(y) for every y in [0, rows) on up to `threads` threads (the calling thread is one
/// of them). See the top of the file for the contract.
template <class F>
void parallel_rows(int rows, int threads, F&& row) {
    threads = std::clamp(threads, 1, std::max(1, rows));
    if (threads == 1) {
        for (int y = 0; y < rows; ++y) row(y);
        return;
    }
    // A few rows per hand-out: small enough to balance, large enough that the counter is not
    // contended.
    const int chunk = std::max(1, rows / (threads * 16));
    std::atomic<int> next{0};
    std::atomic<int> failed_row{rows};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto work = [&] {
        for (;;) {
            const int begin = next.fetch_add(chunk, std::memory_order_relaxed);
            if (begin >= rows || begin > failed_row.load(std::memory_order_relaxed)) return;
            const int end = std::min(rows, begin + chunk);
            for (int y = begin; y < end; ++y) {
                try {
                    row(y);
                } catch (...) {
                    const std::lock_guard<std::mutex> lock(failure_mutex);
                    if (y < failed_row.load(std::memory_order_relaxed)) {
                        failed_row.store(y, std::memory_order_relaxed);
                        failure = std::current_exception();
                    }
                    break;
                }
            }
        }
    };
    std::vector<std::jthread> helpers;
    helpers.reserve(static_cast<std::size_t>(threads - 1));
    for (int t = 1; t < threads; ++t) helpers.emplace_back(work);
    work();
    for (std::jthread& h : helpers) h.join();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace spt
