// The glTF binary container (glTF 2.0 specification, section 4.4 "GLB File Format"): a
// 12-byte header, a JSON chunk padded with spaces to 4 bytes, a BIN chunk padded with zeros.
#include "glb_writer.h"

namespace vdblight::exporter {

namespace {
void put32(std::string& out, uint32_t v) {
    for (int b = 0; b < 4; ++b) out.push_back(char(uint8_t(v >> (8 * b))));
}
}  // namespace

std::string glbBytes(std::string json, std::vector<uint8_t> bin) {
    while (json.size() % 4) json.push_back(' ');
    while (bin.size() % 4) bin.push_back(0);
    std::string out;
    out.reserve(12 + 8 + json.size() + 8 + bin.size());
    put32(out, 0x46546C67);  // "glTF"
    put32(out, 2);
    put32(out, uint32_t(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size())));
    put32(out, uint32_t(json.size()));
    put32(out, 0x4E4F534A);  // "JSON"
    out += json;
    if (!bin.empty()) {
        put32(out, uint32_t(bin.size()));
        put32(out, 0x004E4942);  // "BIN\0"
        out.append(reinterpret_cast<const char*>(bin.data()), bin.size());
    }
    return out;
}

uint32_t GlbBuffer::append(const void* data, std::size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);  // every view starts 4-byte aligned
    const uint32_t offset = uint32_t(bin.size());
    const uint8_t* p = static_cast<const uint8_t*>(data);
    bin.insert(bin.end(), p, p + bytes);
    return offset;
}

}  // namespace vdblight::exporter
