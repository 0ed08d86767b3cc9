// Declared sizes in FBX files (binary and ASCII), checked before Assimp allocates them
// (declared_sizes.cpp says what is checked per format).
#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "declared_sizes_detail.h"

namespace vdblight::declared_sizes {


/// Binary FBX: walks the node records (explicit stack) and checks every array property.
void checkFbxBinary(const std::string& d, Budget& budget) {
    if (d.size() < 27) return;
    const uint32_t version = u32le(d, 23);
    const bool wide = version >= 7500;  // 64-bit record offsets
    const std::size_t headerBytes = wide ? 25 : 13;
    std::size_t at = 27;
    double arrayBytes = 0;
    // Records: endOffset, numProperties, propertyListLen, nameLen, name, properties, children.
    std::vector<std::size_t> ends{d.size()};
    while (at + headerBytes <= d.size() && !ends.empty()) {
        if (at >= ends.back()) { at = ends.back(); ends.pop_back(); continue; }
        const uint64_t end = wide ? u64le(d, at) : u32le(d, at);
        const uint64_t properties = wide ? u64le(d, at + 8) : u32le(d, at + 4);
        const std::size_t nameLength = uint8_t(d[at + headerBytes - 1]);
        // A null record closes a list; at the top level it ends the records, and the footer
        // that follows (padding, version, magic: written by Blender and the FBX SDK) is not one.
        if (end == 0) { if (ends.size() == 1) break; at += headerBytes; continue; }
        if (end > ends.back() || end <= at) budget.refuse("an FBX record's end offset lies outside its parent");
        std::size_t p = at + headerBytes + nameLength;
        for (uint64_t k = 0; k < properties && p < end; ++k) {
            const char type = d[p++];
            switch (type) {
            case 'Y': p += 2; break;
            case 'C': p += 1; break;
            case 'I': case 'F': p += 4; break;
            case 'D': case 'L': p += 8; break;
            case 'S': case 'R':
                if (p + 4 > end) budget.refuse("an FBX string property runs past its record");
                p += 4 + std::size_t(u32le(d, p));
                break;
            case 'f': case 'i': case 'd': case 'l': case 'b': {
                if (p + 12 > end) budget.refuse("an FBX array property runs past its record");
                const double element = (type == 'd' || type == 'l') ? 8 : (type == 'b') ? 1 : 4;
                const double length = double(u32le(d, p)) * element;
                const uint32_t encoding = u32le(d, p + 4), stored = u32le(d, p + 8);
                p += 12;
                if (double(stored) > double(end - std::min<uint64_t>(p, end)))
                    budget.refuse("an FBX array declares " + std::to_string(stored) + " stored bytes past its record");
                // deflate inflates by at most 1032:1; raw arrays hold exactly their length.
                if ((encoding == 0 && double(stored) != length) || (encoding == 1 && length > 1032.0 * stored + 64))
                    budget.refuse("an FBX array declares " + std::to_string(uint64_t(length)) + " bytes but stores " +
                                  std::to_string(stored));
                arrayBytes += length;
                budget.charge(6.0 * length, "FBX arrays");  // decoded arrays, then meshes and faces
                p += stored;
                break;
            }
            default: budget.refuse(std::string("unknown FBX property type '") + type + "'");
            }
        }
        ends.push_back(std::size_t(end));
        at = std::min<std::size_t>(p, std::size_t(end));  // children follow the properties
    }
    (void)arrayBytes;
}

/// ASCII FBX: every `*N` array count must be at most the file size (an element takes >= 1 byte).
void checkFbxAscii(const std::string& d, Budget& budget) {
    double total = 0;
    for (std::size_t at = d.find('*'); at != std::string::npos; at = d.find('*', at + 1)) {
        std::size_t p = at + 1;
        double n = 0;
        while (p < d.size() && std::isdigit(static_cast<unsigned char>(d[p])) && n < 1e18) n = 10 * n + (d[p++] - '0');
        if (p == at + 1) continue;
        if (n > double(d.size()))
            budget.refuse("an FBX array declares " + std::to_string(uint64_t(n)) + " elements in a file of " +
                          std::to_string(d.size()) + " bytes");
        total += n;
        budget.charge(6.0 * 8.0 * n, "FBX arrays");
    }
    (void)total;
}

}  // namespace vdblight::declared_sizes
