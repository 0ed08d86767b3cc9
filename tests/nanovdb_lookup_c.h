// The lookup of shaders/vdblight_nanovdb.h compiled as C (tests/nanovdb_lookup_c.c), callable
// from the C++ tests: the same source a shader compiles as GLSL or HLSL.
#pragma once

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/// Irradiance at x for normal n from the grids of a .nvdb laid back to back in `words`
/// (vdblight_meta first); returns 0 if the lookup does not read the volume (out = 0).
int vdblightNanoIrradiance(const uint32_t* words, const float x[3], const float n[3], float out[3]);
/// The interpolated visibility of listed light `light` at x.
float vdblightNanoLightVisibility(const uint32_t* words, const float x[3], int light);

#ifdef __cplusplus
}
#endif
