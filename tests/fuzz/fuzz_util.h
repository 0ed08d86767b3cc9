// Shared by the libFuzzer harnesses: the fuzz input written to a file with a fixed name in a
// private temporary directory (the loaders take paths, and pick the format by extension).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace vdblight::fuzz {

/// Writes data to DIR/input<extension> (DIR made once per process, removed at exit) and
/// returns that path RELATIVE to DIR, which becomes the working directory: the loaders then
/// see the same path bytes on every run and machine. With an absolute mkdtemp path, the
/// random letters of the directory name steered Assimp's path handling (case folding, length
/// loops) into different coverage on every run, so the same seed grew a different corpus.
inline const std::string& writeInput(const uint8_t* data, std::size_t size, const std::string& extension) {
    static const std::string path = [&] {
        std::string dir = (std::filesystem::temp_directory_path() / "vdblight_fuzz_XXXXXX").string();
        if (!mkdtemp(dir.data())) throw std::runtime_error("mkdtemp failed");
        static std::string removeAtExit = dir;
        std::atexit([] { std::error_code ec; std::filesystem::remove_all(removeAtExit, ec); });
        if (chdir(dir.c_str()) != 0) throw std::runtime_error("chdir to the fuzz directory failed");
        return "input" + extension;
    }();
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0)
        throw std::runtime_error("cannot write the fuzz input file");
    return path;
}

}  // namespace vdblight::fuzz
