// What differs between the formats read through Assimp: their names, units, up axes, light
// units and spot-angle conventions (docs/scene.md, "Formats and what is read").
#pragma once

#include <string>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include "vdblight/scene/scene.h"

namespace vdblight {

/// How punctual light values from Assimp become ours.
enum class LightConvention {
    Gltf,          ///< KHR_lights_punctual: W/sr (cd read as W/sr) and W/m^2, spot half-angles
    BlenderPower,  ///< FBX, COLLADA, others: colour x intensity is Blender's power (W) for point
                   ///< and spot lights (-> / 4 pi W/sr), W/m^2 for directional; full cone angles
};

struct AssimpFormat {
    std::string name;        ///< for SceneStats::format
    aiMatrix4x4 root;        ///< put above the root node: file coordinates -> metres, +Y up
    double metresPerUnit = 1.0;
    std::string units, up;   ///< for SceneStats
    LightConvention lights = LightConvention::BlenderPower;
    bool colladaSpot = false;  ///< Assimp's COLLADA inner angle is the falloff (full) angle; its outer is a guess
    /// The file has no materials (STL, OFF; an OBJ whose material libraries are all missing):
    /// Assimp's stand-ins (0.6 grey, unnamed) are replaced by vdblight's default.
    bool noMaterials = false;
};

/// The extensions Assimp reads, lower case with the dot.
std::vector<std::string> assimpExtensions();

/// Importer properties that must be set before ReadFile (COLLADA: leave the up axis to us
/// when --up is given).
void configureImporter(Assimp::Importer& importer, const std::string& ext, const SceneLoadOptions& options);

/// Reads the file's unit and up axis (FBX GlobalSettings metadata, COLLADA <unit>/<up_axis> as
/// Assimp applied them) and combines them with `options`. Problems go to `warnings`.
AssimpFormat describeAssimpFormat(const Assimp::Importer& importer, const std::string& path, const std::string& ext,
                                  const aiScene& ai, const SceneLoadOptions& options,
                                  std::vector<std::string>& warnings);

/// Whether a material has a diffuse (or glTF base-colour) texture, and if so its mean linear
/// colour: `read` true and `mean` set for a PNG (embedded, or a file beside the scene file),
/// else `read` false and `why` says why. Files over 64 MiB are not read (they are read whole; the
/// loader memory bound of docs/scene.md has a 256 MB floor).
struct DiffuseTexture {
    bool present = false, read = false;
    Rgb mean{0, 0, 0};
    std::string name, why;
};
DiffuseTexture diffuseTexture(const aiScene& ai, const aiMaterial& am, const std::string& scenePath);

/// Assimp 5.2.5's OBJ parser skips a line that starts with white space and drops a vertex line
/// with a number written without its leading zero (".5", "-.5"); the error then shows up as
/// "vertex index out of range" or as missing faces. Returns the text with both fixed (leading
/// white space removed, "0" inserted), or "" if no line needs it.
std::string fixObjTextForAssimp(const std::string& text);

/// OBJ: if fixObjTextForAssimp changes the file, has `importer` read the fixed text in its
/// place (other files, such as the .mtl, are read from disk as usual).
void useFixedObjText(Assimp::Importer& importer, const std::string& path);

/// OBJ: warns about a `mtllib` that does not exist (Assimp then silently uses its defaults).
/// True if the file names material libraries and none of them exists.
bool checkObjMaterialLibraries(const std::string& path, std::vector<std::string>& warnings);

}  // namespace vdblight
