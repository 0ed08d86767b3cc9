// Declared counts in COLLADA, OFF, binary STL, DirectX .x and OBJ files, checked before
// Assimp allocates them (declared_sizes.cpp says what is checked per format).
#include <cctype>
#include <fstream>
#include <string>

#include "declared_sizes_detail.h"

namespace vdblight::declared_sizes {


void checkCollada(const std::string& d, Budget& budget) {
    // Numeric lists hold numbers only: Assimp 5.2.5 mis-sizes its index buffers when a byte it
    // cannot parse sits in a <p> list (found by fuzz_scene_dae: one corrupt byte in Blender's
    // cube asked for 450 MB).
    for (const char* tag : {"<p>", "<vcount>", "<v>", "<h>"}) {
        const std::string open = tag, close = "</" + open.substr(1);
        for (std::size_t at = d.find(open); at != std::string::npos; at = d.find(open, at + 1)) {
            const std::size_t end = d.find(close, at);
            if (end == std::string::npos) break;
            for (std::size_t k = at + open.size(); k < end; ++k)
                if (!std::isdigit(static_cast<unsigned char>(d[k])) && !std::isspace(static_cast<unsigned char>(d[k])))
                    budget.refuse("a COLLADA " + open + " index list holds a character that is not a digit (byte " +
                                  std::to_string(k) + ")");
        }
    }
    static const std::string key = "count=\"";
    for (std::size_t at = d.find(key); at != std::string::npos; at = d.find(key, at + key.size())) {
        std::size_t p = at + key.size();
        double n = 0;
        while (p < d.size() && std::isdigit(static_cast<unsigned char>(d[p])) && n < 1e18) n = 10 * n + (d[p++] - '0');
        if (n > double(d.size()))
            budget.refuse("a COLLADA element declares count=\"" + std::to_string(uint64_t(n)) + "\" in a file of " +
                          std::to_string(d.size()) + " bytes");
        budget.charge(16.0 * n, "COLLADA arrays");
    }
}

void checkOff(const std::string& d, Budget& budget) {
    // Header "[ST][C][N][4]OFF", then (after comments) "vertices faces edges".
    std::size_t p = d.find("OFF");
    if (p == std::string::npos || p > 8) return;
    p += 3;
    double counts[2] = {0, 0};
    for (double& c : counts) {
        while (p < d.size()) {
            if (d[p] == '#') { while (p < d.size() && d[p] != '\n') ++p; }
            else if (std::isspace(static_cast<unsigned char>(d[p]))) ++p;
            else break;
        }
        while (p < d.size() && std::isdigit(static_cast<unsigned char>(d[p])) && c < 1e18) c = 10 * c + (d[p++] - '0');
    }
    if (counts[0] + counts[1] > double(d.size()))
        budget.refuse("the OFF header declares " + std::to_string(uint64_t(counts[0])) + " vertices and " +
                      std::to_string(uint64_t(counts[1])) + " faces in a file of " + std::to_string(d.size()) + " bytes");
    budget.charge(64.0 * (counts[0] + counts[1]), "OFF vertices and faces");
}

void checkStl(const std::string& d, Budget& budget) {
    // Binary unless it starts with "solid" and reads as text (as Assimp decides); a binary
    // body holds 50 bytes per triangle after the 84-byte header.
    if (d.size() < 84 || (d.compare(0, 5, "solid") == 0 && d.size() != 84 + 50ull * u32le(d, 80))) return;
    const double triangles = u32le(d, 80);
    if (84 + 50 * triangles > double(d.size()))
        budget.refuse("the binary STL header declares " + std::to_string(uint64_t(triangles)) + " triangles, more than the file holds");
    budget.charge(128.0 * triangles, "STL triangles");
}

void checkX(const std::string& d, Budget& budget) {
    if (d.size() < 16 || d.compare(0, 4, "xof ") != 0) return;
    const std::string kind = d.substr(8, 4);
    if (kind == "tzip" || kind == "bzip") {
        // Assimp sizes its output as 32786 bytes per MSZIP block before inflating.
        double blocks = 0;
        for (std::size_t p = 22; p + 3 < d.size() - 1;) {
            const std::size_t next = uint8_t(d[p]) | (std::size_t(uint8_t(d[p + 1])) << 8);
            blocks += 1;
            budget.charge(32786.0, "the compressed .x file's " + std::to_string(uint64_t(blocks)) + " MSZIP blocks");
            p += 4 + next;
        }
        return;
    }
    if (kind == "txt ") {
        // Every integer token (a count or an index) is at most the file size.
        for (std::size_t p = 16; p < d.size(); ++p) {
            if (!std::isdigit(static_cast<unsigned char>(d[p]))) continue;
            const bool partOfWord = p > 0 && (std::isalnum(static_cast<unsigned char>(d[p - 1])) || d[p - 1] == '.' ||
                                              d[p - 1] == '_' || d[p - 1] == '-');
            double n = 0;
            const std::size_t start = p;
            while (p < d.size() && std::isdigit(static_cast<unsigned char>(d[p])) && n < 1e18) n = 10 * n + (d[p++] - '0');
            const bool integer = p >= d.size() || (d[p] != '.' && d[p] != 'e' && d[p] != 'E' && !std::isalpha(static_cast<unsigned char>(d[p])));
            if (!partOfWord && integer && n > double(d.size()) && start > 0 && d[start - 1] != '<')
                budget.refuse("a .x count of " + std::to_string(uint64_t(n)) + " exceeds the file's " + std::to_string(d.size()) + " bytes");
        }
        return;
    }
    if (kind == "bin ") {
        // Binary tokens: integer lists (0x06) and single integers (0x03) carry the counts.
        const double limit = budget.bound() / 32.0;
        for (std::size_t p = 16; p + 2 <= d.size();) {
            const unsigned token = uint8_t(d[p]) | (unsigned(uint8_t(d[p + 1])) << 8);
            p += 2;
            auto need = [&](double bytes) {
                if (double(p) + bytes > double(d.size())) budget.refuse("a binary .x token runs past the end of the file");
            };
            switch (token) {
            case 1: need(4); p += 4 + u32le(d, p); break;                // name
            case 2: need(4); p += 4 + u32le(d, p) + 2; break;            // string
            case 3: need(4); if (u32le(d, p) > limit) budget.refuse("a binary .x integer count is absurd"); p += 4; break;
            case 5: need(16); p += 16; break;                            // GUID
            case 6: case 7: {                                            // integer / float list
                need(4);
                const double n = u32le(d, p);
                const double each = token == 6 ? 4 : (d.compare(12, 4, "0064") == 0 ? 8 : 4);
                p += 4;
                need(n * each);
                if (token == 6)
                    for (std::size_t k = 0; k < std::size_t(n); ++k)
                        if (u32le(d, p + 4 * k) > limit) budget.refuse("a binary .x integer count is absurd");
                p += std::size_t(n * each);
                break;
            }
            default: break;                                              // one-word tokens
            }
        }
    }
}

void checkObj(const std::string& path, Budget& budget) {
    // Assimp builds one mesh per object / group and one more per material switch inside it
    // (measured unguarded: 200 000 `usemtl` lines in 4.5 MB took it past 1.9 GB); everything
    // else follows the bytes parsed. Its triangulation is quadratic in a polygon's corners:
    // one face of 900 000 corners did not finish in 10 minutes.
    std::ifstream in(path, std::ios::binary);
    std::string line;
    double groups = 0, materials = 0;
    while (std::getline(in, line)) {
        const std::size_t p = line.find_first_not_of(" \t");
        if (p == std::string::npos) continue;
        if (line.compare(p, 2, "o ") == 0 || line.compare(p, 2, "g ") == 0) groups += 1;
        else if (line.compare(p, 7, "usemtl ") == 0) materials += 1;
        else if (line.compare(p, 2, "f ") == 0) {
            std::size_t corners = 0;
            for (std::size_t k = p + 1; k < line.size(); ++k)
                corners += !std::isspace(static_cast<unsigned char>(line[k])) && std::isspace(static_cast<unsigned char>(line[k - 1]));
            if (corners > kMaxPolygonCorners)
                budget.refuse("an OBJ face has " + std::to_string(corners) + " corners (at most " +
                              std::to_string(kMaxPolygonCorners) + " are triangulated)");
        }
    }
    budget.charge(48.0 * double(budget.fileBytes()) + 2048.0 * groups + 16384.0 * materials,
                  "the OBJ file's " + std::to_string(uint64_t(groups)) + " objects/groups and " +
                      std::to_string(uint64_t(materials)) + " material switches");
}

}  // namespace vdblight::declared_sizes
