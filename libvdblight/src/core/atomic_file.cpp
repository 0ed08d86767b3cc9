// The one atomic file writer (vdblight/atomic_file.h): every file the library and the program
// write goes through it.
#include "vdblight/core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>

#include "vdblight/core/errors.h"

namespace vdblight {

namespace fs = std::filesystem;

namespace {
std::string cannotWrite(const std::string& path, const std::string& reason) {
    return "cannot write '" + path + "': " + reason;
}

/// A fresh name for a temporary copy of `path`, in its directory (or in `tempDir` if given),
/// created empty with O_EXCL so that two writers (threads or processes) never share one.
std::string createTemp(const std::string& path, const fs::path& tempDir = {}) {
    const fs::path p(path);
    const bool beside = tempDir.empty();
    const fs::path dir = !beside ? tempDir : p.has_parent_path() ? p.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw IoError(cannotWrite(path, "directory '" + dir.string() + "' does not exist"));
    static std::atomic<unsigned> counter{0};
    std::random_device rd;
    for (int attempt = 0; attempt < 16; ++attempt) {
        const std::string name = "." + p.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                                 std::to_string(rd() ^ (counter++ * 2654435761u));
        const std::string temp = !beside || p.has_parent_path() ? (dir / name).string() : name;
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

/// What the destination is now: absent or a regular file (replaced by a rename), a directory
/// (refused), or another kind (device, FIFO, socket: written into). stat follows symbolic
/// links, so a link to /dev/null counts as a device.
enum class Destination { Replaceable, Directory, Special };
Destination destinationKind(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) return Destination::Replaceable;  // absent (or unreadable: the rename says)
    if (S_ISDIR(st.st_mode)) return Destination::Directory;
    return S_ISREG(st.st_mode) ? Destination::Replaceable : Destination::Special;
}

/// Copies the file `from` into the existing `to` (a device, FIFO or socket), opened for
/// writing only: no O_CREAT, no O_TRUNC, no rename.
void copyInto(const std::string& from, const std::string& to) {
    const int in = ::open(from.c_str(), O_RDONLY);
    if (in < 0) throw std::runtime_error(std::string("cannot read the temporary file: ") + std::strerror(errno));
    const int out = ::open(to.c_str(), O_WRONLY);
    if (out < 0) {
        const int err = errno;
        ::close(in);
        throw std::runtime_error(std::strerror(err));
    }
    char buffer[1 << 16];
    int err = 0;
    for (;;) {
        const ssize_t got = ::read(in, buffer, sizeof buffer);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) {
            if (got < 0) err = errno;
            break;
        }
        for (ssize_t done = 0; done < got && !err;) {
            const ssize_t put = ::write(out, buffer + done, std::size_t(got - done));
            if (put < 0 && errno == EINTR) continue;
            if (put < 0) err = errno;
            else done += put;
        }
        if (err) break;
    }
    if (::close(out) != 0 && !err) err = errno;
    ::close(in);
    if (err) throw std::runtime_error(std::strerror(err));
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
    switch (destinationKind(path_)) {
    case Destination::Directory:
        throw IoError(cannotWrite(path_, "it is a directory"));
    case Destination::Special: {
        // A rename would put a regular file where the device is, and the device's directory
        // (/dev) is seldom writable: the temporary file goes to the temporary directory.
        copyInto_ = true;
        std::error_code ec;
        const fs::path tempDir = fs::temp_directory_path(ec);
        if (ec) throw IoError(cannotWrite(path_, "no temporary directory: " + ec.message()));
        temp_ = createTemp(path_, tempDir);
        return;
    }
    case Destination::Replaceable:
        break;
    }
    temp_ = createTemp(path_);
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : path_(std::move(other.path_)), temp_(std::move(other.temp_)), committed_(other.committed_),
      copyInto_(other.copyInto_) {
    other.committed_ = true;  // the moved-from object owns no temporary file
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    std::error_code ec;
    fs::remove(temp_, ec);
}

void AtomicFile::commit() {
    try {
        if (copyInto_) {
            copyInto(temp_, path_);  // never a rename: the device (or FIFO, socket) stays
            std::error_code ec;
            fs::remove(temp_, ec);
        } else {
            syncFile(temp_);
            if (std::rename(temp_.c_str(), path_.c_str()) != 0) throw std::runtime_error(std::strerror(errno));
        }
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
