// An export's files written all or nothing (staged_files.h).
#include "staged_files.h"

#include "vdblight/core/errors.h"

namespace vdblight::exporter {

namespace fs = std::filesystem;

StagedFiles::~StagedFiles() {
    files_.clear();  // removes the temporary files before their directories
    std::error_code ec;
    for (auto it = createdDirs_.rbegin(); it != createdDirs_.rend(); ++it) fs::remove(*it, ec);
}

void StagedFiles::createDirectory(const fs::path& dir) {
    std::vector<fs::path> missing;
    std::error_code ec;
    for (fs::path p = fs::absolute(dir); !fs::exists(p, ec) && p != p.parent_path(); p = p.parent_path())
        missing.push_back(p);
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
        if (!fs::create_directory(*it, ec) && !fs::is_directory(*it))
            throw IoError("cannot create output directory '" + it->string() + "': " + ec.message());
        createdDirs_.push_back(*it);
    }
    if (!fs::is_directory(dir, ec)) throw IoError("cannot write into '" + dir.string() + "': not a directory");
}

std::string StagedFiles::stage(const fs::path& dir, const std::string& name) {
    files_.emplace_back((dir / name).string());
    return files_.back().tempPath();
}

std::vector<std::string> StagedFiles::commit() {
    std::vector<std::string> out;
    for (AtomicFile& f : files_) {
        f.commit();
        out.push_back(f.path());
    }
    files_.clear();
    createdDirs_.clear();
    return out;
}

}  // namespace vdblight::exporter
