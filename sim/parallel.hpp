// A plain parallel-for over [0, n) with std::thread: work items are claimed
// from an atomic counter, so results written per item are independent of the
// thread count and of scheduling.
#pragma once

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace sonarfusion::sim {

template <class Body>
void parallelFor(int n, int threads, const Body& body) {
    threads = std::max(1, std::min(threads, n));
    if (threads == 1) {
        for (int i = 0; i < n; ++i) body(i);
        return;
    }
    std::atomic<int> next{0};
    auto worker = [&] {
        for (int i = next++; i < n; i = next++) body(i);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
}

// Threads to use when the user asks for 0 ("all cores").
inline int resolveThreads(int requested) {
    if (requested > 0) return requested;
    return std::max(1u, std::thread::hardware_concurrency());
}

}  // namespace sonarfusion::sim
