// expectThrowWith: a typed exception whose one-line message names what went wrong.
#pragma once

#include <gtest/gtest.h>

#include <string>

namespace vdblight::test {

/// Expects `fn` to throw E whose message contains `part` and is one line.
template <typename E, typename Fn>
void expectThrowWith(Fn fn, const std::string& part) {
    try {
        fn();
        ADD_FAILURE() << "no exception, expected one containing '" << part << "'";
    } catch (const E& e) {
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "message is not one line";
    }
}

}  // namespace vdblight::test
