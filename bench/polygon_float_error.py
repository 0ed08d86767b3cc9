#!/usr/bin/python3
"""Where a polygon light's float irradiance loses its digits (issue 33, the NanoVDB lookup).

query's float path (libvdblight/src/query/fast_exact_lights.cpp) and the shader
(shaders/vdblight_nanovdb_lights.h) evaluate Lambert's contour sum of a polygon clipped to the
receiver's hemisphere in float. Where the clipped polygon is a sliver near the horizon, the sum
is small against its terms, and the two disagree by ~1e-4 of a point's irradiance. This study
splits the float path's absolute error (in the sum's units: twice the projected solid angle)
into its steps, on random quads near the horizon of random receivers, against the same sum in
double on the double inputs:

  inputs:    the quad's vertices and the normal rounded to float, everything else exact;
  clipping:  the clip points computed in float (Sutherland-Hodgman), the sum exact;
  edges:     the edge terms and their sum in float as well (the whole float path);
  polar:     the same clipped polygon in float through a cancellation-free form, the
             azimuthal integral of sin^2(elevation) / 2 along each edge (the horizon edge
             adds nothing), with the winding from the float contour sum.

Deterministic (a fixed seed). Run: /usr/bin/python3 bench/polygon_float_error.py [QUADS]
Needs numpy (Debian: python3-numpy, which scripts/setup.sh installs).
"""
import math
import sys

import numpy as np

F32 = np.float32


def edges(vs, dt):
    """The loop's edges (a, b) with a x b and its length, in dt; those of length 0 (pointing at
    the receiver) left out, as both implementations leave them."""
    for i in range(len(vs)):
        a, b = vs[i], vs[(i + 1) % len(vs)]
        c = np.cross(a, b).astype(dt)
        length = dt(np.sqrt(np.dot(c, c)))
        if length != 0:
            yield a, b, c, length


def contour(vs, n, dt):
    """Lambert's sum over the loop's edges: theta_i dot(n, gamma_i), in dt."""
    s = dt(0)
    for a, b, c, length in edges(vs, dt):
        theta = dt(np.arctan2(length, dt(np.dot(a, b))))
        s = dt(s + dt(theta * dt(np.dot(n, c)) / length))
    return s


def clip(vs, n, dt):
    """The loop clipped to dot(n, v) >= 0, in dt (contour()'s clipping in the C++)."""
    d = [dt(np.dot(n, v)) for v in vs]
    out = []
    for i in range(len(vs)):
        j = (i + 1) % len(vs)
        if d[i] >= 0:
            out.append(vs[i])
        if (d[i] >= 0) != (d[j] >= 0):
            t = dt(d[i] / (d[i] - d[j]))
            out.append((vs[i] + (vs[j] - vs[i]) * t).astype(dt))
    return out


def polar(vs, n, dt):
    """The projected solid angle as -1/2 sum over edges of [G(b) - G(a)], G the antiderivative
    of sin^2(e) along the edge's great circle (pole g, |dot(n, g)| = c):
    G = atan2((1 - c) x y, x^2 + c y^2) + (1 - c) atan2(c y, x), with x = c dot(n, v),
    y = -sign(dot(n, g)) dot(n x g, v) and 1 - c = |n x g|^2 / (1 + c). Returned in contour()'s
    units, without the winding term (2 pi per turn around the normal)."""
    total = dt(0)
    for a, b, cr, length in edges(vs, dt):
        g = (cr / length).astype(dt)
        g3 = dt(np.dot(n, g))
        c = abs(g3)
        w = np.cross(n, g).astype(dt)
        one_minus_c = dt(np.dot(w, w) / (dt(1) + c))
        sign = dt(1) if g3 >= 0 else dt(-1)

        def antiderivative(v):
            x = dt(c * dt(np.dot(n, v)))
            y = dt(-sign * dt(np.dot(w, v)))
            return dt(np.arctan2(dt(one_minus_c * x * y), dt(x * x + c * y * y))) + dt(one_minus_c * dt(np.arctan2(dt(c * y), x)))

        total = dt(total + dt(antiderivative(b) - antiderivative(a)))
    return -total


def main():
    quads = int(sys.argv[1]) if len(sys.argv) > 1 else 30000
    rng = np.random.default_rng(3)
    worst = {"inputs": 0.0, "clipping": 0.0, "edges": 0.0, "polar": 0.0}
    studied = 0
    for _ in range(quads):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        t1 = np.cross(n, [0.3, 0.5, 0.8])
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(n, t1)
        dist, az, el = rng.uniform(0.3, 3), rng.uniform(0, 2 * math.pi), rng.uniform(-0.3, 0.6)
        centre = dist * (math.cos(el) * (math.cos(az) * t1 + math.sin(az) * t2) + math.sin(el) * n)
        e1, e2, size = rng.normal(size=3), rng.normal(size=3), rng.uniform(0.05, 0.5)
        quad = [centre + size * (u * e1 + v * e2) for u, v in [(-1, -1), (1, -1), (1, 1), (-1, 1)]]
        q32, n32 = [q.astype(F32) for q in quad], n.astype(F32)
        if not any(np.dot(n32, q) < 0 for q in q32):
            continue  # the study is of clipped polygons
        exact_loop = clip(quad, n, np.float64)
        float_loop = clip(q32, n32, F32)
        if len(exact_loop) < 3 or len(float_loop) < 3:
            continue
        studied += 1
        exact = contour(exact_loop, n, np.float64)
        nd = n32.astype(np.float64)
        rounded = clip([q.astype(np.float64) for q in q32], nd, np.float64)
        inputs = contour(rounded, nd, np.float64) if len(rounded) >= 3 else 0.0
        clipped = contour([v.astype(np.float64) for v in float_loop], nd, np.float64)
        whole = float(contour(float_loop, n32, F32))
        p = float(polar(float_loop, n32, F32))
        p += 2 * math.pi * round((whole - p) / (2 * math.pi))  # the winding, from the contour sum
        worst["inputs"] = max(worst["inputs"], abs(inputs - exact))
        worst["clipping"] = max(worst["clipping"], abs(clipped - inputs))
        worst["edges"] = max(worst["edges"], abs(whole - clipped))
        worst["polar"] = max(worst["polar"], abs(p - exact))
        worst.setdefault("float path", 0.0)
        worst["float path"] = max(worst["float path"], abs(whole - exact))
    print(f"{studied} clipped quads; worst absolute error of the contour sum (its units):")
    for step in ["inputs", "clipping", "edges", "float path", "polar"]:
        print(f"  {step:10s} {worst[step]:.3g}")


if __name__ == "__main__":
    main()
