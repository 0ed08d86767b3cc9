// A small, defensive PLY reader (see load_ply.h and docs/scene.md, "PLY").
//
// The file is read whole; the header is parsed line by line (at most kMaxHeaderBytes), then
// the body element by element in the declared order. Before any element is read, its count
// is checked against the bytes left: a binary record needs at least the sum of its scalar
// sizes and list-count sizes, an ascii record at least one byte per token. A list length is
// checked the same way before its items are read. Indices are range-checked against the
// declared vertex count. Every loop is bounded by the file size; nothing recurses.
#include "load_ply.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "vdblight/core/errors.h"
#include "scene/scene_origin.h"
#include "file_frame.h"

namespace vdblight {

namespace {

constexpr std::size_t kMaxHeaderBytes = 1 << 20;  ///< a real header is a few hundred bytes

enum class Format { Ascii, BinaryLittle, BinaryBig };

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::size_t sizeOf(Type t) {
    switch (t) {
    case Type::Int8: case Type::UInt8: return 1;
    case Type::Int16: case Type::UInt16: return 2;
    case Type::Int32: case Type::UInt32: case Type::Float32: return 4;
    case Type::Float64: return 8;
    }
    return 1;
}

bool isInteger(Type t) { return t != Type::Float32 && t != Type::Float64; }

bool parseType(const std::string& s, Type& t) {
    static const struct { const char* name; Type type; } kTypes[] = {
        {"char", Type::Int8},     {"int8", Type::Int8},      {"uchar", Type::UInt8},
        {"uint8", Type::UInt8},   {"short", Type::Int16},    {"int16", Type::Int16},
        {"ushort", Type::UInt16}, {"uint16", Type::UInt16},  {"int", Type::Int32},
        {"int32", Type::Int32},   {"uint", Type::UInt32},    {"uint32", Type::UInt32},
        {"float", Type::Float32}, {"float32", Type::Float32}, {"double", Type::Float64},
        {"float64", Type::Float64}};
    for (const auto& k : kTypes)
        if (s == k.name) { t = k.type; return true; }
    return false;
}

struct Property {
    std::string name;
    bool list = false;
    Type countType = Type::UInt8;  ///< lists only
    Type type = Type::Float32;     ///< the scalar, or a list's item type
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
    std::size_t lineNumber = 0;
};

class PlyReader {
public:
    PlyReader(const std::string& path, std::string data, const FileFrame& frame, SceneLoadReport& report)
        : path_(path), data_(std::move(data)), frame_(frame), report_(report) {}

    Scene read() {
        parseHeader();
        const Element* vertex = nullptr;
        for (const Element& e : elements_)
            if (e.name == "vertex") vertex = &e;
        if (!vertex) fail("no 'vertex' element in the header");
        vertexCount_ = vertex->count;
        if (vertexCount_ > std::numeric_limits<uint32_t>::max()) fail("more than 2^32 - 1 vertices");
        xyz_[0] = xyz_[1] = xyz_[2] = -1;
        for (std::size_t p = 0; p < vertex->properties.size(); ++p) {
            const Property& prop = vertex->properties[p];
            for (int k = 0; k < 3; ++k) {
                if (prop.name != std::string(1, char('x' + k))) continue;
                if (prop.list) fail(std::string("vertex property '") + prop.name + "' is a list");
                xyz_[k] = int(p);
            }
        }
        if (xyz_[0] < 0 || xyz_[1] < 0 || xyz_[2] < 0) fail("the vertex element lacks an x, y or z property");

        for (const Element& e : elements_) readElement(e);
        return buildScene();  // bytes after the last element are ignored, as other readers do
    }

private:
    [[noreturn]] void fail(const std::string& problem) const {
        throw SceneError("scene file '" + path_ + "': PLY: " + problem);
    }

    // ---------------------------------------------------------------- header
    void parseHeader() {
        std::size_t lineNo = 0;
        bool sawFormat = false;
        for (;;) {
            if (pos_ >= data_.size() || pos_ >= kMaxHeaderBytes)
                fail(pos_ >= kMaxHeaderBytes ? "header longer than 1 MiB" : "header has no 'end_header' line");
            const std::size_t eol = data_.find('\n', pos_);
            if (eol == std::string::npos) fail("header has no 'end_header' line");
            std::string line = data_.substr(pos_, eol - pos_);
            pos_ = eol + 1;
            ++lineNo;
            if (!line.empty() && line.back() == '\r') line.pop_back();
            std::istringstream in(line);
            std::vector<std::string> words;
            for (std::string w; in >> w;) words.push_back(w);
            const std::string bad = "bad header line " + std::to_string(lineNo);
            if (lineNo == 1) {
                if (line != "ply") fail("not a PLY file (first line is not 'ply')");
                continue;
            }
            if (words.empty()) continue;
            const std::string& key = words[0];
            if (key == "comment" || key == "obj_info") continue;
            if (key == "end_header") {
                if (words.size() != 1) fail(bad);
                break;
            }
            if (key == "format") {
                if (words.size() != 3 || sawFormat) fail(bad);
                if (words[2] != "1.0") fail("unsupported format version '" + words[2] + "'");
                if (words[1] == "ascii") format_ = Format::Ascii;
                else if (words[1] == "binary_little_endian") format_ = Format::BinaryLittle;
                else if (words[1] == "binary_big_endian") format_ = Format::BinaryBig;
                else fail("unknown format '" + words[1] + "'");
                sawFormat = true;
            } else if (key == "element") {
                if (words.size() != 3) fail(bad);
                Element e;
                e.name = words[1];
                e.lineNumber = lineNo;
                if (!parseCount(words[2], e.count)) fail(bad + ": bad element count '" + words[2] + "'");
                for (const Element& other : elements_)
                    if (other.name == e.name && (e.name == "vertex" || e.name == "face"))
                        fail("element '" + e.name + "' declared twice");
                elements_.push_back(std::move(e));
            } else if (key == "property") {
                if (elements_.empty()) fail(bad + ": property before any element");
                Property p;
                if (words.size() == 5 && words[1] == "list") {
                    p.list = true;
                    if (!parseType(words[2], p.countType) || !parseType(words[3], p.type)) fail(bad + ": unknown type");
                    if (!isInteger(p.countType)) fail(bad + ": list count type must be an integer type");
                    p.name = words[4];
                } else if (words.size() == 3) {
                    if (!parseType(words[1], p.type)) fail(bad + ": unknown type '" + words[1] + "'");
                    p.name = words[2];
                } else {
                    fail(bad);
                }
                elements_.back().properties.push_back(std::move(p));
            } else {
                // Old Blender ("Created by Blender3D 247 ...") and scanner software write free
                // text lines; Assimp skips them, and so do we, unless the line could declare a
                // property or an element, whose loss would change how the data is read.
                if (mayDeclareData(words))
                    fail(bad + ": unknown keyword '" + key.substr(0, 32) + "' in what may declare a property or element");
                if (unknownLines_++ == 0) firstUnknown_ = "line " + std::to_string(lineNo) + " '" + line.substr(0, 48) + "'";
            }
        }
        if (!sawFormat) fail("header has no 'format' line");
    }

    /// "prop float x", "elemnt vertex 8", "propery list uchar int vertex_indices": a type
    /// name or "list" among the words, or a count as the last of three.
    static bool mayDeclareData(const std::vector<std::string>& words) {
        Type t;
        uint64_t n;
        if (words.size() == 3 && parseCount(words[2], n)) return true;
        if (words.size() != 3 && words.size() != 5) return false;
        for (std::size_t k = 1; k + 1 < words.size(); ++k)
            if (words[k] == "list" || parseType(words[k], t)) return true;
        return false;
    }

    static bool parseCount(const std::string& s, uint64_t& out) {
        if (s.empty() || s.size() > 19) return false;
        uint64_t v = 0;
        for (char c : s) {
            if (c < '0' || c > '9') return false;
            v = v * 10 + uint64_t(c - '0');
        }
        out = v;
        return true;
    }

    // ---------------------------------------------------------------- body
    std::size_t remaining() const { return data_.size() - pos_; }

    void readElement(const Element& e) {
        if (e.count == 0 || e.properties.empty()) return;  // nothing to read
        // Smallest possible record: binary, the scalars and list counts; ascii, one byte per
        // token (a token and its separator take two, except the file's very last one).
        std::size_t minBytes = 0;
        for (const Property& p : e.properties)
            minBytes += format_ == Format::Ascii ? 1 : sizeOf(p.list ? p.countType : p.type);
        if (e.count > remaining() / minBytes)
            fail("element '" + e.name + "' declares " + std::to_string(e.count) + " records, more than the " +
                 std::to_string(remaining()) + " bytes left in the file can hold");

        const bool isVertex = e.name == "vertex";
        const bool isFace = e.name == "face";
        int indexList = -1;
        if (isFace)
            for (std::size_t p = 0; p < e.properties.size(); ++p) {
                const Property& prop = e.properties[p];
                if (prop.list && (prop.name == "vertex_indices" || prop.name == "vertex_index")) {
                    if (!isInteger(prop.type)) fail("face list '" + prop.name + "' has a non-integer item type");
                    indexList = int(p);
                    break;
                }
            }
        if (isVertex) positions_.reserve(std::size_t(e.count));  // count checked above
        if (isFace && indexList >= 0) polygonSizes_.reserve(std::size_t(e.count));

        cur_ = &e;
        for (uint64_t r = 0; r < e.count; ++r) {
            record_ = r;
            double xyz[3] = {0, 0, 0};
            for (std::size_t p = 0; p < e.properties.size(); ++p) {
                const Property& prop = e.properties[p];
                if (!prop.list) {
                    const double v = readScalar(prop.type, nullptr);
                    if (isVertex)
                        for (int k = 0; k < 3; ++k)
                            if (xyz_[k] == int(p)) xyz[k] = v;
                    continue;
                }
                const int64_t n = readInteger(prop.countType, "list length");
                if (n < 0) fail(where() + ": negative list length");
                const std::size_t itemBytes = format_ == Format::Ascii ? 1 : sizeOf(prop.type);
                if (uint64_t(n) > remaining() / itemBytes)
                    fail(where() + ": list length " + std::to_string(n) + " exceeds the bytes left in the file");
                if (int(p) != indexList) {
                    for (int64_t i = 0; i < n; ++i) readScalar(prop.type, nullptr);
                    continue;
                }
                for (int64_t i = 0; i < n; ++i) {
                    const int64_t index = readInteger(prop.type, "vertex index");
                    if (index < 0 || uint64_t(index) >= vertexCount_)
                        fail(where() + ": vertex index " + std::to_string(index) + " out of range (" +
                             std::to_string(vertexCount_) + " vertices)");
                    corners_.push_back(uint32_t(index));
                }
                polygonSizes_.push_back(uint64_t(n));
            }
            if (isVertex) {
                for (double c : xyz)  // beyond float range would not even convert: refused too
                    if (!(std::fabs(c) <= double(std::numeric_limits<float>::max())))
                        fail("vertex " + std::to_string(r) + " has a non-finite coordinate");
                const Vec3f v{float(xyz[0]), float(xyz[1]), float(xyz[2])};
                positions_.push_back(v);
            }
        }
    }

    void skipSpace() {
        while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
    }

    /// "element 'NAME' record R[: what]", for messages (built only on failure).
    std::string where(const char* what = nullptr) const {
        std::string s = "element '" + cur_->name + "' record " + std::to_string(record_);
        if (what) s += std::string(": ") + what;
        return s;
    }

    /// The next whitespace-separated ascii token, NUL-terminated in token_; fails at the end
    /// of the file or on a token longer than 64 characters (no number is that long).
    const char* token(const char* what) {
        skipSpace();
        if (pos_ >= data_.size()) fail(where(what) + ": file ends early");
        std::size_t n = 0;
        while (pos_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[pos_]))) {
            if (n == sizeof(token_) - 1) fail(where(what) + ": token longer than 64 characters");
            token_[n++] = data_[pos_++];
        }
        token_[n] = '\0';
        tokenLength_ = n;
        return token_;
    }

    /// Bytes of one binary scalar, in host order.
    uint64_t rawBits(Type t, const char* what) {
        const std::size_t n = sizeOf(t);
        if (remaining() < n) fail(where(what) + ": file ends early");
        uint64_t v = 0;
        for (std::size_t k = 0; k < n; ++k) {
            const uint64_t byte = uint8_t(data_[pos_ + k]);
            const std::size_t shift = format_ == Format::BinaryLittle ? 8 * k : 8 * (n - 1 - k);
            v |= byte << shift;
        }
        pos_ += n;
        return v;
    }

    double binaryValue(Type t, uint64_t bits) const {
        switch (t) {
        case Type::Int8: return double(int8_t(uint8_t(bits)));
        case Type::UInt8: return double(uint8_t(bits));
        case Type::Int16: return double(int16_t(uint16_t(bits)));
        case Type::UInt16: return double(uint16_t(bits));
        case Type::Int32: return double(int32_t(uint32_t(bits)));
        case Type::UInt32: return double(uint32_t(bits));
        case Type::Float32: { const uint32_t b = uint32_t(bits); float f; std::memcpy(&f, &b, 4); return double(f); }
        case Type::Float64: { double d; std::memcpy(&d, &bits, 8); return d; }
        }
        return 0;
    }

    double readScalar(Type t, const char* what) {
        if (format_ != Format::Ascii) return binaryValue(t, rawBits(t, what));
        const char* s = token(what);
        char* end = nullptr;
        const double v = std::strtod(s, &end);
        if (end != s + tokenLength_) fail(where(what) + ": '" + std::string(s).substr(0, 32) + "' is not a number");
        return v;
    }

    int64_t readInteger(Type t, const char* what) {
        if (format_ != Format::Ascii) return int64_t(binaryValue(t, rawBits(t, what)));  // exact: at most 32 bits
        const char* s = token(what);
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(s, &end, 10);
        if (end != s + tokenLength_ || errno == ERANGE)
            fail(where(what) + ": '" + std::string(s).substr(0, 32) + "' is not an integer");
        return int64_t(v);
    }

    // ---------------------------------------------------------------- scene
    /// Index into `corners` of the corner a polygon's fan starts from. Convex polygons start
    /// at corner 0; a quad with one reflex corner starts there (its fan then stays inside),
    /// as Assimp's triangulation did.
    static std::size_t fanStart(const std::vector<Vec3f>& positions, const uint32_t* corners, uint64_t n) {
        if (n != 4) return 0;
        for (std::size_t i = 0; i < 4; ++i) {
            const Vec3f p = positions[corners[i]];
            const Vec3f a = positions[corners[(i + 1) % 4]], b = positions[corners[(i + 2) % 4]],
                        c = positions[corners[(i + 3) % 4]];
            const Vec3f normal = cross(b - a, c - a);
            if (!(dot(normal, normal) > 0.0f)) continue;
            if (dot(cross(b - a, p - a), normal) > 0.0f && dot(cross(c - b, p - b), normal) > 0.0f &&
                dot(cross(a - c, p - c), normal) > 0.0f)
                return i;  // p lies inside the triangle of the other three: reflex corner
        }
        return 0;
    }

    Scene buildScene() {
        Scene scene;
        scene.name = std::filesystem::path(path_).stem().string();
        scene.positions = std::move(positions_);
        for (Vec3f& p : scene.positions) p = frame_.apply(p);  // a rotation and a uniform scale
        const uint32_t material = addMaterial(scene, Material{"default"});
        std::size_t at = 0;
        for (const uint64_t n : polygonSizes_) {
            const uint32_t* c = corners_.data() + at;
            at += std::size_t(n);
            if (n < 3) continue;  // points and lines carry no area
            const std::size_t s = fanStart(scene.positions, c, n);
            for (uint64_t k = 1; k + 1 < n; ++k)
                addIndexedTriangle(scene, c[s], c[(s + k) % n], c[(s + k + 1) % n], material);
        }
        ++scene.stats.meshes;
        report_.meshes = report_.meshInstances = 1;
        report_.format = format_ == Format::Ascii ? "PLY (ascii)"
                             : format_ == Format::BinaryLittle ? "PLY (binary little-endian)" : "PLY (binary big-endian)";
        report_.defaultAlbedoOnly = true;
        if (unknownLines_ > 0)
            report_.warnings.push_back("PLY: skipped " + std::to_string(unknownLines_) +
                                           " header line(s) with an unknown keyword (first: " + firstUnknown_ + ")");
        return scene;
    }

    std::string path_;
    std::string data_;
    FileFrame frame_;
    SceneLoadReport& report_;
    std::size_t unknownLines_ = 0;
    std::string firstUnknown_;
    std::size_t pos_ = 0;
    Format format_ = Format::Ascii;
    std::vector<Element> elements_;
    uint64_t vertexCount_ = 0;
    int xyz_[3] = {-1, -1, -1};
    std::vector<Vec3f> positions_;
    std::vector<uint32_t> corners_;
    std::vector<uint64_t> polygonSizes_;
    const Element* cur_ = nullptr;  ///< the element being read, for messages
    uint64_t record_ = 0;
    char token_[65] = {};
    std::size_t tokenLength_ = 0;
};

}  // namespace

Scene loadPlyScene(const std::string& path, const SceneLoadOptions& options, SceneLoadReport& report) {
    checkLoadOptions(options);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError("cannot read scene file '" + path + "': " + std::strerror(errno));
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw IoError("cannot read scene file '" + path + "'");
    Scene scene;
    try {
        const double scale = options.scale > 0 ? options.scale : 1.0;
        scene = PlyReader(path, std::move(data), makeFileFrame(scale, options.up == UpAxis::Z), report).read();
        report.metresPerUnit = scale;
        report.units = describeUnit(scale) + (options.scale > 0 ? " (--scale)" : " (as stored)");
        report.up = options.up == UpAxis::Z ? "Z (--up)" : options.up == UpAxis::Y ? "Y (--up)" : "Y (as stored)";
        validateScene(scene);
        recenterScene(scene);
    } catch (const SceneError& e) {
        const std::string what = e.what();
        if (what.find(path) != std::string::npos) throw;
        throw SceneError(what + " (file '" + path + "')");
    }
    return scene;
}

}  // namespace vdblight
