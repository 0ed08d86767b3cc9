// vdblight: the whole public API in one include, for applications that link
// vdblight::vdblight (find_package(vdblight), examples/bake_and_query.cpp).
//
// What a user needs, in the order of the data flow:
//   scene_load.h   loadScene: every format Assimp reads, plus our PLY reader (scene.h: Scene)
//   trace.h        Tracer: the Embree BVH every pass traces through
//   layout.h       placeUniformGrid: where the nodes go (layout_levels.h: bilevel/adaptive)
//   basis.h        Basis: what a node stores; makeBasis("sh:3") from the registry
//   bake_volume.h  bakeVolume / bakeToFile: the bake `vdblight bake` runs, from a BakeRequest
//                  (pass.h: the passes behind it; bake.h, bake_*.h, photons.h: each pass alone;
//                  bake_basis.h: bakeBasis, the generic gather of any registered basis)
//   vdb_io.h       writeVolume (atomic) / readVolume / inspectVolumeFile
//   query.h        IrradianceQuery: irradiance(x, n) at run time
//   sh_truncate.h  truncateSh: fewer SH bands (what an engine's L2 probe holds of an sh:4 bake)
//   export.h       exportTextures: dense textures + manifest for engines
//   export_nanovdb.h  exportNanoVdb: the volume's own nodes as one .nvdb (shaders/vdblight_nanovdb.h reads it)
//   export_three.h exportThreeGrid: the probe grid of three.js LightProbeGridWebGL
//   errors.h       the typed exceptions every call may throw (catch vdblight::Error once)
// Smaller programs may include only the headers they use.
#pragma once

#include "vdblight/errors.h"
#include "vdblight/math.h"
#include "vdblight/scene.h"
#include "vdblight/scene_load.h"
#include "vdblight/trace.h"
#include "vdblight/layout.h"
#include "vdblight/layout_levels.h"
#include "vdblight/sh.h"
#include "vdblight/volume.h"
#include "vdblight/basis.h"
#include "vdblight/bake.h"
#include "vdblight/bake_volume.h"
#include "vdblight/bake_basis.h"
#include "vdblight/vdb_io.h"
#include "vdblight/query.h"
#include "vdblight/volume_query.h"
#include "vdblight/sh_truncate.h"
#include "vdblight/export.h"
#include "vdblight/export_nanovdb.h"
#include "vdblight/export_three.h"
