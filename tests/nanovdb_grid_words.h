// A .nvdb's grid buffers back to back (vdblight_meta first), as a renderer uploads them, for
// the C build of the PNanoVDB lookup (nanovdb_lookup_c.h): nanovdb_export_test and
// vdblight_bench's NanoVDB rows read files the same way.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <nanovdb/util/IO.h>

namespace vdblight::test {

/// The grids of `file` in 64-bit words, because PNanoVDB reads 64-bit values at 8-byte aligned
/// offsets; each grid's size in bytes goes to `gridBytes` if given (a grid that does not end
/// 32-byte aligned would shift the next one).
inline std::vector<uint64_t> nanoGridWords(const std::string& file, std::vector<std::size_t>* gridBytes = nullptr) {
    const auto handles = nanovdb::io::readGrids<nanovdb::HostBuffer, std::vector>(file);
    std::size_t bytes = 0;
    for (const auto& h : handles) bytes += h.size();
    std::vector<uint64_t> words((bytes + 7) / 8);
    std::size_t at = 0;
    for (const auto& h : handles) {
        if (gridBytes) gridBytes->push_back(h.size());
        std::memcpy(reinterpret_cast<char*>(words.data()) + at, h.data(), h.size());
        at += h.size();
    }
    return words;
}

}  // namespace vdblight::test
