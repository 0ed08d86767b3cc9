// Loading every format Assimp reads into a Scene (PLY: load_ply.cpp; what differs between
// formats, such as units, axes and light units: assimp_formats.cpp).
//
// Assimp's PreTransformVertices would bake node transforms into the meshes but drops the
// lights, so the node hierarchy is walked here and every mesh instance and light is put
// into world space with its node's accumulated transform.
//
// Assimp 5.2.5 facts this relies on (code/AssetLib/glTF2/glTF2Importer.cpp):
//  - material i of the aiScene is glTF material i; one default material is appended;
//  - KHR_materials_emissive_strength is NOT read, so it is read from the JSON below
//    (5.3 maps it to AI_MATKEY_EMISSIVE_INTENSITY, which then takes precedence);
//  - light colours are already multiplied by the glTF intensity;
//  - spot mAngleInnerCone/mAngleOuterCone are the glTF values, i.e. half-angles;
//  - a light is tied to its node by aiLight::mName == aiNode::mName.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "vdblight/core/errors.h"
#include "vdblight/scene/scene.h"
#include "scene/scene_origin.h"
#include "assimp_formats.h"
#include "declared_sizes.h"
#include "file_frame.h"
#include "json_access.h"
#include "load_ply.h"

namespace vdblight {

namespace {

using json::Json;

/// The JSON text of a .gltf, or the first (JSON) chunk of a .glb; empty if unreadable.
std::string gltfJsonText(const std::string& path, bool binary) {
    std::ifstream in(path, std::ios::binary);
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!binary) return data;
    auto u32 = [&](std::size_t at) {
        uint32_t v = 0;
        for (int k = 0; k < 4; ++k) v |= uint32_t(uint8_t(data[at + k])) << (8 * k);
        return v;
    };
    // 12-byte header (magic "glTF", version, length), then chunk length, type "JSON", data.
    if (data.size() < 20 || data.compare(0, 4, "glTF") != 0 || u32(16) != 0x4E4F534Au) return {};
    const uint32_t length = u32(12);
    if (length > data.size() - 20) return {};
    return data.substr(20, length);
}

/// emissiveStrength per glTF material index (1 where the extension is absent). Assimp has
/// already parsed the file successfully, so a parse failure here only loses the strength.
std::vector<float> gltfEmissiveStrengths(const std::string& path, bool binary) {
    std::vector<float> strengths;
    const Json doc = json::parseOrDiscarded(gltfJsonText(path, binary));
    for (const Json& m : json::elements(json::member(doc, "materials"))) {
        const Json* es = json::member(json::member(m, "extensions"), "KHR_materials_emissive_strength");
        strengths.push_back(float(json::numberOr(json::member(es, "emissiveStrength"), 1.0)));
    }
    return strengths;
}

// ---------------------------------------------------------------------------------------
// Assimp to Scene.

std::string oneLine(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    std::replace(s.begin(), s.end(), '\r', ' ');
    while (!s.empty() && s.back() == ' ') s.pop_back();
    return s;
}

Rgb toRgb(const aiColor3D& c) { return {c.r, c.g, c.b}; }
Vec3f toVec(const aiVector3D& v) { return {v.x, v.y, v.z}; }

void checkReadable(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists(path, ec)) throw IoError("scene file '" + path + "' does not exist");
    if (fs::is_directory(path, ec)) throw IoError("scene file '" + path + "' is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError("cannot read scene file '" + path + "': " + std::strerror(errno));
}

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

/// glTF baseColorFactor (or a diffuse colour), emissive colour x strength, doubleSided.
Material convertMaterial(const aiMaterial& am, float emissiveStrength) {
    Material m;
    aiString name;
    if (am.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) m.name = name.C_Str();
    if (m.name == AI_DEFAULT_MATERIAL_NAME) return m;  // Assimp's stand-in: our default grey
    aiColor3D c;
    if (am.Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS || am.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS)
        m.albedo = toRgb(c);
    if (am.Get(AI_MATKEY_COLOR_EMISSIVE, c) == AI_SUCCESS) {
        // Assimp >= 5.3 stores the glTF strength here itself; then it must not count twice.
        float intensity = emissiveStrength;
        am.Get(AI_MATKEY_EMISSIVE_INTENSITY, intensity);
        m.emission = toRgb(c) * intensity;
    }
    int twoSided = 0;
    if (am.Get(AI_MATKEY_TWOSIDED, twoSided) == AI_SUCCESS) m.twoSidedEmission = twoSided != 0;
    return m;
}

struct Loader {
    const std::string& path;
    const aiScene& ai;
    Scene& scene;
    const AssimpFormat& format;
    std::vector<uint32_t> materialOf;                       ///< aiScene material -> ours
    std::vector<bool> defaultMaterial;                      ///< aiScene material is Assimp's stand-in
    std::multimap<std::string, aiMatrix4x4> nodeTransforms;  ///< world transform by node name
    std::set<unsigned> meshesUsed;
    std::size_t meshInstances = 0;
    bool anyOwnMaterial = false;
    std::uint64_t memoryBound = 0;                           ///< sceneMemoryBound of the file

    void addMesh(unsigned meshIndex, const aiMatrix4x4& world) {
        const aiMesh& mesh = *ai.mMeshes[meshIndex];
        if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || !mesh.mVertices) return;  // points, lines
        // Instancing multiplies meshes: the flattened scene must stay within the bound too.
        const double bytes = 12.0 * double(scene.positions.size() + mesh.mNumVertices) +
                             16.0 * double(scene.materialIds.size() + mesh.mNumFaces);
        if (bytes > double(memoryBound))
            throw SceneError("scene file '" + path + "': its instanced meshes would need more memory than the loader's bound of " +
                             std::to_string(memoryBound >> 20) + " MB (docs/scene.md)");
        const auto base = uint32_t(scene.positions.size());
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
            const Vec3f p = toVec(world * mesh.mVertices[v]);
            if (!isFinite(p))
                throw SceneError("scene file '" + path + "': mesh '" + mesh.mName.C_Str() +
                                 "' has a non-finite vertex coordinate");
            scene.positions.push_back(p);
        }
        // A mirroring transform turns counter-clockwise into clockwise (glTF 2.0, 3.7.4):
        // swap two corners so that the front face stays the authored one.
        const bool mirrored = world.Determinant() < 0;
        const uint32_t materialId = materialOf.at(mesh.mMaterialIndex);
        for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
            const aiFace& face = mesh.mFaces[f];
            if (face.mNumIndices != 3) continue;
            for (int k = 0; k < 3; ++k)
                if (face.mIndices[k] >= mesh.mNumVertices)
                    throw SceneError("scene file '" + path + "': mesh '" + mesh.mName.C_Str() +
                                     "' has a vertex index out of range");
            const uint32_t a = base + face.mIndices[0], b = base + face.mIndices[1], c = base + face.mIndices[2];
            addIndexedTriangle(scene, a, mirrored ? c : b, mirrored ? b : c, materialId);
        }
        meshesUsed.insert(meshIndex);
        ++scene.stats.meshes;
        ++meshInstances;
        if (mesh.mMaterialIndex < defaultMaterial.size() && !defaultMaterial[mesh.mMaterialIndex]) anyOwnMaterial = true;
    }

    void addNode(const aiNode& node, const aiMatrix4x4& parent) {
        const aiMatrix4x4 world = parent * node.mTransformation;
        nodeTransforms.emplace(node.mName.C_Str(), world);
        for (unsigned k = 0; k < node.mNumMeshes; ++k) {
            if (node.mMeshes[k] >= ai.mNumMeshes)
                throw SceneError("scene file '" + path + "': node '" + node.mName.C_Str() +
                                 "' refers to a missing mesh");
            addMesh(node.mMeshes[k], world);
        }
        for (unsigned k = 0; k < node.mNumChildren; ++k) addNode(*node.mChildren[k], world);
    }

    /// Position as a point, direction as a vector (normalised) through the light's node.
    /// A light no node of the scene refers to is not part of the scene and is ignored.
    void addLight(const aiLight& light) {
        // Several lights may share a node name: each takes the first node not yet taken.
        auto it = nodeTransforms.lower_bound(light.mName.C_Str());
        if (it == nodeTransforms.end() || it->first != light.mName.C_Str()) return;
        const aiMatrix4x4 world = it->second;
        nodeTransforms.erase(it);
        const Vec3f position = toVec(world * light.mPosition);
        Vec3f direction = toVec(aiMatrix3x3(world) * light.mDirection);
        Rgb colour = toRgb(light.mColorDiffuse);
        float inner = light.mAngleInnerCone, outer = light.mAngleOuterCone;
        if (format.lights == LightConvention::BlenderPower) {
            // Blender writes its lights' power (W) into FBX Intensity x 100 and COLLADA colours;
            // a point light of power P radiates P / (4 pi) W/sr, and a spot light is a point
            // light with a mask (Blender, and its glTF exporter). Suns are W/m^2 already.
            if (light.mType != aiLightSource_DIRECTIONAL) colour = colour * float(1.0 / (4.0 * kPi));
            // Assimp gives full cone angles; COLLADA's is the falloff angle, with an outer
            // angle Assimp guesses from the falloff exponent: the cone is taken as hard.
            if (format.colladaSpot) inner = outer = 0.5f * light.mAngleInnerCone;
            else { inner *= 0.5f; outer *= 0.5f; }
        }
        if (light.mType == aiLightSource_SPOT || light.mType == aiLightSource_DIRECTIONAL) {
            if (!(length(direction) > 0.0f))
                throw SceneError("scene file '" + path + "': light '" + light.mName.C_Str() +
                                 "' has no direction");
            direction = normalize(direction);
        }
        switch (light.mType) {
        case aiLightSource_POINT: scene.pointLights.push_back({position, colour}); break;
        case aiLightSource_SPOT:
            scene.spotLights.push_back({position, direction, colour, std::min(inner, outer), outer});
            break;
        case aiLightSource_DIRECTIONAL: scene.directionalLights.push_back({direction, colour}); break;
        default: break;  // ambient and area lights have no glTF counterpart
        }
    }
};


/// Triangles, materials and lights of every node; the file's frame (unit, up axis) above the root.
Scene loadAssimpScene(const std::string& path, const std::string& ext, const SceneLoadOptions& options,
                      SceneLoadReport& report) {
    checkLoadOptions(options);
    Assimp::Importer importer;
    configureImporter(importer, ext, options);
    if (ext == ".obj") useFixedObjText(importer, path);  // indented lines, numbers like ".5"
    // No aiProcess_ValidateDataStructure: it rejects a mesh without faces (an OBJ of bare
    // vertices), which should rather end in "no triangles"; the walk checks indices itself.
    // Node transforms and instancing are applied by the walk below (Loader::addNode).
    // Degenerate triangles are dropped by addIndexedTriangle, which counts them (Assimp's
    // aiProcess_FindDegenerates would drop them silently).
    const aiScene* ai = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
    if (!ai || !ai->mRootNode)
        throw SceneError("cannot load scene file '" + path + "': " + oneLine(importer.GetErrorString()));

    Scene scene;
    scene.name = std::filesystem::path(path).stem().string();
    std::vector<std::string>& warnings = report.warnings;
    const bool objLibrariesMissing = ext == ".obj" && checkObjMaterialLibraries(path, warnings);
    AssimpFormat format = describeAssimpFormat(importer, path, ext, *ai, options, warnings);
    format.noMaterials = format.noMaterials || objLibrariesMissing;
    Loader loader{path, *ai, scene, format, {}, {}, {}, {}, 0, false,
                  sceneMemoryBound(std::filesystem::file_size(path))};
    try {
        const bool gltf = ext == ".gltf" || ext == ".glb";
        const std::vector<float> strengths = gltf ? gltfEmissiveStrengths(path, ext == ".glb") : std::vector<float>{};
        std::size_t unread = 0;
        std::string firstUnread;
        for (unsigned i = 0; i < ai->mNumMaterials; ++i) {
            const aiMaterial& am = *ai->mMaterials[i];
            const float strength = i < strengths.size() ? strengths[i] : 1.0f;
            Material m = format.noMaterials ? Material{} : convertMaterial(am, strength);
            if (format.noMaterials) m.name = AI_DEFAULT_MATERIAL_NAME;
            loader.defaultMaterial.push_back(m.name == AI_DEFAULT_MATERIAL_NAME);
            const DiffuseTexture texture = format.noMaterials ? DiffuseTexture{} : diffuseTexture(*ai, am, path);
            // glTF multiplies baseColorFactor by the texture; OBJ, FBX and COLLADA
            // renderers let the texture replace the diffuse colour.
            if (texture.read) m.albedo = gltf ? m.albedo * texture.mean : texture.mean;
            if (texture.present && !texture.read && unread++ == 0) firstUnread = texture.why;
            loader.materialOf.push_back(addMaterial(scene, m));
        }
        if (unread > 0)
            warnings.push_back(std::to_string(unread) + " diffuse texture(s) not read (first: " + firstUnread +
                               "): their materials' diffuse colour is the albedo");
        loader.addNode(*ai->mRootNode, format.root);
        for (unsigned i = 0; i < ai->mNumLights; ++i) loader.addLight(*ai->mLights[i]);
        report.meshes = loader.meshesUsed.size();
        report.meshInstances = loader.meshInstances;
        report.format = format.name;
        report.metresPerUnit = format.metresPerUnit;
        report.units = format.units;
        report.up = format.up;
        report.defaultAlbedoOnly = !loader.anyOwnMaterial;
        validateScene(scene);
        recenterScene(scene);  // far from the origin: local float geometry, double origin
    } catch (const SceneError& e) {
        const std::string what = e.what();
        if (what.find(path) != std::string::npos) throw;
        throw SceneError(what + " (file '" + path + "')");
    } catch (const std::out_of_range&) {
        throw SceneError("scene file '" + path + "': mesh with a material index out of range");
    }
    return scene;
}

}  // namespace

namespace {
bool isSupportedExtension(const std::string& ext) {
    const std::vector<std::string> supported = supportedSceneExtensions();
    return !ext.empty() && std::binary_search(supported.begin(), supported.end(), ext);
}

std::string supportedExtensionList() {
    std::string list;
    for (const std::string& e : supportedSceneExtensions()) list += (list.empty() ? "" : " ") + e;
    return list;
}
}  // namespace

std::vector<std::string> supportedSceneExtensions() {
    static const std::vector<std::string> extensions = [] {
        std::vector<std::string> e = assimpExtensions();
        if (std::find(e.begin(), e.end(), ".ply") == e.end()) e.push_back(".ply");
        std::sort(e.begin(), e.end());
        return e;
    }();
    return extensions;
}

Scene loadScene(const std::string& path) { return loadScene(path, SceneLoadOptions{}); }

Scene loadScene(const std::string& path, const SceneLoadOptions& options, SceneLoadReport* report) {
    checkReadable(path);
    const std::string ext = lowerExtension(path);
    checkDeclaredSizes(path, ext);  // the memory bound: declared sizes checked before any reader trusts them
    if (!isSupportedExtension(ext))
        throw SceneError("scene file '" + path + "': unsupported scene format '" + ext + "' (supported: " +
                         supportedExtensionList() + ")");
    SceneLoadReport local;
    SceneLoadReport& r = report ? *report : local;
    r = SceneLoadReport{};
    if (ext == ".ply") return loadPlyScene(path, options, r);  // our own reader: Assimp's crashes on corrupt files
    return loadAssimpScene(path, ext, options, r);
}

}  // namespace vdblight
