// TerminalProgress (interrupter.h): the command-line tools' progress bar with ETA on stderr,
// redrawn at most five times a second from any worker thread, and their cancel request.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "vdblight/core/interrupter.h"

namespace vdblight {

namespace {
double nowSeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

TerminalProgress::TerminalProgress(bool quiet, std::function<bool()> cancelRequested)
    : enabled_(!quiet && ::isatty(STDERR_FILENO)), cancelRequested_(std::move(cancelRequested)) {}

void TerminalProgress::start(const char* task, uint64_t total) {
    task_ = task;
    total_ = total;
    startTime_ = nowSeconds();
    lastDraw_ = 0;
    if (enabled_) draw(0, false);
}

void TerminalProgress::progress(uint64_t done) {
    if (!enabled_) return;
    const double now = nowSeconds();
    double last = lastDraw_.load();
    if (now - last < 0.2 && done < total_) return;  // at most five redraws a second
    if (!lastDraw_.compare_exchange_strong(last, now)) return;
    bool expected = false;
    if (!drawing_.compare_exchange_strong(expected, true)) return;
    draw(done, false);
    drawing_ = false;
}

bool TerminalProgress::wasInterrupted() { return cancelRequested_ && cancelRequested_(); }

void TerminalProgress::end() {
    if (enabled_) std::fprintf(stderr, "\r\033[K");
}

void TerminalProgress::draw(uint64_t done, bool) {
    const double fraction = total_ ? double(done) / double(total_) : 1.0;
    const double elapsed = nowSeconds() - startTime_;
    const int width = 30;
    const int filled = int(fraction * width);
    std::string bar(std::size_t(filled), '#');
    bar.resize(width, '.');
    std::string eta = fraction > 0.001 ? formatSeconds(elapsed / fraction - elapsed) : "?";
    std::fprintf(stderr, "\r\033[K%s [%s] %5.1f%%  %s/%s  ETA %s", task_, bar.c_str(), 100.0 * fraction,
                 formatCount(double(done)).c_str(), formatCount(double(total_)).c_str(), eta.c_str());
    std::fflush(stderr);
}

}  // namespace vdblight
