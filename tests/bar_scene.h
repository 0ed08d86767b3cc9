// A scene whose light casts a shadow narrower than a cell (shadow edges' second edge, the
// "strips" of docs/shadow_visibility.md), for the tests that bake it through the command line.
#pragma once

#include <fstream>
#include <string>

#include "test_util.h"

namespace vdblight::test {

/// A small square lamp 1.6 m up, facing down, over a bar 4 cm wide 0.9 m up: below it, on a
/// 0.125 m lattice (bake --bounds -0.5,0,-0.5,0.5,0.4,0.5 --resolution 9), the bar's shadow is
/// a strip about half a cell wide, whose two edges the nodes on either side hold as a second
/// edge. Written into `dir` (bar.obj, bar.mtl); returns the OBJ's path.
inline std::string barScene(const TempDir& dir) {
    std::ofstream(dir.file("bar.mtl")) << "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 2000 2000 2000\n";
    std::ofstream(dir.file("bar.obj")) << "mtllib bar.mtl\n"
                                          "v -0.01 1.6 -0.01\nv 0.01 1.6 -0.01\nv 0.01 1.6 0.01\nv -0.01 1.6 0.01\n"
                                          "v -0.6 0.9 0.0\nv 0.6 0.9 0.0\nv 0.6 0.9 0.04\nv -0.6 0.9 0.04\n"
                                          "usemtl lamp\nf 1 2 3\nf 1 3 4\nusemtl grey\nf 5 6 7\nf 5 7 8\n";
    return dir.file("bar.obj");
}

}  // namespace vdblight::test
