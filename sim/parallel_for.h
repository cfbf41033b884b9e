// Work shared over threads through an atomic counter: one definition for the CPU reference's tiles and the
// optical-depth measurement's rows and views. Header-only (a template); brume_sim and everything above it
// may use it.
#pragma once

#include "sim/usable_cpus.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace brume {

// How many workers parallel_for runs: `requested` (0: every usable CPU), at most one per item.
inline int worker_count(int requested, std::size_t items) {
    unsigned n = requested > 0 ? unsigned(requested) : usable_cpus();
    if (n == 0) n = 1;
    return int(std::min<std::size_t>(n, std::max<std::size_t>(items, 1)));
}

// Calls body(item, worker) for every item in [0, count), worker in [0, worker_count(threads, count)) so
// callers can keep per-worker scratch. Items are handed out in runs that shrink as the work does (an
// eighth of each worker's share of what is left, down to one item), so uneven items still share out
// at the end while a large count costs few trips to the shared counter: taken one item at a time, the
// counter's cache line went back and forth between the cores at every item (trace's 7,500 tiles of
// the layers scene at 800x600: 16% of a frame on two threads). The calling thread is worker 0. The
// first exception stops the others at their next run and is rethrown here.
namespace detail {
// Runs a worker in a frame of its own: inlined into the caller, the calling thread's worker kept its
// hot locals (the body's sums and counters, spilled to the stack) in the caller's frame, beside the
// variables that the body's lambdas capture by reference and every other worker reads, and the line
// went back and forth between the cores (the reference's 2-layer frame at 800x600 took 2x longer on
// two threads than on one, depending on how the compiler laid out that frame).
template <class Worker>
[[gnu::noinline]] void run_worker(const Worker& worker, int w) {
    worker(w);
}
}  // namespace detail

template <class Body>
void parallel_for(std::size_t count, int threads, const Body& body) {
    struct alignas(64) Counter {  // a cache line of its own
        std::atomic<std::size_t> next{0};
    } counter;
    const int n = worker_count(threads, count);
    std::vector<std::exception_ptr> errors(static_cast<std::size_t>(n));
    const std::size_t split = 8 * std::size_t(n);
    auto worker = [&](int w) {
        try {
            std::size_t first = counter.next.load(std::memory_order_relaxed);
            for (;;) {
                if (first >= count) break;
                const std::size_t run = std::max<std::size_t>(1, (count - first) / split);
                if (!counter.next.compare_exchange_weak(first, first + run, std::memory_order_relaxed)) continue;
                for (std::size_t item = first; item < std::min(count, first + run); ++item) body(item, w);
                first = counter.next.load(std::memory_order_relaxed);
            }
        } catch (...) {
            errors[std::size_t(w)] = std::current_exception();
            counter.next.store(count);
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(std::size_t(n - 1));
    for (int w = 1; w < n; ++w) pool.emplace_back(worker, w);
    detail::run_worker(worker, 0);
    for (std::thread& t : pool) t.join();
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
}

}  // namespace brume
