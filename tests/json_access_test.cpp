// The glTF loaders read JSON that Assimp has not checked yet (scene/json_access.h over
// nlohmann::json): a member of the wrong type reads as absent, never as an exception or, for a
// scalar where an array belongs, as a one-element list; bad or hostile text is "not JSON".
#include <gtest/gtest.h>

#include <string>

#include "../libvdblight/src/scene/json_access.h"  // internal to the scene module

namespace vdblight::json {
namespace {

TEST(JsonAccess, MembersOfTheWrongTypeReadAsAbsent) {
    const Json doc = parseOrDiscarded(R"({"meshes": 7, "nodes": {"0": 1}, "buffers": [{"byteLength": 12}],
                                          "count": "12", "flag": true, "n": 3, "x": 2.5})");
    ASSERT_FALSE(doc.is_discarded());
    EXPECT_TRUE(elements(member(doc, "meshes")).empty());  // nlohmann alone iterates 7 once
    EXPECT_TRUE(elements(member(doc, "nodes")).empty());
    EXPECT_TRUE(elements(member(doc, "missing")).empty());
    EXPECT_EQ(elements(member(doc, "buffers")).size(), 1u);
    EXPECT_TRUE(members(member(doc, "meshes")).empty());
    EXPECT_EQ(members(member(doc, "nodes")).size(), 1u);
    EXPECT_EQ(member(member(doc, "meshes"), "primitives"), nullptr);  // a member of a number
    EXPECT_EQ(member(nullptr, "x"), nullptr);
    EXPECT_EQ(numberOr(member(elements(member(doc, "buffers"))[0], "byteLength"), -1), 12.0);
    EXPECT_EQ(numberOr(member(doc, "x"), -1), 2.5);
    EXPECT_EQ(numberOr(member(doc, "count"), -1), -1);  // a string is no number
    EXPECT_EQ(numberOr(member(doc, "flag"), -1), -1);   // nor is a boolean
    EXPECT_EQ(stringOr(member(doc, "count")), "12");
    EXPECT_EQ(stringOr(member(doc, "n")), "");
}

TEST(JsonAccess, BadOrHostileTextIsNotJsonWithoutThrowing) {
    EXPECT_TRUE(parseOrDiscarded("").is_discarded());
    EXPECT_TRUE(parseOrDiscarded(R"({"a": [1, 2)").is_discarded());
    EXPECT_TRUE(parseOrDiscarded(R"({"a": 1} trailing)").is_discarded());
    EXPECT_TRUE(parseOrDiscarded(R"({"a": NaN})").is_discarded());
    // Deep nesting: no recursion to overflow the stack, in parsing or in freeing.
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    EXPECT_FALSE(parseOrDiscarded(deep).is_discarded());
    EXPECT_TRUE(parseOrDiscarded(std::string(100000, '[')).is_discarded());
    // Escapes decode (the old reader turned \uXXXX into '?').
    EXPECT_EQ(stringOr(member(parseOrDiscarded(R"({"uri": "a\u00e9\/b"})"), "uri")), "a\xc3\xa9/b");
}

}  // namespace
}  // namespace vdblight::json
