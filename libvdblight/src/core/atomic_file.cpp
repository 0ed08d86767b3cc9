// The one atomic file writer (vdblight/atomic_file.h): every file the library and the program
// write goes through it.
#include "vdblight/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>

#include "vdblight/errors.h"

namespace vdblight {

namespace fs = std::filesystem;

namespace {
std::string cannotWrite(const std::string& path, const std::string& reason) {
    return "cannot write '" + path + "': " + reason;
}

/// A fresh name in `dir` for a temporary copy of `name`, created empty with O_EXCL so that
/// two writers (threads or processes) never share one.
std::string createTemp(const std::string& path) {
    const fs::path p(path);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw IoError(cannotWrite(path, "directory '" + dir.string() + "' does not exist"));
    static std::atomic<unsigned> counter{0};
    std::random_device rd;
    for (int attempt = 0; attempt < 16; ++attempt) {
        const std::string name = "." + p.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                                 std::to_string(rd() ^ (counter++ * 2654435761u));
        const std::string temp = p.has_parent_path() ? (dir / name).string() : name;
        const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd >= 0) {
            ::close(fd);
            return temp;
        }
        if (errno != EEXIST) throw IoError(cannotWrite(path, std::strerror(errno)));
    }
    throw IoError(cannotWrite(path, "no free temporary file name"));
}

/// fsync, so that the rename never publishes a file whose blocks are not on disk yet.
void syncFile(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0 || ::fsync(fd) != 0) {
        const int err = errno;
        if (fd >= 0) ::close(fd);
        throw std::runtime_error(std::string("cannot flush the temporary file: ") + std::strerror(err));
    }
    ::close(fd);
}

/// An error's text about the destination: the temporary name replaced by `path`, and the
/// "cannot write '<path>': " prefix once.
std::string aboutDestination(std::string what, const std::string& temp, const std::string& path) {
    for (std::size_t at = what.find(temp); at != std::string::npos; at = what.find(temp, at + path.size()))
        what.replace(at, temp.size(), path);
    const std::string prefix = "cannot write '" + path + "'";
    return what.compare(0, prefix.size(), prefix) == 0 ? what : cannotWrite(path, what);
}
}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    if (path_.empty()) throw IoError("no output path given");
    temp_ = createTemp(path_);
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : path_(std::move(other.path_)), temp_(std::move(other.temp_)), committed_(other.committed_) {
    other.committed_ = true;  // the moved-from object owns no temporary file
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    std::error_code ec;
    fs::remove(temp_, ec);
}

void AtomicFile::commit() {
    try {
        syncFile(temp_);
        if (std::rename(temp_.c_str(), path_.c_str()) != 0) throw std::runtime_error(std::strerror(errno));
    } catch (const std::exception& e) {
        std::error_code ec;
        fs::remove(temp_, ec);
        committed_ = true;  // nothing left to remove
        throw IoError(cannotWrite(path_, e.what()));
    }
    committed_ = true;
}

void writeFileAtomically(const std::string& path, const std::function<void(const std::string& tempPath)>& fill) {
    AtomicFile file(path);
    try {
        fill(file.tempPath());
        file.commit();
    } catch (const IoError& e) {
        throw IoError(aboutDestination(e.what(), file.tempPath(), path));
    } catch (const Error&) {
        throw;  // about the content, not the file (ValueError, FormatError, Cancelled, ...)
    } catch (const std::exception& e) {
        throw IoError(aboutDestination(e.what(), file.tempPath(), path));
    }
}

void writeFileAtomically(const std::string& path, const std::string& bytes) {
    writeFileAtomically(path, [&](const std::string& temp) {
        std::FILE* f = std::fopen(temp.c_str(), "wb");
        if (!f) throw IoError(cannotWrite(temp, std::strerror(errno)));
        const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
        const bool closed = std::fclose(f) == 0;
        if (!written || !closed) throw IoError(cannotWrite(temp, "disk full or I/O error"));
    });
}

}  // namespace vdblight
