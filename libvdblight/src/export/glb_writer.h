// The glTF binary container (internal to the export module; glb_writer.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vdblight::exporter {

/// The GLB file of a glTF JSON document and its binary buffer (buffer 0).
std::string glbBytes(std::string json, std::vector<uint8_t> bin);

/// The binary buffer being filled: append() returns the 4-byte aligned offset of the data.
struct GlbBuffer {
    std::vector<uint8_t> bin;
    uint32_t append(const void* data, std::size_t bytes);
};

}  // namespace vdblight::exporter
