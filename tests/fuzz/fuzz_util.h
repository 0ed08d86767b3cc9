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
/// returns that path.
inline const std::string& writeInput(const uint8_t* data, std::size_t size, const std::string& extension) {
    static const std::string path = [&] {
        std::string dir = (std::filesystem::temp_directory_path() / "vdblight_fuzz_XXXXXX").string();
        if (!mkdtemp(dir.data())) throw std::runtime_error("mkdtemp failed");
        static std::string removeAtExit = dir;
        std::atexit([] { std::error_code ec; std::filesystem::remove_all(removeAtExit, ec); });
        return dir + "/input" + extension;
    }();
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f || (size > 0 && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0)
        throw std::runtime_error("cannot write the fuzz input file");
    return path;
}

}  // namespace vdblight::fuzz
