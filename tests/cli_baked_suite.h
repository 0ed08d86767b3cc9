// A test suite of end-to-end tests that share volumes baked once by `vdblight bake`.
#pragma once

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "cli_util.h"

namespace vdblight::test {

/// One volume of a suite: its file name in the suite's directory and the `bake` options.
struct SuiteBake {
    std::string file, options;
};

/// Base of a fixture `class X : public BakedSuite<X>` that defines
/// `static std::vector<SuiteBake> bakes()`. `file(name)` is a path in DIR, a temporary
/// directory removed when the suite ends; the first time it names one of the bakes, that
/// volume is baked there with `vdblight bake -q -o DIR/FILE OPTIONS` (a failed bake fails the
/// test that asked for it). Lazily, because CTest runs each test in its own process: baking
/// every volume of the suite before each test baked the whole list once per test (CI's ASan
/// suite paid 18 bakes for a suite of 3 tests that use 7 volumes).
template <class Suite>
class BakedSuite : public ::testing::Test {
protected:
    static void SetUpTestSuite() { dir_ = new TempDir(); }
    static void TearDownTestSuite() {
        delete dir_;
        dir_ = nullptr;
        baked_().clear();
    }
    static std::string file(const std::string& name) {
        for (const SuiteBake& b : Suite::bakes())
            if (b.file == name && baked_().insert(name).second) {
                std::string out;
                EXPECT_EQ(runCommand(cliPath() + " bake -q -o " + dir_->file(b.file) + " " + b.options, &out), 0)
                    << b.file << ": " << out;
            }
        return dir_->file(name);
    }

private:
    static inline TempDir* dir_ = nullptr;
    static std::set<std::string>& baked_() {
        static std::set<std::string> names;  // the bakes done in dir_
        return names;
    }
};

}  // namespace vdblight::test
