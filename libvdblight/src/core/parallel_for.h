// The one parallel loop of the library: an index range on a TBB arena of the requested size,
// with progress and cancelling through an Interrupter (interrupter.h). (Internal.)
//
// Determinism is the caller's: f(i) must depend only on i (its sample streams derive from the
// seed and i) and write only i's outputs; then the result is the same for any thread count.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>

#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"

namespace vdblight::core {

/// Workers for a `threads` option: the value itself, or all cores for 0.
inline int threadCount(int threads) { return threads > 0 ? threads : tbb::this_task_arena::max_concurrency(); }

/// Progress and cancelling of one task: Interrupter::start on construction and end on
/// destruction (also when an exception leaves the task), a counter of finished units that any
/// thread advances, and the Cancelled error to throw once the interrupter asked to stop.
/// Without an interrupter it only counts.
class TaskProgress {
public:
    /// A task of `total` units named `task`; `cancelMessage` is the Cancelled error's text.
    TaskProgress(Interrupter* in, const char* task, uint64_t total, std::string cancelMessage)
        : in_(in), owns_(true), cancelMessage_(std::move(cancelMessage)) {
        if (in_) in_->start(task, total);
    }
    /// Counts for a task that the caller started and ends itself (no start / end here).
    TaskProgress(Interrupter* in, std::string cancelMessage) : in_(in), cancelMessage_(std::move(cancelMessage)) {}
    ~TaskProgress() {
        if (in_ && owns_) in_->end();
    }
    TaskProgress(const TaskProgress&) = delete;
    TaskProgress& operator=(const TaskProgress&) = delete;

    /// One more unit finished: reported, then the interrupter is asked whether to stop.
    void step() {
        const uint64_t finished = done_.fetch_add(1, std::memory_order_relaxed) + 1;
        if (in_) poll(finished);
    }
    /// `done` units finished in all (a task that counts in batches).
    void reportDone(uint64_t done) {
        done_.store(done, std::memory_order_relaxed);
        if (in_) poll(done);
    }
    bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }
    /// Throws Cancelled if the interrupter asked to stop.
    void throwIfCancelled() const {
        if (cancelled()) throw Cancelled(cancelMessage_);
    }

private:
    void poll(uint64_t done) {
        in_->progress(done);
        if (in_->wasInterrupted()) cancelled_ = true;
    }

    Interrupter* in_ = nullptr;
    bool owns_ = false;
    std::string cancelMessage_;
    std::atomic<uint64_t> done_{0};
    std::atomic<bool> cancelled_{false};
};

/// Calls f(i) for every i in [0, count) on an arena of threadCount(threads) workers. With
/// `progress`, every finished i is one step, items not begun when a cancel is asked are
/// skipped, and the loop then throws Cancelled.
template <typename F>
void parallelFor(std::size_t count, int threads, F&& f, TaskProgress* progress = nullptr) {
    tbb::task_arena arena(threadCount(threads));
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) {
                if (progress && progress->cancelled()) return;
                f(i);
                if (progress) progress->step();
            }
        });
    });
    if (progress) progress->throwIfCancelled();
}

}  // namespace vdblight::core
