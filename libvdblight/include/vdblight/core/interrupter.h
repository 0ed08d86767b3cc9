// Progress reporting and cancellation for long operations (bakes, references).
//
// Like OpenVDB's util::NullInterrupter: the library calls these hooks, an application
// implements them (a terminal progress bar, a GUI, a Ctrl-C flag). Calls may come from
// any worker thread, so implementations must be thread-safe; the library calls
// `progress` often and cheaply, implementations should throttle their own output.
#pragma once

#include <cstdint>

namespace vdblight {

class Interrupter {
public:
    virtual ~Interrupter() = default;
    /// A task with `total` units of work begins.
    virtual void start(const char* task, uint64_t total) {}
    /// `done` of `total` units are finished (monotonic).
    virtual void progress(uint64_t done) {}
    /// Return true to cancel: the operation then throws vdblight::Cancelled.
    virtual bool wasInterrupted() { return false; }
    /// The task ended (finished, failed or cancelled).
    virtual void end() {}
};

}  // namespace vdblight
