#include "blender_scene.h"

#include <cstdlib>

#include "test_util.h"

namespace vdblight::test {

namespace {
const char* kScript = R"PY(
import bpy, sys, math
args = sys.argv[sys.argv.index("--") + 1:]
out, u, scale_units = args[0], float(args[1]), args[2] == "1"
bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene
sc.unit_settings.system = 'METRIC'
sc.unit_settings.scale_length = 1.0 / u
def mat(name, base, emit=None, strength=0.0):
    m = bpy.data.materials.new(name); m.use_nodes = True
    p = m.node_tree.nodes["Principled BSDF"]
    p.inputs["Base Color"].default_value = (*base, 1)
    if emit:
        p.inputs["Emission"].default_value = (*emit, 1)
        p.inputs["Emission Strength"].default_value = strength
    return m
bpy.ops.mesh.primitive_cube_add(size=1, location=(0, 0, 0.25 * u))
box = bpy.context.object; box.name = "Box"; box.scale = (2 * u, 1 * u, 0.5 * u)
box.data.materials.append(mat("Blue", (0.2, 0.4, 0.6)))
bpy.ops.mesh.primitive_plane_add(size=0.4 * u, location=(0, 0, 0.9 * u))
panel = bpy.context.object; panel.name = "Panel"
panel.data.materials.append(mat("Glow", (0.5, 0.5, 0.5), (1.0, 0.5, 0.25), 3.0))
bpy.ops.mesh.primitive_cube_add(size=0.1 * u, location=(0.6 * u, 0.2 * u, 0.55 * u))
small = bpy.context.object; small.name = "SmallA"
red = mat("Red", (0.7, 0.1, 0.1))
img = bpy.data.images.new("checker", 2, 2)  # texels 0 or 1: the same in sRGB and linear
img.pixels = [1, 0, 0, 1,  1, 0, 0, 1,  0, 0, 1, 1,  1, 1, 1, 1]
img.filepath_raw = out + "/checker.png"; img.file_format = 'PNG'; img.save()
tex = red.node_tree.nodes.new("ShaderNodeTexImage"); tex.image = img
red.node_tree.links.new(tex.outputs["Color"], red.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
small.data.materials.append(red)
inst = small.copy(); inst.name = "SmallB"; inst.location = (-0.6 * u, 0.2 * u, 0.55 * u)
sc.collection.objects.link(inst)
def light(kind, name, loc, energy, rot):
    d = bpy.data.lights.new(name, kind); d.energy = energy; d.color = (1.0, 0.9, 0.8)
    o = bpy.data.objects.new(name, d); o.location = [c * u for c in loc]; o.rotation_euler = rot
    sc.collection.objects.link(o); return d
light('POINT', "Bulb", (0.5, 0, 1.5), 1000.0, (0, 0, 0))
light('SUN', "Sun", (0, 0, 3), 3.0, (math.radians(30), 0, 0))
s = light('SPOT', "Spot", (0, -0.8, 1.5), 500.0, (math.radians(20), 0, 0))
s.spot_size = math.radians(60); s.spot_blend = 0.25
bpy.ops.object.select_all(action='SELECT')
bpy.ops.export_scene.fbx(filepath=out + "/scene.fbx",
                         apply_scale_options='FBX_SCALE_UNITS' if scale_units else 'FBX_SCALE_NONE')
bpy.ops.wm.collada_export(filepath=out + "/scene.dae")
bpy.ops.export_mesh.stl(filepath=out + "/scene_ascii.stl", ascii=True)
bpy.ops.export_mesh.stl(filepath=out + "/scene_bin.stl", ascii=False)
bpy.ops.export_mesh.ply(filepath=out + "/scene.ply")
bpy.ops.wm.obj_export(filepath=out + "/scene.obj")
bpy.ops.export_scene.gltf(filepath=out + "/scene.glb", export_lights=True, convert_lighting_mode='COMPAT')
)PY";
}  // namespace

bool haveBlender() { return runCommand("command -v blender") == 0; }

std::string exportBlenderScene(const std::string& dir, double unitsPerMetre, bool fbxScaleUnits) {
    const std::string script = dir + "/export_scene.py";
    writeTextFile(script, kScript);
    std::string output;
    const int status = runCommand("blender -b --factory-startup --python-exit-code 1 --python '" + script + "' -- '" +
                                      dir + "' " + std::to_string(unitsPerMetre) + (fbxScaleUnits ? " 1" : " 0"),
                                  &output);
    return status == 0 ? std::string() : "blender exited with " + std::to_string(status) + ":\n" + output;
}

}  // namespace vdblight::test
