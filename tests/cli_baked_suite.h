// A test suite of end-to-end tests that share volumes baked once by `vdblight bake`.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli_util.h"

namespace vdblight::test {

/// One volume of a suite: its file name in the suite's directory and the `bake` options.
struct SuiteBake {
    std::string file, options;
};

/// Base of a fixture `class X : public BakedSuite<X>` that defines
/// `static std::vector<SuiteBake> bakes()`. Before the suite's first test each is baked with
/// `vdblight bake -q -o DIR/FILE OPTIONS` (the suite fails at the first bake that fails);
/// `file(name)` is a path in DIR, a temporary directory removed when the suite ends.
template <class Suite>
class BakedSuite : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir();
        for (const SuiteBake& b : Suite::bakes()) {
            std::string out;
            ASSERT_EQ(runCommand(cliPath() + " bake -q -o " + file(b.file) + " " + b.options, &out), 0) << out;
        }
    }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
    }
    static std::string file(const std::string& name) { return dir_->file(name); }

private:
    static inline TempDir* dir_ = nullptr;
};

}  // namespace vdblight::test
