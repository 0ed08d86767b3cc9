/* shaders/vdblight_nanovdb.h compiled as C with PNANOVDB_C, for nanovdb_export_test
   and vdblight_bench (library vdblight_nanovdb_lookup_c, the top CMakeLists.txt). */
#define PNANOVDB_C
#include <nanovdb/PNanoVDB.h>

#include "../shaders/vdblight_nanovdb.h"
#include "nanovdb_lookup_c.h"

static pnanovdb_vec3_t vec3Of(const float v[3]) {
    pnanovdb_vec3_t r;
    r.x = v[0];
    r.y = v[1];
    r.z = v[2];
    return r;
}

int vdblightNanoIrradiance(const uint32_t* words, const float x[3], const float n[3], float out[3]) {
    pnanovdb_buf_t buf = pnanovdb_make_buf((uint32_t*)words, 0);
    vdblight_nano_volume_t v = vdblight_nano_open(buf);
    pnanovdb_vec3_t e = vdblight_nano_irradiance(buf, &v, vec3Of(x), vec3Of(n));
    out[0] = e.x;
    out[1] = e.y;
    out[2] = e.z;
    return v.supported ? 1 : 0;
}

float vdblightNanoLightVisibility(const uint32_t* words, const float x[3], int light) {
    pnanovdb_buf_t buf = pnanovdb_make_buf((uint32_t*)words, 0);
    vdblight_nano_volume_t v = vdblight_nano_open(buf);
    return vdblight_nano_light_visibility(buf, &v, vec3Of(x), light);
}
