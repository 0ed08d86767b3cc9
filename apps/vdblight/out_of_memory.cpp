#include "out_of_memory.h"

#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <new>

namespace vdblight::app {

namespace {
constexpr std::size_t kReserveBytes = 4u << 20;
void* gReserve = nullptr;

void releaseReserveAndFail() {
    if (gReserve) {
        std::free(gReserve);
        gReserve = nullptr;
    }
    // Not a retry: the allocation that failed fails (std::bad_alloc, or null for nothrow new,
    // which the library's StreamedVolume turns into OutOfMemory), and the reserve is left to
    // the unwinding.
    throw std::bad_alloc();
}

std::string megabytes(rlim_t bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MB", double(bytes) / 1e6);
    return text;
}
}  // namespace

void installMemoryReserve() {
    gReserve = std::malloc(kReserveBytes);
    std::set_new_handler(releaseReserveAndFail);
}

namespace {
bool memoryLimited() {
    rlimit as{}, data{};
    return (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) ||
           (getrlimit(RLIMIT_DATA, &data) == 0 && data.rlim_cur != RLIM_INFINITY);
}
}  // namespace

bool threadStartFailedForMemory(const std::exception& e) {
    // oneTBB's rml thread_monitor::launch reports a failed pthread_create with this prefix
    // (std::runtime_error); seen under `prlimit --as` at 188-195 MB for a 5.2 MB default bake.
    return std::string(e.what()).rfind("pthread_create has failed", 0) == 0 && memoryLimited();
}

std::string outOfMemoryMessage(const std::string& what) {
    std::string line = "out of memory";
    if (!what.empty()) line += " (" + what + ")";
    rlimit as{}, data{};
    const bool asLimited = getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY;
    const bool dataLimited = getrlimit(RLIMIT_DATA, &data) == 0 && data.rlim_cur != RLIM_INFINITY;
    if (asLimited && (!dataLimited || as.rlim_cur <= data.rlim_cur))
        return line + ": the process may use at most " + megabytes(as.rlim_cur) +
               " of address space (RLIMIT_AS; `ulimit -v` or `prlimit --as` raises it)";
    if (dataLimited)
        return line + ": the process may use at most " + megabytes(data.rlim_cur) +
               " of data segment (RLIMIT_DATA; `ulimit -d` or `prlimit --data` raises it)";
    return line + ": no memory limit is set on the process, the machine's memory is used up";
}

}  // namespace vdblight::app
