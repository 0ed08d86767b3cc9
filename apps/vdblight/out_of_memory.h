// Running out of memory ends a command with one line, like every other error (issue 33): the
// line names the process's memory limit and how to raise it.
#pragma once

#include <exception>
#include <string>

namespace vdblight::app {

/// Sets aside a few MiB and a new-handler that gives them back at the first allocation that
/// fails (then lets it fail): the destructors that run while the error unwinds (OpenVDB's
/// trees allocate as they free their nodes) find memory, instead of ending the process with
/// std::terminate. Call once, first thing in main.
void installMemoryReserve();

/// "out of memory (<what>): the process may use at most 205.0 MB of address space (RLIMIT_AS;
/// `ulimit -v` or `prlimit --as` raises it)", or the data-segment limit (RLIMIT_DATA;
/// `ulimit -d`, `prlimit --data`), or that no limit is set and the machine's memory ran out.
std::string outOfMemoryMessage(const std::string& what);

/// True if `e` is TBB's report of a worker thread it could not start ("pthread_create has
/// failed: ...") while the process runs under a memory limit (RLIMIT_AS or RLIMIT_DATA), where
/// the thread's stack is what did not fit: main then reports it as out of memory.
bool threadStartFailedForMemory(const std::exception& e);

}  // namespace vdblight::app
