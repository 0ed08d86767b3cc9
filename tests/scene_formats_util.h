// What the scene format tests (scene_formats_*_test.cpp, one executable scene_formats_test)
// share: vectors compared component by component, with the label of what is compared.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "vdblight/core/math.h"

namespace vdblight::test {

inline constexpr double kPiD = 3.14159265358979323846;

inline void expectVec(const Vec3d& got, const Vec3d& want, double tol, const std::string& what) {
    EXPECT_NEAR(got.x, want.x, tol) << what;
    EXPECT_NEAR(got.y, want.y, tol) << what;
    EXPECT_NEAR(got.z, want.z, tol) << what;
}

}  // namespace vdblight::test
