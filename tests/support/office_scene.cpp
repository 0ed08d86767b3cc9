// The generated office scene (office_scene.h).
#include "support/office_scene.h"

#include <algorithm>
#include <cmath>

#include "vdblight/core/errors.h"
#include "vdblight/sampling/sampling.h"

#include "support/scene_generators.h"

namespace vdblight {

namespace {
/// The box [lo, hi] with every face split into square-ish cells of about `cell` (two
/// triangles each), front faces into the box if `inward`.
void appendTessellatedBox(Scene& s, const Vec3f& lo, const Vec3f& hi, bool inward, float cell, uint32_t material) {
    const Vec3f size = hi - lo;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const int a = (axis + 1) % 3, b = (axis + 2) % 3;
            const int na = std::max(1, int(std::lround(size[a] / cell))), nb = std::max(1, int(std::lround(size[b] / cell)));
            // Outward normal of this face is +axis for side 1, -axis for side 0.
            const bool flip = (side == 1) == inward;
            for (int j = 0; j < nb; ++j)
                for (int i = 0; i < na; ++i) {
                    auto corner = [&](int di, int dj) {
                        Vec3f p;
                        p[axis] = side ? hi[axis] : lo[axis];
                        p[a] = lo[a] + size[a] * float(i + di) / float(na);
                        p[b] = lo[b] + size[b] * float(j + dj) / float(nb);
                        return p;
                    };
                    // (a, b, axis) is right-handed: counter-clockwise in (a, b) faces +axis.
                    const Vec3f p00 = corner(0, 0), p10 = corner(1, 0), p11 = corner(1, 1), p01 = corner(0, 1);
                    if (flip) {
                        addTriangle(s, p00, p11, p10, material);
                        addTriangle(s, p00, p01, p11, material);
                    } else {
                        addTriangle(s, p00, p10, p11, material);
                        addTriangle(s, p00, p11, p01, material);
                    }
                }
        }
}

uint32_t material(Scene& s, const char* name, const Rgb& albedo, const Rgb& emission = {0, 0, 0}) {
    Material m;
    m.name = name;
    m.albedo = albedo;
    m.emission = emission;
    return addMaterial(s, m);
}

void appendDesk(Scene& s, const Vec3f& at, uint32_t wood, uint32_t metal, float cell) {
    appendTessellatedBox(s, at + Vec3f(0, 0.72f, 0), at + Vec3f(1.6f, 0.76f, 0.8f), false, cell, wood);
    for (int k = 0; k < 4; ++k) {
        const Vec3f leg = at + Vec3f((k & 1) ? 1.52f : 0.03f, 0, (k & 2) ? 0.72f : 0.03f);
        appendBox(s, leg, leg + Vec3f(0.05f, 0.72f, 0.05f), false, metal);
    }
}

void appendChair(Scene& s, const Vec3f& at, uint32_t fabric, uint32_t metal) {
    appendBox(s, at + Vec3f(0, 0.42f, 0), at + Vec3f(0.48f, 0.48f, 0.48f), false, fabric);
    appendBox(s, at + Vec3f(0, 0.48f, 0.42f), at + Vec3f(0.48f, 1.0f, 0.48f), false, fabric);
    appendBox(s, at + Vec3f(0.21f, 0, 0.21f), at + Vec3f(0.27f, 0.42f, 0.27f), false, metal);
}

void appendShelf(Scene& s, const Vec3f& at, uint32_t wood, uint64_t seed, float cell) {
    const float w = 1.2f, d = 0.35f, h = 2.0f;
    appendTessellatedBox(s, at, at + Vec3f(0.03f, h, d), false, cell, wood);
    appendTessellatedBox(s, at + Vec3f(w - 0.03f, 0, 0), at + Vec3f(w, h, d), false, cell, wood);
    for (int board = 0; board < 5; ++board) {
        const float y = 0.05f + board * 0.45f;
        appendTessellatedBox(s, at + Vec3f(0.03f, y, 0), at + Vec3f(w - 0.03f, y + 0.03f, d), false, cell, wood);
        if (board == 4) break;
        float x = 0.05f;
        for (int book = 0; x < w - 0.12f; ++book) {
            const uint64_t hsh = hashCombine(seed, uint64_t(board * 100 + book));
            const float thick = 0.03f + 0.04f * toUnitFloat(hsh), tall = 0.22f + 0.15f * toUnitFloat(mix64(hsh));
            const Rgb colour(0.15f + 0.6f * toUnitFloat(mix64(hsh + 1)), 0.15f + 0.6f * toUnitFloat(mix64(hsh + 2)),
                             0.15f + 0.6f * toUnitFloat(mix64(hsh + 3)));
            const uint32_t m = material(s, "book", colour);
            appendBox(s, at + Vec3f(x, y + 0.03f, 0.04f), at + Vec3f(x + thick, y + 0.03f + tall, d - 0.03f), false, m);
            x += thick + 0.005f;
        }
    }
}
}  // namespace

Scene makeOfficeScene(int detail) {
    if (detail < 1 || detail > 8) throw ValueError("office detail must be 1..8, got " + std::to_string(detail));
    const float cell = 0.1f / float(detail);
    Scene s;
    s.name = "office";
    const uint32_t wall = material(s, "wall", {0.72f, 0.72f, 0.68f});
    const uint32_t floor = material(s, "floor", {0.35f, 0.28f, 0.22f});
    const uint32_t wood = material(s, "wood", {0.55f, 0.4f, 0.25f});
    const uint32_t metal = material(s, "metal", {0.3f, 0.3f, 0.32f});
    const uint32_t fabric = material(s, "fabric", {0.2f, 0.25f, 0.45f});
    const uint32_t screen = material(s, "screen", {0.05f, 0.05f, 0.05f});
    const uint32_t divider = material(s, "divider", {0.8f, 0.7f, 0.15f});
    const uint32_t plant = material(s, "plant", {0.15f, 0.45f, 0.12f});
    const uint32_t panel = material(s, "ceiling_light", {0.8f, 0.8f, 0.8f}, {12.0f, 11.5f, 10.5f});
    const uint32_t bulb = material(s, "desk_lamp", {0.8f, 0.8f, 0.8f}, {40.0f, 34.0f, 24.0f});

    // Room: walls and ceiling, floor with its own material (a thin slab of the room box).
    appendTessellatedBox(s, {0, 0, 0}, {6, 3, 5}, true, cell, wall);
    appendTessellatedBox(s, {0, 0, 0}, {6, 0.01f, 5}, false, cell, floor);
    // Ceiling light panel facing down, just below the ceiling.
    addTriangle(s, {2.4f, 2.98f, 2.2f}, {3.6f, 2.98f, 2.2f}, {3.6f, 2.98f, 2.8f}, panel);
    addTriangle(s, {2.4f, 2.98f, 2.2f}, {3.6f, 2.98f, 2.8f}, {2.4f, 2.98f, 2.8f}, panel);

    const Vec3f desks[4] = {{0.6f, 0, 0.5f}, {0.6f, 0, 2.4f}, {3.6f, 0, 0.5f}, {3.6f, 0, 2.4f}};
    for (const Vec3f& d : desks) {
        appendDesk(s, d, wood, metal, cell);
        appendChair(s, d + Vec3f(0.55f, 0, 0.95f), fabric, metal);
        appendBox(s, d + Vec3f(0.5f, 0.76f, 0.1f), d + Vec3f(1.1f, 1.15f, 0.14f), false, screen);
        appendBox(s, d + Vec3f(0.78f, 0.76f, 0.14f), d + Vec3f(0.82f, 0.9f, 0.2f), false, metal);
    }
    // The yellow divider between the two rows of desks.
    appendTessellatedBox(s, {0.4f, 0.01f, 1.9f}, {2.6f, 1.5f, 1.95f}, false, cell, divider);
    // Shelves along the back wall, a plant in the corner, a lamp on one desk.
    appendShelf(s, {0.2f, 0.01f, 4.6f}, wood, 11, cell);
    appendShelf(s, {1.6f, 0.01f, 4.6f}, wood, 12, cell);
    appendBox(s, {5.2f, 0.01f, 4.2f}, {5.6f, 0.45f, 4.6f}, false, metal);
    appendIcosphere(s, {5.4f, 0.85f, 4.4f}, 0.4f, 4, plant);
    appendBox(s, {4.9f, 0.76f, 2.6f}, {4.93f, 1.2f, 2.63f}, false, metal);
    appendIcosphere(s, {4.915f, 1.25f, 2.615f}, 0.05f, 3, bulb);
    return s;
}

}  // namespace vdblight
