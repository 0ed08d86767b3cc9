// Typed exceptions thrown at the library's boundary. The library never exits the
// process; applications catch vdblight::Error once and print what() on one line.
#pragma once

#include <stdexcept>
#include <string>

namespace vdblight {

/// Base of every error the library throws.
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};
/// A parameter is out of range or inconsistent (spacing <= 0, too many nodes, ...).
struct ValueError : Error { using Error::Error; };
/// A scene could not be loaded or is unusable (no triangles, NaN coordinates, ...).
struct SceneError : Error { using Error::Error; };
/// A file could not be read or written.
struct IoError : Error { using Error::Error; };
/// A file was read but is not a (valid) vdblight volume.
struct FormatError : Error { using Error::Error; };
/// An allocation failed where the library can still stop cleanly: the process reached its
/// memory limit (a streamed volume's next leaf could not be read, vdb_stream.h; a file could
/// not be mapped for delayed loading). The app names the limit. Other allocations throw
/// std::bad_alloc as usual.
struct OutOfMemory : Error { using Error::Error; };
/// A long operation was cancelled through its Interrupter.
struct Cancelled : Error { using Error::Error; };

}  // namespace vdblight
