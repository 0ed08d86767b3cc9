// The default scene (the bundled Cornell box) with its tracer, built once per test program for
// the tests that only read it.
#pragma once

#include "vdblight/scene/scene.h"
#include "vdblight/trace/trace.h"

namespace vdblight::test {

struct DefaultScene {
    Scene scene = loadScene(defaultScenePath());
    Tracer tracer{scene};
};

/// Built on first use, kept until the program ends.
inline const DefaultScene& defaultScene() {
    static const DefaultScene d;
    return d;
}

}  // namespace vdblight::test
