// The command line's own checks (app/cli_util.h): the last guard before a frame is written, and the
// parsers of option values. The shell checks (tests/cli_errors.sh) run the same code through the binary,
// but no valid input reaches refuse_non_finite any more (every range is checked where it enters), so its
// refusal is proven here, directly.
#include "app/cli_util.h"
#include "render/image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace brume::app {
namespace {

TEST(CliUtil, NonFinitePixelsAreRefusedNamingTheFirst) {
    Image image(4, 3);
    EXPECT_NO_THROW(refuse_non_finite(image, "the frame"));
    image.pixel(2, 1)[1] = std::numeric_limits<float>::quiet_NaN();
    image.pixel(3, 2)[0] = std::numeric_limits<float>::infinity();
    try {
        refuse_non_finite(image, "frame 7");
        ADD_FAILURE() << "a NaN pixel was let through";
    } catch (const std::runtime_error& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.rfind("frame 7 has 2 non-finite (NaN or infinite) values, the first at pixel (2, 1)", 0), 0u) << m;
        EXPECT_NE(m.find("nothing was written"), std::string::npos) << m;
    }
    Image all_nan(2, 2);
    for (float& v : all_nan.rgb) v = -std::numeric_limits<float>::infinity();
    EXPECT_THROW(refuse_non_finite(all_nan, "the frame"), std::runtime_error);
}

TEST(CliUtil, JsonStringsAreValidUtf8WhateverTheBytes) {
    EXPECT_EQ(json_string("a\"b\\c\n"), "\"a\\\"b\\\\c\\u000a\"");
    // Well-formed UTF-8 passes as it is: 2, 3 and 4 bytes.
    EXPECT_EQ(json_string("f\xc3\xa9\xe2\x82\xac\xf0\x9f\x94\xa5"), "\"f\xc3\xa9\xe2\x82\xac\xf0\x9f\x94\xa5\"");
    // A Latin-1 byte, a cut sequence, an overlong form, a surrogate and a lone continuation byte are each
    // U+FFFD, one per byte that begins no sequence, and the text after them is kept.
    EXPECT_EQ(json_string("bad\xff.toml"), "\"bad\\ufffd.toml\"");
    EXPECT_EQ(json_string("\xe2\x82"), "\"\\ufffd\\ufffd\"");
    EXPECT_EQ(json_string("\xc0\xaf"), "\"\\ufffd\\ufffd\"");
    EXPECT_EQ(json_string("\xed\xa0\x80x"), "\"\\ufffd\\ufffd\\ufffdx\"");
    EXPECT_EQ(json_string("\x80"), "\"\\ufffd\"");
}

TEST(CliUtil, WholeNumbersNeverWrap) {
    EXPECT_EQ(parse_whole_number("4294967328"), 4294967328LL);
    EXPECT_EQ(parse_whole_number("-3"), -3LL);
    EXPECT_FALSE(parse_whole_number("99999999999999999999"));
    EXPECT_FALSE(parse_whole_number(""));
    EXPECT_FALSE(parse_whole_number("12abc"));
    EXPECT_FALSE(parse_whole_number("1.5"));
}

TEST(CliUtil, RangeListsAreCheckedAndBounded) {
    EXPECT_EQ(parse_int_list("2-8:2"), (std::vector<int>{2, 4, 6, 8}));
    EXPECT_EQ(parse_int_list("2,4,16"), (std::vector<int>{2, 4, 16}));
    EXPECT_EQ(parse_int_list("2147483000-2147483647:1000"), (std::vector<int>{2147483000}));  // no wrap past B
    EXPECT_THROW(parse_int_list("4294967296-4294967300:2"), UsageError);
    EXPECT_THROW(parse_int_list("8-2:2"), UsageError);
    EXPECT_THROW(parse_int_list("2-8:0"), UsageError);
    EXPECT_THROW(parse_int_list("2-1000000:2"), UsageError);  // over 10,000 values
    EXPECT_THROW(parse_int_list("2,x"), UsageError);
    EXPECT_THROW(parse_int_list("4294967296"), UsageError);
}

TEST(CliUtil, OptionChecksSayWhatTheyWant) {
    EXPECT_EQ(refuse_non_positive("1.5"), "");
    EXPECT_EQ(refuse_non_positive("1e-3"), "");
    for (const char* bad : {"0", "-1", "abc", "", "inf", "nan", "1e999"})
        EXPECT_NE(refuse_non_positive(bad).find("not a positive number"), std::string::npos) << bad;
    EXPECT_EQ(refuse_non_frame_number("0"), "");
    EXPECT_EQ(refuse_non_frame_number("143"), "");
    for (const char* bad : {"-1", "1.5", "abc", "", "4294967296"})
        EXPECT_NE(refuse_non_frame_number(bad).find("not a frame number"), std::string::npos) << bad;
    // A message echoes at most 40 characters of what was typed.
    EXPECT_LT(refuse_non_frame_number(std::string(100000, '7')).size(), 100u);
    EXPECT_NE(refuse_empty_path(""), "");
    EXPECT_EQ(refuse_empty_path("out.exr"), "");
}

TEST(CliUtil, OutputFormatFollowsTheName) {
    EXPECT_NO_THROW(check_output_format("-o", "out.exr", ".exr"));
    EXPECT_NO_THROW(check_output_format("-o", "out.EXR", ".exr"));
    EXPECT_NO_THROW(check_output_format("--png", "out", ".png"));
    EXPECT_THROW(check_output_format("-o", "out.png", ".exr"), UsageError);
    EXPECT_THROW(check_output_format("--png", "out.exr", ".png"), UsageError);
}

}  // namespace
}  // namespace brume::app
