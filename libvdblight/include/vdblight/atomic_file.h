// One way to write a file: under a temporary name beside the destination, renamed over it
// only when complete. Readers never see a half-written file, and a failure (an exception
// half way, a full disk, a failed rename) leaves neither the file nor the temporary behind.
//
// Public because the command-line program writes its CSV and script outputs through it too.
#pragma once

#include <functional>
#include <string>

namespace vdblight {

/// A temporary file ".<name>.tmp-<pid>-<n>" in the directory of `path`, created empty and
/// exclusively (O_EXCL), renamed over `path` by commit() and removed by the destructor if
/// commit() did not succeed.
class AtomicFile {
public:
    /// IoError ("cannot write '<path>': ...") if the directory does not exist or the
    /// temporary file cannot be created.
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
    /// Flushes the temporary file to disk (fsync) and renames it over the destination.
    /// IoError naming the destination on failure (the temporary file is then removed).
    void commit();

private:
    std::string path_, temp_;
    bool committed_ = false;
};

/// Writes `path` through an AtomicFile: `fill(tempPath)` writes the content, then the file is
/// committed. If `fill` or the commit throws, the temporary file is removed and the error
/// propagates: ValueError, FormatError, Cancelled and other typed errors of errors.h that are
/// not IoError unchanged; anything else as IoError "cannot write '<path>': <reason>" (with the
/// temporary name in the reason replaced by `path`).
void writeFileAtomically(const std::string& path, const std::function<void(const std::string& tempPath)>& fill);

/// The same with `bytes` as the file's whole content.
void writeFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace vdblight
