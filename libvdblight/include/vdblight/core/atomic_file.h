// One way to write a file: under a temporary name beside the destination, renamed over it
// only when complete. Readers never see a half-written file, and a failure (an exception
// half way, a full disk, a failed rename) leaves neither the file nor the temporary behind.
//
// A destination that exists and is no regular file is not replaced: a directory is refused,
// and a device, FIFO or socket (`-o /dev/null`, `-o /dev/stdout`, a named pipe) receives the
// content instead. Renaming over it would replace the device by a regular file (for root,
// /dev/null itself).
//
// Public because the command-line program writes its CSV and script outputs through it too.
#pragma once

#include <functional>
#include <string>

namespace vdblight {

/// A temporary file ".<name>.tmp-<pid>-<n>" in the directory of `path`, created empty and
/// exclusively (O_EXCL), renamed over `path` by commit() and removed by the destructor if
/// commit() did not succeed. If `path` is a device, FIFO or socket, the temporary file is in
/// the system's temporary directory instead (TMPDIR) and commit() copies it into `path`.
class AtomicFile {
public:
    /// IoError ("cannot write '<path>': ...") if the directory does not exist, `path` is a
    /// directory, or the temporary file cannot be created.
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(AtomicFile&& other) noexcept;
    AtomicFile& operator=(AtomicFile&&) = delete;
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    /// The destination.
    const std::string& path() const { return path_; }
    /// Where the content goes before commit().
    const std::string& tempPath() const { return temp_; }
    /// True if the destination is a device, FIFO or socket: commit() writes the content into
    /// it (opened for writing, never created, truncated or renamed over) instead of a rename.
    bool copiesIntoDestination() const { return copyInto_; }
    /// Flushes the temporary file to disk (fsync) and renames it over the destination (or, for
    /// a device, FIFO or socket, copies it into the destination and removes it). IoError
    /// naming the destination on failure (the temporary file is then removed).
    void commit();

private:
    std::string path_, temp_;
    bool committed_ = false;
    bool copyInto_ = false;
};

/// Writes `path` through an AtomicFile: `fill(tempPath)` writes the content, then the file is
/// committed. If `fill` or the commit throws, the temporary file is removed and the error
/// propagates: ValueError, FormatError, Cancelled and other typed errors of core/errors.h that are
/// not IoError unchanged; anything else as IoError "cannot write '<path>': <reason>" (with the
/// temporary name in the reason replaced by `path`).
void writeFileAtomically(const std::string& path, const std::function<void(const std::string& tempPath)>& fill);

/// The same with `bytes` as the file's whole content.
void writeFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace vdblight
