// JSON reader: values, positions (with the file's index), and the strictness rules (each
// defect a located error).
#include <gtest/gtest.h>

#include <string>

#include "scene/json_scene_reader.h"

namespace spt {
namespace {

std::string error_of(const std::string& text) {
    try {
        read_json_value(text, "t.json");
    } catch (const LocatedError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(Json, ParsesValuesWithPositions) {
    const ParamValue v = read_json_value("{\n  \"a\": [1, -2.5e3, true, null],\n  \"b\": \"x\\u00e9\\n\"\n}", "t.json", 3);
    ASSERT_TRUE(v.is_object());
    const ParamValue* a = v.find("a");
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->pos().line, 2);
    EXPECT_EQ(a->pos().column, 8);
    ASSERT_EQ(a->items().size(), 4u);
    EXPECT_EQ(a->items()[1].as_number(), -2500.0);
    EXPECT_EQ(a->items()[1].pos().column, 12);
    EXPECT_TRUE(a->items()[2].as_bool());
    EXPECT_EQ(a->items()[3].kind(), ParamValue::Kind::Null);
    EXPECT_EQ(a->items()[1].pos().file, 3u);  // every value and key names the file it came from
    EXPECT_EQ(v.key_pos(1).file, 3u);
    EXPECT_EQ(v.key_pos(1).line, 3);
    EXPECT_EQ(v.key_pos(1).column, 3);
    EXPECT_EQ(v.find("b")->as_string(), "x\xc3\xa9\n");
    EXPECT_EQ(v.members()[0].first, "a");  // file order kept
}

TEST(Json, SurrogatePairsBecomeUtf8) {
    EXPECT_EQ(read_json_value("\"\\ud83d\\ude00\"", "t").as_string(), "\xf0\x9f\x98\x80");
}

TEST(Json, RejectsMalformedInputWithPosition) {
    EXPECT_EQ(error_of(""), "t.json:1:1: the file is empty; expected a JSON value");
    EXPECT_NE(error_of("{\"a\": NaN}").find("t.json:1:7: NaN and Infinity"), std::string::npos);
    EXPECT_NE(error_of("[1, -Infinity]").find("t.json:1:5:"), std::string::npos);
    EXPECT_NE(error_of("{\"a\": 1, \"a\": 2}").find("t.json:1:10: duplicate key"), std::string::npos);
    EXPECT_NE(error_of("[1, 2,]").find("trailing comma"), std::string::npos);
    EXPECT_NE(error_of("{} x").find("t.json:1:4: unexpected 'x' after the end"), std::string::npos);
    EXPECT_NE(error_of("[1e999]").find("too large"), std::string::npos);
    EXPECT_NE(error_of("[01]").find("leading zero"), std::string::npos);
    EXPECT_NE(error_of("[1.]").find("after '.'"), std::string::npos);
    EXPECT_NE(error_of("\"abc").find("t.json:1:1: string never closed"), std::string::npos);
    EXPECT_NE(error_of("\"a\tb\"").find("control character"), std::string::npos);
    EXPECT_NE(error_of("\"\\x\"").find("unknown escape"), std::string::npos);
    EXPECT_NE(error_of("\"\\ud800\"").find("surrogate"), std::string::npos);
    EXPECT_NE(error_of("{\"a\" 1}").find("expected ':'"), std::string::npos);
    EXPECT_NE(error_of("{1: 2}").find("expected a key"), std::string::npos);
    EXPECT_NE(error_of("[1\n  2]").find("t.json:2:3:"), std::string::npos);
    EXPECT_NE(error_of("// comment\n{}").find("t.json:1:1:"), std::string::npos);
    EXPECT_NE(error_of(std::string("[\x01]")).find("byte 0x01"), std::string::npos);
}

TEST(Json, UnderflowIsZero) { EXPECT_EQ(read_json_value("[1e-400]", "t").items()[0].as_number(), 0.0); }

TEST(Json, NestingIsLimited) {
    const std::string ok = std::string(63, '[') + std::string(63, ']');
    EXPECT_NO_THROW(read_json_value(ok, "t"));
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    EXPECT_NE(error_of(deep).find("nesting deeper than 64"), std::string::npos);
}

}  // namespace
}  // namespace spt
