// Declared sizes in glTF 2.0 files (.gltf, .glb), checked before Assimp allocates them
// (declared_sizes.cpp says what is checked per format).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "declared_sizes_detail.h"
#include "json_access.h"

namespace vdblight::declared_sizes {

namespace {

using json::Json;
using json::elements;
using json::member;

/// A non-negative integer member (0 if absent); refuses negatives, fractions and absurd values.
double count(const Json* obj, const char* key, Budget& budget, const std::string& where) {
    const Json* v = member(obj, key);
    if (!v) return 0;
    const double n = json::numberOr(v, -1);
    if (!(n >= 0) || n != std::floor(n) || n > 1e15) budget.refuse(where + " has an invalid " + key);
    return n;
}

const Json* element(const Json& doc, const char* array, double index) {
    const Json::array_t& a = elements(member(doc, array));
    if (index < 0 || index >= double(a.size())) return nullptr;
    return &a[std::size_t(index)];
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
        const Json::array_t& list = elements(member(doc, "buffers"));
        for (std::size_t i = 0; i < list.size(); ++i) {
            const Json& b = list[i];
            const std::string where = "buffer " + std::to_string(i);
            const double length = count(&b, "byteLength", budget, where);
            const Json* uri = member(b, "uri");
            const std::string uriText = json::stringOr(uri);
            double available = -1;
            if (!uri) {
                available = binChunkBytes;  // GLB body (or nothing in a .gltf)
            } else if (uri->is_string() && uriText.compare(0, 5, "data:") == 0) {
                available = dataUriBytes(uriText);
            } else if (uri->is_string()) {
                std::error_code ec;
                const auto size = std::filesystem::file_size(std::filesystem::path(directory) / uriText, ec);
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
        const double elementBytes =
            double(components(json::stringOr(member(a, "type"))) *
                   componentBytes(count(a, "componentType", budget, name)));
        if (member(a, "bufferView")) {
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
        if (const Json* sparse = member(a, "sparse")) {
            if (count(sparse, "count", budget, name + " sparse") > n)
                budget.refuse(name + " has more sparse elements than elements");
        }
        budget.charge(n * std::max(elementBytes, 16.0), name + " (" + where + ")");  // Assimp's copy
        return n;
    }

    /// Vertices + faces one instance of each mesh adds to the scene (Assimp's and ours).
    std::vector<double> meshBytes() {
        std::vector<double> bytes;
        const Json::array_t& meshes = elements(member(doc, "meshes"));
        for (std::size_t m = 0; m < meshes.size(); ++m) {
            const std::string where = "mesh " + std::to_string(m);
            double total = 0;
            for (const Json& p : elements(member(meshes[m], "primitives"))) {
                double vertices = 0;
                for (const auto& [name, index] : json::members(member(p, "attributes")))
                    if (index.is_number()) vertices = std::max(vertices, accessorCount(index.get<double>(), where));
                for (const Json& t : elements(member(p, "targets")))
                    for (const auto& [name, index] : json::members(&t))
                        if (index.is_number()) accessorCount(index.get<double>(), where);
                const double indices = member(p, "indices") ? accessorCount(count(&p, "indices", budget, where), where) : vertices;
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
        const Json::array_t& nodes = elements(member(doc, "nodes"));
        const std::size_t n = nodes.size();
        std::vector<double> paths(n, 0);      // root-to-node paths
        std::vector<int> state(n, 0);         // 0 new, 1 on stack, 2 done: cycle check
        std::vector<std::vector<std::size_t>> children(n);
        for (std::size_t i = 0; i < n; ++i)
            for (const Json& k : elements(member(nodes[i], "children"))) {
                const double c = json::numberOr(&k, -1);
                if (c >= 0 && c < double(n)) children[i].push_back(std::size_t(c));
            }
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
        for (const Json& s : elements(member(doc, "scenes")))
            for (const Json& r : elements(member(s, "nodes"))) {
                const double root = json::numberOr(&r, -1);
                if (root >= 0 && root < double(n)) paths[std::size_t(root)] += 1;
            }
        for (std::size_t i = 0; i < n; ++i) if (!isChild[i] && paths[i] == 0) paths[i] = 1;  // Assimp's fallback root
        for (std::size_t node : order) {
            for (std::size_t c : children[node]) paths[c] += paths[node];
            budget.charge(paths[node] * 1024.0, "node " + std::to_string(node) + " instanced " +
                                                    std::to_string(uint64_t(paths[node])) + " times");
            const double mesh = json::numberOr(member(nodes[node], "mesh"), -1);
            if (mesh >= 0 && mesh < double(meshBytes.size()))
                budget.charge(paths[node] * meshBytes[std::size_t(mesh)],
                              "mesh " + std::to_string(uint64_t(mesh)) + " instanced " +
                                  std::to_string(uint64_t(paths[node])) + " times");
        }
    }

    void run() {
        buffers();
        const std::size_t views = elements(member(doc, "bufferViews")).size();
        for (std::size_t i = 0; i < views; ++i) viewBytes(double(i), "declared");
        instances(meshBytes());
        for (const Json& image : elements(member(doc, "images")))
            if (member(image, "bufferView")) budget.charge(viewBytes(count(&image, "bufferView", budget, "image"), "image"), "images");
    }
};

}  // namespace

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
    const Json doc = json::parseOrDiscarded(text);
    if (doc.is_discarded()) return;  // not JSON: Assimp refuses it with its own message
    GltfCheck check{doc, budget, std::filesystem::path(path).parent_path().string(), binChunk, {}};
    check.run();
}

}  // namespace vdblight::declared_sizes
