// vdblight: the whole public API in one include, for applications that link
// vdblight::vdblight (find_package(vdblight), examples/bake_and_query.cpp).
//
// The installed headers, one folder per module (docs/architecture.md), in the order of the
// data flow; this file includes every one of them (tests/install_example_test.sh checks it):
//   core/          core/errors.h (the typed exceptions every call may throw: catch vdblight::Error
//                  once), core/math.h, core/interrupter.h (progress, cancel), core/atomic_file.h
//   scene/         scene/scene.h: Scene and loadScene (every format Assimp reads, plus our PLY reader)
//   trace/         trace/trace.h: Tracer, the Embree BVH every pass traces through
//   sampling/      sampling/sampling.h: the random and low-discrepancy points the estimators use
//   light/         light/light.h: RadianceEstimator, a scene's lights; light/direct_light.h: exact direct light
//   reference/     reference/reference.h: ground-truth irradiance
//   layout/        layout/layout.h: where the nodes go (uniform grid, node budget, bilevel/adaptive levels)
//   basis/         basis/basis.h: Basis, what a node stores (makeBasis("sh:3") from the registry);
//                  basis/bins.h, basis/depth_moments.h, basis/irradiance_vectors.h: the bases that need more
//   volume/        volume/volume.h: Volume; volume/vdb_io.h: writeVolume (atomic) / readVolume / streaming;
//                  volume/tiles.h: a bake split into tiles and merged
//   bake/          bake/each_pass.h: bakeVolume / bakeToFile from a BakeRequest, the bake `vdblight bake`
//                  runs, and the passes behind it; each_pass.h: each pass alone;
//                  bake/scene_check.h: faces seen from behind
//   query/         query/query.h: IrradianceQuery, irradiance(x, n) at run time;
//                  query/volume_query.h: Query, the complete answer of `vdblight query`
//   export/        export/export.h: dense textures + manifest for engines; engines.h: presets,
//                  three.js, NanoVDB (shaders/vdblight_nanovdb.h reads it), glTF;
//                  export/slice.h: pictures of a volume
//   prt/           prt/prt.h: precomputed radiance transfer for moving lights
// Smaller programs may include only the headers they use.
#pragma once

#include "vdblight/core/atomic_file.h"
#include "vdblight/core/errors.h"
#include "vdblight/core/interrupter.h"
#include "vdblight/core/math.h"
#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"
#include "vdblight/sampling/sampling.h"
#include "vdblight/light/direct_light.h"
#include "vdblight/light/light.h"
#include "vdblight/reference/reference.h"
#include "vdblight/layout/layout.h"
#include "vdblight/basis/basis.h"
#include "vdblight/basis/bins.h"
#include "vdblight/basis/depth_moments.h"
#include "vdblight/basis/irradiance_vectors.h"
#include "vdblight/volume/volume.h"
#include "vdblight/volume/vdb_io.h"
#include "vdblight/volume/tiles.h"
#include "vdblight/bake/each_pass.h"
#include "vdblight/bake/bake.h"
#include "vdblight/bake/scene_check.h"
#include "vdblight/query/query.h"
#include "vdblight/query/volume_query.h"
#include "vdblight/export/export.h"
#include "vdblight/export/engines.h"
#include "vdblight/export/slice.h"
#include "vdblight/prt/prt.h"
