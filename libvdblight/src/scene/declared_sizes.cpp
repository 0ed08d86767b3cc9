// Sizes declared inside scene files, checked before Assimp trusts them (declared_sizes.h).
//
// Per format, what Assimp 5.2.5 allocates from a declared size, and the check made here:
//  - GLB / glTF: chunk lengths (must lie inside the file), buffer byteLength (Assimp allocates
//    it: must fit the BIN chunk, the data: URI or the external file), buffer views and
//    accessors (must lie inside their view; an accessor without a view is zero-filled at its
//    declared count), and the meshes Assimp and our loader build from them: every primitive's
//    vertices and faces times the number of node instances that reach its mesh (a node
//    hierarchy that reuses children multiplies them; a cycle is refused).
//  - FBX binary: every array property's declared length (Assimp inflates into a buffer of
//    that size): raw arrays must hold exactly that many bytes, zlib arrays cannot inflate by
//    more than deflate's maximum ratio; the total is charged. FBX ASCII: every `*N` count.
//  - COLLADA: every count="N" attribute (Assimp reserves N values): N <= bytes in the file.
//  - OFF: the vertex and face counts of the header. STL (binary): the triangle count against
//    the file size. 3DS counts are 16-bit (at most 65535 items per chunk): not scanned.
//  - DirectX .x: MSZIP-compressed files are charged 32 KiB per block, as Assimp allocates;
//    integer tokens (Assimp resizes arrays to a count it reads) must not exceed the file
//    size (text) or bound / 32 (binary: one element is at most 32 bytes in Assimp).
//  - OBJ: Assimp's allocation follows the bytes it parses; counted per object/group/material
//    statement (each becomes a mesh). PLY: vdblight's own reader checks its counts.
#include "declared_sizes.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "vdblight/errors.h"
#include "json.h"

namespace vdblight {

namespace {

using json::Json;

constexpr std::uint64_t kMiB = 1024ull * 1024ull;
/// Assimp's ear-clipping triangulation is quadratic in the corners of a polygon.
constexpr std::size_t kMaxPolygonCorners = 4096;

std::string humanBytes(double bytes) {
    char text[64];
    if (bytes >= 1024.0 * kMiB) std::snprintf(text, sizeof text, "%.1f GB", bytes / (1024.0 * kMiB));
    else std::snprintf(text, sizeof text, "%.0f MB", bytes / double(kMiB));
    return text;
}

/// What the importer will allocate, summed as the scan goes; refuses past the bound.
class Budget {
public:
    Budget(const std::string& path, std::uint64_t fileBytes)
        : path_(path), fileBytes_(fileBytes), bound_(double(sceneMemoryBound(fileBytes))) {}

    [[noreturn]] void refuse(const std::string& reason) const {
        throw SceneError("scene file '" + path_ + "': " + reason);
    }
    /// Charges `bytes` for `what`; refuses once the total exceeds the bound.
    void charge(double bytes, const std::string& what) {
        used_ += bytes;
        if (!(used_ <= bound_))  // also catches NaN
            refuse(what + " would need about " + humanBytes(used_) + " of memory, over the loader's bound of " +
                   humanBytes(bound_) + " for a file of " + std::to_string(fileBytes_) + " bytes (docs/scene.md)");
    }
    double bound() const { return bound_; }
    std::uint64_t fileBytes() const { return fileBytes_; }

private:
    std::string path_;
    std::uint64_t fileBytes_;
    double bound_;
    double used_ = 0;
};

std::string readAll(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

uint32_t u32le(const std::string& d, std::size_t at) {
    uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= uint32_t(uint8_t(d[at + k])) << (8 * k);
    return v;
}
uint64_t u64le(const std::string& d, std::size_t at) {
    return uint64_t(u32le(d, at)) | (uint64_t(u32le(d, at + 4)) << 32);
}

// ---------------------------------------------------------------------------------------
// glTF 2.0 (.gltf text, .glb binary)

/// A non-negative integer member (0 if absent); refuses negatives, fractions and absurd values.
double count(const Json* obj, const char* key, Budget& budget, const std::string& where) {
    const Json* v = obj ? obj->get(key) : nullptr;
    if (!v) return 0;
    if (v->type != Json::Number || !(v->number >= 0) || v->number != std::floor(v->number) || v->number > 1e15)
        budget.refuse(where + " has an invalid " + key);
    return v->number;
}

const Json* element(const Json& doc, const char* array, double index) {
    const Json* a = doc.get(array);
    if (!a || a->type != Json::Array || index < 0 || index >= double(a->items.size())) return nullptr;
    return &a->items[std::size_t(index)];
}

int components(const std::string& type) {
    static const std::map<std::string, int> k = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
                                                  {"MAT2", 4},   {"MAT3", 9}, {"MAT4", 16}};
    const auto it = k.find(type);
    return it == k.end() ? 16 : it->second;
}

int componentBytes(double componentType) {
    const int t = int(componentType);
    return (t == 5120 || t == 5121) ? 1 : (t == 5122 || t == 5123) ? 2 : 4;
}

/// Bytes a data: URI decodes to (base64 or percent-encoded), an upper bound.
double dataUriBytes(const std::string& uri) {
    const std::size_t comma = uri.find(',');
    if (comma == std::string::npos) return 0;
    const double payload = double(uri.size() - comma - 1);
    const bool base64 = uri.rfind(";base64", comma) != std::string::npos;
    return base64 ? payload * 3 / 4 + 3 : payload;
}

struct GltfCheck {
    const Json& doc;
    Budget& budget;
    std::string directory;      ///< for external buffers
    double binChunkBytes = -1;  ///< GLB: the BIN chunk's length (-1: none)

    std::vector<double> bufferBytes;

    void buffers() {
        const Json* list = doc.get("buffers");
        if (!list) return;
        for (std::size_t i = 0; i < list->items.size(); ++i) {
            const Json& b = list->items[i];
            const std::string where = "buffer " + std::to_string(i);
            const double length = count(&b, "byteLength", budget, where);
            const Json* uri = b.get("uri");
            double available = -1;
            if (!uri) {
                available = binChunkBytes;  // GLB body (or nothing in a .gltf)
            } else if (uri->type == Json::String && uri->string.compare(0, 5, "data:") == 0) {
                available = dataUriBytes(uri->string);
            } else if (uri->type == Json::String) {
                std::error_code ec;
                const auto size = std::filesystem::file_size(std::filesystem::path(directory) / uri->string, ec);
                if (!ec) available = double(size);  // a missing file is the importer's to report
            }
            if (available >= 0 && length > available + 3)
                budget.refuse(where + " declares " + std::to_string(uint64_t(length)) + " bytes but only " +
                              std::to_string(uint64_t(available)) + " exist");
            budget.charge(length, where);  // Assimp reads the whole buffer
            bufferBytes.push_back(length);
        }
    }

    /// Byte length of a buffer view, checked against its buffer (-1 if it does not exist).
    double viewBytes(double index, const std::string& where) {
        const Json* view = element(doc, "bufferViews", index);
        if (!view) return -1;
        const double buffer = count(view, "buffer", budget, where);
        const double offset = count(view, "byteOffset", budget, where), length = count(view, "byteLength", budget, where);
        if (buffer >= double(bufferBytes.size())) return -1;  // the importer reports the missing buffer
        if (offset + length > bufferBytes[std::size_t(buffer)])
            budget.refuse("buffer view " + std::to_string(uint64_t(index)) + " (" + where + ") reaches past the end of its buffer");
        return length;
    }

    /// Elements of an accessor after checking that its data lie inside its view.
    double accessorCount(double index, const std::string& where) {
        const Json* a = element(doc, "accessors", index);
        if (!a) return 0;
        const std::string name = "accessor " + std::to_string(uint64_t(index));
        const double n = count(a, "count", budget, name);
        const Json* type = a->get("type");
        const double elementBytes =
            double(components(type && type->type == Json::String ? type->string : "") *
                   componentBytes(count(a, "componentType", budget, name)));
        if (a->get("bufferView")) {
            const double view = viewBytes(count(a, "bufferView", budget, name), name);
            if (view >= 0) {
                const Json* vw = element(doc, "bufferViews", count(a, "bufferView", budget, name));
                const double stride = std::max(elementBytes, count(vw, "byteStride", budget, name));
                const double need = n > 0 ? count(a, "byteOffset", budget, name) + stride * (n - 1) + elementBytes : 0;
                if (need > view)
                    budget.refuse(name + " (" + where + ") declares " + std::to_string(uint64_t(n)) +
                                  " elements, more than its buffer view holds");
            }
        }
        if (const Json* sparse = a->get("sparse")) {
            if (count(sparse, "count", budget, name + " sparse") > n)
                budget.refuse(name + " has more sparse elements than elements");
        }
        budget.charge(n * std::max(elementBytes, 16.0), name + " (" + where + ")");  // Assimp's copy
        return n;
    }

    /// Vertices + faces one instance of each mesh adds to the scene (Assimp's and ours).
    std::vector<double> meshBytes() {
        std::vector<double> bytes;
        const Json* meshes = doc.get("meshes");
        if (!meshes) return bytes;
        for (std::size_t m = 0; m < meshes->items.size(); ++m) {
            const std::string where = "mesh " + std::to_string(m);
            double total = 0;
            const Json* prims = meshes->items[m].get("primitives");
            for (const Json& p : prims ? prims->items : std::vector<Json>{}) {
                double vertices = 0;
                if (const Json* attributes = p.get("attributes"))
                    for (const auto& [name, index] : attributes->members)
                        if (index.type == Json::Number) vertices = std::max(vertices, accessorCount(index.number, where));
                if (const Json* targets = p.get("targets"))
                    for (const Json& t : targets->items)
                        for (const auto& [name, index] : t.members)
                            if (index.type == Json::Number) accessorCount(index.number, where);
                const double indices = p.get("indices") ? accessorCount(count(&p, "indices", budget, where), where) : vertices;
                // Assimp: an aiMesh (about 2 KB before any data: measured 2.2 KB per primitive),
                // an aiFace (16 B + a heap array of 3) per triangle, the vertex arrays, then
                // JoinIdenticalVertices' tables; ours: 12 B per vertex and 16 B per triangle.
                const double bytes = 64.0 * vertices + 32.0 * indices + 4096.0;
                total += bytes;
                budget.charge(bytes, where);
            }
            bytes.push_back(total);
        }
        return bytes;
    }

    /// Node instances: a node listed as a child several times, or under several parents, is
    /// instanced once per path from a scene root (Assimp copies it; we flatten every copy).
    void instances(const std::vector<double>& meshBytes) {
        const Json* nodes = doc.get("nodes");
        if (!nodes) return;
        const std::size_t n = nodes->items.size();
        std::vector<double> paths(n, 0);      // root-to-node paths
        std::vector<int> state(n, 0);         // 0 new, 1 on stack, 2 done: cycle check
        std::vector<std::vector<std::size_t>> children(n);
        for (std::size_t i = 0; i < n; ++i)
            if (const Json* c = nodes->items[i].get("children"))
                for (const Json& k : c->items)
                    if (k.type == Json::Number && k.number >= 0 && k.number < double(n)) children[i].push_back(std::size_t(k.number));
        // Topological order by an explicit-stack DFS (no recursion on hostile depth).
        std::vector<std::size_t> order;
        for (std::size_t start = 0; start < n; ++start) {
            if (state[start]) continue;
            std::vector<std::pair<std::size_t, std::size_t>> stack{{start, 0}};
            state[start] = 1;
            while (!stack.empty()) {
                auto& [node, next] = stack.back();
                if (next < children[node].size()) {
                    const std::size_t c = children[node][next++];
                    if (state[c] == 1) budget.refuse("node " + std::to_string(c) + " is its own ancestor (a cycle in the node hierarchy)");
                    if (state[c] == 0) { state[c] = 1; stack.push_back({c, 0}); }
                } else {
                    state[node] = 2; order.push_back(node); stack.pop_back();
                }
            }
        }
        std::reverse(order.begin(), order.end());  // parents before children
        std::vector<bool> isChild(n, false);
        for (const auto& c : children) for (std::size_t k : c) isChild[k] = true;
        if (const Json* scenes = doc.get("scenes"))
            for (const Json& s : scenes->items)
                if (const Json* roots = s.get("nodes"))
                    for (const Json& r : roots->items)
                        if (r.type == Json::Number && r.number >= 0 && r.number < double(n)) paths[std::size_t(r.number)] += 1;
        for (std::size_t i = 0; i < n; ++i) if (!isChild[i] && paths[i] == 0) paths[i] = 1;  // Assimp's fallback root
        for (std::size_t node : order) {
            for (std::size_t c : children[node]) paths[c] += paths[node];
            budget.charge(paths[node] * 1024.0, "node " + std::to_string(node) + " instanced " +
                                                    std::to_string(uint64_t(paths[node])) + " times");
            const Json* mesh = nodes->items[node].get("mesh");
            if (mesh && mesh->type == Json::Number && mesh->number >= 0 && mesh->number < double(meshBytes.size()))
                budget.charge(paths[node] * meshBytes[std::size_t(mesh->number)],
                              "mesh " + std::to_string(uint64_t(mesh->number)) + " instanced " +
                                  std::to_string(uint64_t(paths[node])) + " times");
        }
    }

    void run() {
        buffers();
        if (const Json* views = doc.get("bufferViews"))
            for (std::size_t i = 0; i < views->items.size(); ++i) viewBytes(double(i), "declared");
        instances(meshBytes());
        if (const Json* images = doc.get("images"))
            for (const Json& image : images->items)
                if (image.get("bufferView")) budget.charge(viewBytes(count(&image, "bufferView", budget, "image"), "image"), "images");
    }
};

void checkGltf(const std::string& path, bool binary, Budget& budget) {
    const std::string data = readAll(path);
    std::string text = data;
    double binChunk = -1;
    if (binary) {
        if (data.size() < 20 || data.compare(0, 4, "glTF") != 0) return;  // Assimp reports the magic
        if (u32le(data, 8) > data.size())
            budget.refuse("the GLB header declares " + std::to_string(u32le(data, 8)) + " bytes but the file has " +
                          std::to_string(data.size()));
        // Chunks: length, type, data; each must lie inside the file.
        std::size_t at = 12;
        text.clear();
        for (int chunk = 0; at + 8 <= data.size(); ++chunk) {
            const uint64_t length = u32le(data, at);
            if (length > data.size() - at - 8)
                budget.refuse("GLB chunk " + std::to_string(chunk) + " declares " + std::to_string(length) +
                              " bytes, past the end of the file");
            const uint32_t type = u32le(data, at + 4);
            if (chunk == 0) text = data.substr(at + 8, length);
            else if (type == 0x004E4942u && binChunk < 0) binChunk = double(length);  // "BIN\0"
            at += 8 + length;
        }
    }
    Json doc;
    try {
        doc = json::JsonParser(text).parse();
    } catch (const std::runtime_error&) {
        return;  // not JSON: Assimp refuses it with its own message
    }
    GltfCheck check{doc, budget, std::filesystem::path(path).parent_path().string(), binChunk, {}};
    check.run();
}

// ---------------------------------------------------------------------------------------
// FBX

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

// ---------------------------------------------------------------------------------------
// COLLADA, OFF, STL, .x, OBJ

void checkCollada(const std::string& d, Budget& budget) {
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

}  // namespace

std::uint64_t sceneMemoryBound(std::uint64_t fileBytes) {
    return std::max<std::uint64_t>(256 * kMiB, 64 * fileBytes);
}

void checkDeclaredSizes(const std::string& path, const std::string& extension) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) return;  // unreadable files are reported by the caller
    Budget budget(path, size);
    if (extension == ".glb" || extension == ".gltf") {
        checkGltf(path, extension == ".glb", budget);
    } else if (extension == ".fbx") {
        const std::string d = readAll(path);
        if (d.compare(0, 18, "Kaydara FBX Binary") == 0) checkFbxBinary(d, budget);
        else checkFbxAscii(d, budget);
    } else if (extension == ".dae") {
        checkCollada(readAll(path), budget);
    } else if (extension == ".off") {
        checkOff(readAll(path), budget);
    } else if (extension == ".stl") {
        checkStl(readAll(path), budget);
    } else if (extension == ".x") {
        checkX(readAll(path), budget);
    } else if (extension == ".obj") {
        checkObj(path, budget);
    }
}

}  // namespace vdblight
