// A scene built and exported at test time by headless Blender 3.4 with its own exporters
// (FBX, COLLADA, STL ascii/binary, PLY, OBJ), so that the format tests read files a real DCC
// writes. The scene, in Blender's Z-up frame and `unitsPerMetre` Blender units per metre
// (scene unit scale 1 / unitsPerMetre):
//   Box     2 x 1 x 0.5 m, base on z = 0, material "Blue" (0.2, 0.4, 0.6)
//   Panel   0.4 x 0.4 m plane at z = 0.9, material "Glow": emission (1, 0.5, 0.25), strength 3
//   SmallA, SmallB  0.1 m cubes sharing one mesh, at (+-0.6, 0.2, 0.55), material "Red"
//           whose base colour is the 2 x 2 PNG checker.png (mean (0.75, 0.25, 0.5))
//   Bulb    point light 1000 W at (0.5, 0, 1.5), colour (1, 0.9, 0.8)
//   Sun     sun 3 W/m^2, rotated 30 deg about X, colour (1, 0.9, 0.8)
//   Spot    spot 500 W at (0, -0.8, 1.5), rotated 20 deg about X, size 60 deg, blend 0.25
// 38 triangles in all. Read +Y up in metres it spans x [-1, 1], y [0, 0.9], z [-0.5, 0.5].
#pragma once

#include <string>

namespace vdblight::test {

/// True if a `blender` executable is on PATH.
bool haveBlender();

/// Builds the scene and writes scene.fbx, scene.dae, scene_ascii.stl, scene_bin.stl,
/// scene.ply, scene.obj (+ .mtl) and scene.glb (lights in the exporter's "standard" W/sr
/// mode, COMPAT) into `dir`; `fbxScaleUnits` exports the FBX with
/// apply_scale_options = FBX_SCALE_UNITS (coordinates in Blender units, the unit in
/// UnitScaleFactor) instead of Blender's default (coordinates in centimetres). Returns
/// Blender's output if it fails, "" on success.
std::string exportBlenderScene(const std::string& dir, double unitsPerMetre, bool fbxScaleUnits);

}  // namespace vdblight::test
