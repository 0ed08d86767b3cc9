// An export's files written all or nothing (internal to the export module): each file under a
// temporary name (AtomicFile, atomic_file.h) in directories created as needed; commit()
// renames them all into place, and the destructor removes what is left, and the directories
// it created, after an error. `export` and `export --cells` both write through it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "vdblight/core/atomic_file.h"

namespace vdblight::exporter {

class StagedFiles {
public:
    StagedFiles() = default;
    StagedFiles(const StagedFiles&) = delete;
    StagedFiles& operator=(const StagedFiles&) = delete;
    ~StagedFiles();

    /// Creates `dir` and its missing parents (removed again unless committed). IoError if one
    /// cannot be created or `dir` is not a directory.
    void createDirectory(const std::filesystem::path& dir);
    /// The temporary path to write file `name` of `dir` to (created before).
    std::string stage(const std::filesystem::path& dir, const std::string& name);
    std::size_t count() const { return files_.size(); }
    /// Renames every staged file into place; their destinations, in staging order.
    std::vector<std::string> commit();

private:
    std::vector<AtomicFile> files_;
    std::vector<std::filesystem::path> createdDirs_;
};

}  // namespace vdblight::exporter
