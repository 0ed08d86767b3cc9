// See assimp_formats.h. The facts about Assimp 5.2.5 this relies on were checked against files
// written by Blender 3.4 (tests/scene_formats_blender_test.cpp):
//  - FBX: coordinates are left in the file's unit and axes; GlobalSettings (UpAxis, UpAxisSign,
//    FrontAxis, FrontAxisSign, CoordAxis, CoordAxisSign, UnitScaleFactor in centimetres) is in
//    the scene metadata. Light colour is Color x Intensity / 100; spot angles are full angles.
//  - COLLADA: Assimp multiplies the root node's transform by <unit meter> and, unless
//    AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, by the Z-up (or X-up) to Y-up rotation.
#include "assimp_formats.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <assimp/DefaultIOSystem.h>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/config.h>
#include <assimp/importerdesc.h>

#include "file_frame.h"
#include "texture_mean.h"

namespace vdblight {

namespace {

aiMatrix4x4 toAi(const FileFrame& f) {
    aiMatrix4x4 m;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) m[r][c] = ai_real(f.m[r][c]);
    return m;
}

std::string fileHead(const std::string& path, std::size_t n) {
    std::ifstream in(path, std::ios::binary);
    std::string head(n, '\0');
    in.read(&head[0], std::streamsize(n));
    head.resize(std::size_t(in.gcount()));
    return head;
}

std::string formatName(const Assimp::Importer& importer, const std::string& path, const std::string& ext,
                       const aiScene& ai) {
    if (ext == ".fbx") return fileHead(path, 18) == "Kaydara FBX Binary" ? "FBX (binary)" : "FBX (ascii)";
    if (ext == ".stl")
        return std::string(ai.mRootNode->mName.C_Str()) == "<STL_BINARY>" ? "STL (binary)" : "STL (ascii)";
    if (ext == ".gltf") return "glTF 2.0";
    if (ext == ".glb") return "glTF 2.0 (binary)";
    if (ext == ".obj") return "OBJ";
    if (ext == ".dae") return "COLLADA";
    if (ext == ".3ds") return "3DS";
    if (ext == ".off") return "OFF";
    if (ext == ".x") return "DirectX .x";
    const aiImporterDesc* desc = importer.GetImporterInfo(importer.GetImporterIndex(ext.c_str()));
    return desc ? desc->mName : ext.substr(1);
}

std::string number(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

const char* axisName(int axis) { return axis == 0 ? "X" : axis == 1 ? "Y" : "Z"; }

/// FBX GlobalSettings -> the rotation into +Y up, +Z front, +X coord (FBX's axis system:
/// the "front" axis is the one facing the viewer, our +Z), and the unit.
AssimpFormat fbxFrame(const aiScene& ai, const SceneLoadOptions& options, std::vector<std::string>& warnings) {
    AssimpFormat f;
    int32_t axis[3] = {0, 1, 2}, sign[3] = {1, 1, 1};  // coord (our X), up (our Y), front (our Z)
    double unitCm = 1.0;
    const aiMetadata* meta = ai.mMetaData;
    bool axesFound = false;
    if (meta) {
        axesFound = meta->Get("CoordAxis", axis[0]) && meta->Get("UpAxis", axis[1]) && meta->Get("FrontAxis", axis[2]);
        meta->Get("CoordAxisSign", sign[0]);
        meta->Get("UpAxisSign", sign[1]);
        meta->Get("FrontAxisSign", sign[2]);
        if (!meta->Get("UnitScaleFactor", unitCm)) {
            float f32 = 1.0f;
            if (meta->Get("UnitScaleFactor", f32)) unitCm = f32;
        }
    }
    bool axesValid = axesFound;
    for (int k = 0; k < 3; ++k) axesValid = axesValid && axis[k] >= 0 && axis[k] <= 2 && (sign[k] == 1 || sign[k] == -1);
    axesValid = axesValid && axis[0] != axis[1] && axis[1] != axis[2] && axis[0] != axis[2];
    if (axesFound && !axesValid) warnings.push_back("FBX GlobalSettings has an invalid axis system; read as Y up");
    if (!axesValid) { axis[0] = 0; axis[1] = 1; axis[2] = 2; sign[0] = sign[1] = sign[2] = 1; }
    if (!(std::isfinite(unitCm) && unitCm > 0)) {
        warnings.push_back("FBX UnitScaleFactor is not a positive number; read as 1 (centimetres)");
        unitCm = 1.0;
    }

    f.metresPerUnit = options.scale > 0 ? options.scale : unitCm / 100.0;
    f.units = options.scale > 0 ? describeUnit(f.metresPerUnit) + " (--scale)"
                                : describeUnit(f.metresPerUnit) + " (FBX UnitScaleFactor " +
                                      number(unitCm) + " cm)";
    FileFrame frame;
    if (options.up != UpAxis::FromFile) {
        frame = makeFileFrame(f.metresPerUnit, options.up == UpAxis::Z);
        f.up = std::string(options.up == UpAxis::Z ? "Z" : "Y") + " (--up)";
    } else {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) frame.m[r][c] = c == axis[r] ? sign[r] * f.metresPerUnit : 0.0;
        f.up = std::string(sign[1] < 0 ? "-" : "") + axisName(axis[1]) + (axesFound ? " (FBX UpAxis)" : " (default)");
    }
    f.root = toAi(frame);
    return f;
}

/// COLLADA: Assimp has put <unit meter> (and the up rotation, unless --up) into the root node.
AssimpFormat colladaFrame(const aiScene& ai, const SceneLoadOptions& options) {
    AssimpFormat f;
    f.colladaSpot = true;
    const aiMatrix4x4& r = ai.mRootNode->mTransformation;
    const double det = aiMatrix3x3(r).Determinant();
    const double fileScale = std::isfinite(det) && det != 0 ? std::cbrt(std::fabs(det)) : 1.0;
    double rescale = 1.0;
    if (options.scale > 0) {
        rescale = options.scale / fileScale;
        f.metresPerUnit = options.scale;
        f.units = describeUnit(f.metresPerUnit) + " (--scale)";
    } else {
        f.metresPerUnit = fileScale;
        f.units = describeUnit(f.metresPerUnit) + " (COLLADA <unit meter>)";
    }
    if (options.up != UpAxis::FromFile) {
        f.root = toAi(makeFileFrame(rescale, options.up == UpAxis::Z));
        f.up = std::string(options.up == UpAxis::Z ? "Z" : "Y") + " (--up)";
    } else {
        f.root = toAi(makeFileFrame(rescale, false));
        // Our Y is the file axis whose column is non-zero in the root's Y row.
        int fileUp = 1;
        for (int c = 0; c < 3; ++c)
            if (std::fabs(r[1][c]) > std::fabs(r[1][fileUp])) fileUp = c;
        f.up = std::string(axisName(fileUp)) + " (COLLADA <up_axis>)";
    }
    return f;
}

/// Serves the fixed OBJ text for the OBJ's own path, and every other file from disk.
class FixedObjIOSystem : public Assimp::DefaultIOSystem {
public:
    FixedObjIOSystem(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {}
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (file && path_ == file)
            return new Assimp::MemoryIOStream(reinterpret_cast<const uint8_t*>(text_.data()), text_.size());
        return DefaultIOSystem::Open(file, mode);
    }

private:
    std::string path_, text_;
};

bool isSpace(char c) { return c == ' ' || c == '\t'; }

}  // namespace

DiffuseTexture diffuseTexture(const aiScene& ai, const aiMaterial& am, const std::string& scenePath) {
    namespace fs = std::filesystem;
    DiffuseTexture t;
    aiString name;
    if (am.GetTexture(aiTextureType_BASE_COLOR, 0, &name) != AI_SUCCESS &&
        am.GetTexture(aiTextureType_DIFFUSE, 0, &name) != AI_SUCCESS)
        return t;
    t.present = true;
    t.name = name.C_Str();
    if (const aiTexture* embedded = ai.GetEmbeddedTexture(name.C_Str())) {
        if (embedded->mHeight != 0) {  // uncompressed BGRA8888 texels
            const std::size_t n = std::size_t(embedded->mWidth) * embedded->mHeight;
            double sum[3] = {0, 0, 0};
            auto lin = [](uint8_t v) { const double c = v / 255.0; return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
            for (std::size_t i = 0; i < n; ++i) {
                sum[0] += lin(embedded->pcData[i].r); sum[1] += lin(embedded->pcData[i].g); sum[2] += lin(embedded->pcData[i].b);
            }
            t.mean = Rgb(float(sum[0] / double(n)), float(sum[1] / double(n)), float(sum[2] / double(n)));
            t.read = n > 0;
            if (!t.read) t.why = "an empty embedded texture";
            return t;
        }
        t.read = pngMeanLinear(reinterpret_cast<const uint8_t*>(embedded->pcData), embedded->mWidth, t.mean, t.why);
        if (!t.read) t.why = "embedded: " + t.why + " (only PNG is read)";
        return t;
    }
    std::string relative = t.name;
    std::replace(relative.begin(), relative.end(), '\\', '/');
    const fs::path file = fs::path(relative).is_absolute() ? fs::path(relative) : fs::path(scenePath).parent_path() / relative;
    std::error_code ec;
    const auto size = fs::file_size(file, ec);
    if (ec || !fs::is_regular_file(file, ec)) { t.why = "file '" + file.string() + "' not found"; return t; }
    if (size > (std::uintmax_t(64) << 20)) { t.why = "file '" + file.string() + "' over 64 MiB"; return t; }  // within the 256 MB loader bound
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    t.read = pngMeanLinear(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), t.mean, t.why);
    if (!t.read) t.why = "'" + file.string() + "': " + t.why + " (only PNG is read)";
    return t;
}

std::string fixObjTextForAssimp(const std::string& text) {
    std::string out;
    bool changed = false;
    std::size_t begin = 0;
    while (begin < text.size()) {
        std::size_t end = text.find('\n', begin);
        end = end == std::string::npos ? text.size() : end + 1;
        std::size_t i = begin;
        while (i < end && isSpace(text[i])) ++i;
        changed = changed || i != begin;
        const bool vertexData = text[i] == 'v' && i + 1 < end && (isSpace(text[i + 1]) ||
                                (i + 2 < end && std::strchr("tnp", text[i + 1]) && isSpace(text[i + 2])));
        if (!vertexData) {
            out.append(text, i, end - i);
        } else {
            for (std::size_t k = i; k < end; ++k) {  // "0" before a number's leading "."
                const bool tokenStart = k == i || isSpace(text[k - 1]);
                const bool signedDot = (text[k] == '-' || text[k] == '+') && k + 1 < end && text[k + 1] == '.';
                if (tokenStart && (text[k] == '.' || signedDot)) {
                    changed = true;
                    if (signedDot) out += text[k++];
                    out += '0';
                }
                out += text[k];
            }
        }
        begin = end;
    }
    return changed ? out : std::string();
}

void useFixedObjText(Assimp::Importer& importer, const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string fixed = fixObjTextForAssimp(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
    if (!fixed.empty()) importer.SetIOHandler(new FixedObjIOSystem(path, std::move(fixed)));
}

std::vector<std::string> assimpExtensions() {
    Assimp::Importer importer;
    std::string list;  // "*.3d;*.3ds;..."
    importer.GetExtensionList(list);
    std::vector<std::string> out;
    std::stringstream ss(list);
    for (std::string item; std::getline(ss, item, ';');) {
        const auto dot = item.rfind('.');  // "*.mesh.xml" -> ".xml", as lowerExtension sees it
        if (dot == std::string::npos) continue;
        std::string ext = item.substr(dot);
        for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
        out.push_back(ext);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

void configureImporter(Assimp::Importer& importer, const std::string& ext, const SceneLoadOptions& options) {
    if (ext == ".dae" && options.up != UpAxis::FromFile)
        importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
}

AssimpFormat describeAssimpFormat(const Assimp::Importer& importer, const std::string& path, const std::string& ext,
                                  const aiScene& ai, const SceneLoadOptions& options,
                                  std::vector<std::string>& warnings) {
    AssimpFormat f;
    if (ext == ".fbx") f = fbxFrame(ai, options, warnings);
    else if (ext == ".dae") f = colladaFrame(ai, options);
    else {
        f.metresPerUnit = options.scale > 0 ? options.scale : 1.0;
        f.root = toAi(makeFileFrame(f.metresPerUnit, options.up == UpAxis::Z));
        const bool gltf = ext == ".gltf" || ext == ".glb";
        f.units = describeUnit(f.metresPerUnit) + (options.scale > 0 ? " (--scale)" : gltf ? " (glTF)" : " (as stored)");
        f.up = options.up == UpAxis::Z ? "Z (--up)" : options.up == UpAxis::Y ? "Y (--up)" : gltf ? "Y (glTF)" : "Y (as stored)";
        if (gltf) f.lights = LightConvention::Gltf;
    }
    f.name = formatName(importer, path, ext, ai);
    f.noMaterials = ext == ".stl" || ext == ".off";
    return f;
}

bool checkObjMaterialLibraries(const std::string& path, std::vector<std::string>& warnings) {
    namespace fs = std::filesystem;
    std::ifstream in(path, std::ios::binary);
    std::string line;
    std::size_t libraries = 0, missing = 0;
    for (std::size_t n = 0; n < (1u << 22) && std::getline(in, line); ++n) {
        std::size_t i = line.find_first_not_of(" \t");
        if (i == std::string::npos || line.compare(i, 7, "mtllib ") != 0) continue;
        std::string name = line.substr(i + 7);
        while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
        name.erase(0, name.find_first_not_of(" \t"));
        if (name.empty()) continue;
        ++libraries;
        std::error_code ec;
        const fs::path lib = fs::path(path).parent_path() / name;
        if (fs::is_regular_file(lib, ec)) continue;
        ++missing;
        warnings.push_back("OBJ material library '" + lib.string() + "' not found: its materials get the default albedo 0.8");
    }
    return libraries > 0 && missing == libraries;
}

}  // namespace vdblight
