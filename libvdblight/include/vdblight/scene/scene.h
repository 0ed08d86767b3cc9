// The scene module's API: the Scene (below) and loadScene, every format it reads (second part).
//
// The scene: triangles with per-triangle materials, punctual lights and a sky.
//
// Conventions (see docs/scene.md):
//  - Positions are in the scene file's units; lighting quantities do not depend on them
//    except punctual lights (intensity / distance^2 uses scene units as metres).
//  - Radiance is linear RGB in W/(m^2 sr). Albedo is linear RGB in [0, 1).
//  - A triangle's front face is counter-clockwise: Ng = (p1 - p0) x (p2 - p0).
//    Emissive triangles emit from the front face only unless Material::twoSidedEmission.
//  - Every surface reflects diffusely on both sides (Lambertian, albedo / pi).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vdblight/core/math.h"

namespace vdblight {

struct Material {
    std::string name;
    Rgb albedo{0.8f, 0.8f, 0.8f};   ///< diffuse reflectance, clamped to [0, 0.999]
    Rgb emission{0, 0, 0};          ///< emitted radiance, W/(m^2 sr)
    bool twoSidedEmission = false;  ///< emit from the back face as well

    bool isEmissive() const { return maxComponent(emission) > 0.0f; }
};

/// Isotropic point light (also the base of spot lights). Intensity in W/sr.
struct PointLight {
    Vec3f position;
    Rgb intensity;
};

/// Spot light: a point light whose intensity falls off smoothly between the inner
/// and outer cone half-angles (glTF KHR_lights_punctual convention).
struct SpotLight {
    Vec3f position;
    Vec3f direction{0, 0, -1};  ///< unit vector the spot points along
    Rgb intensity;              ///< W/sr on the axis
    float innerConeAngle = 0.0f;
    float outerConeAngle = float(kPi / 4);
};

/// Distant light: parallel rays travelling along `direction`, irradiance in W/m^2
/// on a surface facing the light.
struct DirectionalLight {
    Vec3f direction{0, -1, 0};
    Rgb irradiance;
};

/// Equirectangular (latitude-longitude) environment map, +Y up, nearest texel.
/// Row 0 is the zenith (+Y), the last row the nadir: v = acos(y) / pi.
/// u = 0.5 + atan2(z, x) / (2 pi), wrapped to [0, 1): the centre column (u = 0.5) looks along +X,
/// and u = 0 / 0.25 / 0.5 / 0.75 look along -X / -Z / +X / +Z. This is Blender/Cycles' (and
/// three.js') convention for a Y-up glTF scene imported into Blender (Blender Z = our Y,
/// Blender Y = our -Z), so an HDRI lights us as it does Blender's world. See docs/scene.md.
struct SkyMap {
    int width = 0, height = 0;
    std::vector<Rgb> texels;  ///< row-major, width * height, radiance W/(m^2 sr)
    std::string path;

    /// Radiance arriving from direction `dirToSky` (unit), nearest texel.
    Rgb lookup(const Vec3f& dirToSky) const;
};

/// Radiance arriving from directions where rays escape the scene.
struct Sky {
    Rgb constant{0, 0, 0};
    std::shared_ptr<const SkyMap> map;  ///< if set, overrides constant

    bool isBlack() const { return !map && maxComponent(constant) <= 0.0f; }
    Rgb radiance(const Vec3f& dirToSky) const { return map ? map->lookup(dirToSky) : constant; }
};

/// What loading found and fixed.
struct SceneStats {
    std::size_t inputTriangles = 0;
    std::size_t degenerateTrianglesSkipped = 0;
    std::size_t meshes = 0;
};

struct Scene {
    std::string name;                  ///< file stem, or "cornell_box" for the default
    /// World position (double) of the scene's local frame. Vertices, light positions, bounds(),
    /// tracing, light transport and every bake's node positions are local, i.e. relative to
    /// `origin`, in float; a volume is placed in the world by adding `origin` to its grids'
    /// origins (placeVolumeInWorld, scene_origin.h). (0, 0, 0) unless the scene lies far from
    /// the world origin (docs/scene.md, "Large coordinates").
    Vec3d origin{0, 0, 0};
    std::vector<Vec3f> positions;      ///< vertices in the local frame (world = origin + position)
    std::vector<uint32_t> indices;     ///< 3 per triangle
    std::vector<uint32_t> materialIds; ///< 1 per triangle, into materials
    std::vector<Material> materials;
    std::vector<PointLight> pointLights;
    std::vector<SpotLight> spotLights;
    std::vector<DirectionalLight> directionalLights;
    Sky sky;
    SceneStats stats;

    std::size_t triangleCount() const { return materialIds.size(); }
    Vec3f vertex(std::size_t tri, int k) const { return positions[indices[3 * tri + k]]; }
    const Material& material(std::size_t tri) const { return materials[materialIds[tri]]; }
    /// Bounds of the triangles in the local frame.
    Bounds bounds() const;
    /// Bounds of the triangles in world space: bounds() + origin.
    Bounds worldBounds() const;
    Vec3d toWorld(const Vec3f& local) const { return origin + Vec3d(local); }
    /// Local float position of a world point (the subtraction is done in double).
    Vec3f toLocal(const Vec3d& world) const { return Vec3f(world - origin); }
    bool hasEmissiveTriangles() const;
    /// True if anything emits: emissive triangles, punctual lights or a non-black sky.
    bool hasLight() const;
    /// 64-bit FNV-1a hash of geometry, materials, lights and sky, as 16 hex digits.
    std::string contentHash() const;
};

/// Adds a triangle with material `materialId`, skipping (and counting) degenerate ones.
/// Throws SceneError on non-finite coordinates.
void addTriangle(Scene& scene, const Vec3f& a, const Vec3f& b, const Vec3f& c, uint32_t materialId);

/// Same over vertices already in scene.positions (so that meshes keep shared vertices).
/// Throws SceneError on an index out of range or a non-finite vertex.
void addIndexedTriangle(Scene& scene, uint32_t i0, uint32_t i1, uint32_t i2, uint32_t materialId);

/// Appends `m` with its albedo clamped to [0, 0.999] and negative emission set to 0;
/// returns its id. Throws SceneError on non-finite colours.
uint32_t addMaterial(Scene& scene, Material m);

/// Checks invariants every consumer relies on: at least one triangle, finite coordinates,
/// valid indices and material ids. Throws SceneError naming the problem.
void validateScene(const Scene& scene);

/// Loads a scene in any format loadScene(path, SceneLoadOptions) reads (scene/scene.h), with
/// the file's own unit and up axis.
/// Applies node transforms, triangulates, skips degenerate triangles (counted in stats).
/// A scene far from the world origin is recentred (recenterScene, scene_origin.h); Assimp
/// parses coordinates to float, so precision lost at parse time is not recovered.
/// Throws SceneError / IoError with a one-line message.
Scene loadScene(const std::string& path);

/// Path of the bundled default scene (the Cornell box), searched next to the executable
/// and in the source tree. Throws IoError if it cannot be found.
std::string defaultScenePath();

/// Reads an equirectangular EXR sky map with OpenEXR. Throws IoError.
std::shared_ptr<const SkyMap> loadSkyMap(const std::string& path);

}  // namespace vdblight

// ---------------------------------------------------------------------------------------------
// Loading a scene file with options (unit, up axis) and a report of how it was read
// (format, meshes and instances, unit, up axis, warnings). docs/scene.md, "Formats".

namespace vdblight {

/// The up axis of a file's coordinates. vdblight's scenes are +Y up (docs/scene.md).
enum class UpAxis { FromFile, Y, Z };

/// How loadScene reads a file's coordinates.
struct SceneLoadOptions {
    /// > 0: metres per file unit, overriding the file's own unit (FBX UnitScaleFactor,
    /// COLLADA <unit meter>). 0: the file's unit, or 1 where the format has none.
    double scale = 0.0;
    /// Y or Z: the file's up axis, overriding its metadata (FBX GlobalSettings, COLLADA
    /// <up_axis>). FromFile: the metadata, or Y where the format has none.
    UpAxis up = UpAxis::FromFile;
};

/// How a file was read.
struct SceneLoadReport {
    std::string format;              ///< e.g. "FBX (binary)", "COLLADA", "STL (ascii)"
    std::size_t meshes = 0;          ///< distinct meshes with triangles
    std::size_t meshInstances = 0;   ///< placements of those meshes by the node hierarchy
    double metresPerUnit = 1.0;      ///< scale applied to the file's coordinates
    std::string units;               ///< e.g. "1 unit = 0.01 m (FBX UnitScaleFactor 1 cm)"
    std::string up;                  ///< the file's up axis and its source, e.g. "Z (COLLADA <up_axis>)"
    bool defaultAlbedoOnly = false;  ///< no material of the file was used: every surface has albedo 0.8
    std::vector<std::string> warnings;  ///< one line each: what was read in spite of a problem
};

/// Loads a scene: every format Assimp 5.2 reads (glTF 2.0, OBJ+MTL, FBX, COLLADA, 3DS, STL,
/// OFF, .x, ...: supportedSceneExtensions()) through Assimp, PLY (ascii, binary little/big-endian)
/// through vdblight's own reader (docs/scene.md, "PLY"). Converts to metres and +Y up as the
/// file says or `options` override; applies node transforms (instancing included),
/// triangulates, joins identical vertices, drops degenerate faces (counted in
/// Scene::stats). A diffuse texture's mean colour is the albedo where the texture is a PNG.
/// A scene far from the world origin is recentred (recenterScene). Problems that do not stop
/// the load (an unknown PLY header line, a missing OBJ material library, unread textures)
/// are in `report->warnings`. Throws SceneError / IoError / ValueError
/// (a bad option) with a one-line message.
Scene loadScene(const std::string& path, const SceneLoadOptions& options, SceneLoadReport* report = nullptr);

/// How the scene file was read, for summaries: "FBX (binary): 3 meshes in 4 instances,
/// 1 unit = 0.01 m (FBX UnitScaleFactor 1 cm), up axis Z (FBX UpAxis)".
std::string describeSceneSource(const SceneLoadReport& report);

/// The file extensions loadScene reads, lower case with the dot, sorted (".3ds", ".dae", ...).
std::vector<std::string> supportedSceneExtensions();

}  // namespace vdblight
