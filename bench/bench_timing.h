// Timing helpers shared by the benchmarks: wall-clock seconds and rays per second over a ray
// list split across threads.
#pragma once
#include <chrono>
#include <cstddef>
#include <thread>
#include <vector>

#include "geometry/ray.h"

namespace spt::bench {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Rays per second over `rays` using `threads` threads (ray i on thread i mod threads);
/// `trace(i, ray)` is called once per ray and returns 1 for a hit, summed into `hits`.
template <class Trace>
double rays_per_second(const std::vector<Ray>& rays, int threads, Trace trace, long& hits) {
    std::vector<long> counts(threads, 0);
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (int k = 0; k < threads; ++k)
        pool.emplace_back([&, k] {
            long c = 0;
            for (std::size_t i = k; i < rays.size(); i += threads) c += trace(i, rays[i]);
            counts[k] = c;
        });
    for (auto& t : pool) t.join();
    const double s = seconds_since(t0);
    hits = 0;
    for (long c : counts) hits += c;
    return rays.size() / s;
}

}  // namespace spt::bench
