// Declared sizes in glTF 2.0 files (.gltf, .glb), checked before Assimp allocates them
// (declared_sizes.cpp says what is checked per format).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "declared_sizes_detail.h"
#include "json.h"

namespace vdblight::declared_sizes {

namespace {

using json::Json;

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
    Json doc;
    try {
        doc = json::JsonParser(text).parse();
    } catch (const std::runtime_error&) {
        return;  // not JSON: Assimp refuses it with its own message
    }
    GltfCheck check{doc, budget, std::filesystem::path(path).parent_path().string(), binChunk, {}};
    check.run();
}

}  // namespace vdblight::declared_sizes
