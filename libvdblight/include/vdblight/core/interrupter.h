// Progress reporting and cancellation for long operations (bakes, references).
//
// Like OpenVDB's util::NullInterrupter: the library calls these hooks, an application
// implements them (a terminal progress bar, a GUI, a Ctrl-C flag). Calls may come from
// any worker thread, so implementations must be thread-safe; the library calls
// `progress` often and cheaply, implementations should throttle their own output.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

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

/// A progress bar with ETA on stderr when it is a terminal (silent otherwise or if quiet), for
/// command-line tools; `cancelRequested` (e.g. a Ctrl-C flag set by a signal handler), when it
/// answers true, cancels the operation.
class TerminalProgress : public Interrupter {
public:
    explicit TerminalProgress(bool quiet, std::function<bool()> cancelRequested = {});
    void start(const char* task, uint64_t total) override;
    void progress(uint64_t done) override;
    bool wasInterrupted() override;
    void end() override;

private:
    void draw(uint64_t done, bool final);
    bool enabled_;
    std::function<bool()> cancelRequested_;
    const char* task_ = "";
    uint64_t total_ = 0;
    double startTime_ = 0;
    std::atomic<double> lastDraw_{0};
    std::atomic<bool> drawing_{false};
};

/// Human-readable durations ("1 min 28 s"), counts ("176.36 M") and sizes ("4.9 MiB"), as
/// progress bars and summaries (bakeSummary) print them.
std::string formatSeconds(double s);
std::string formatCount(double n);
std::string formatBytes(double bytes);

}  // namespace vdblight
