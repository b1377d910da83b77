// The worker codec (validate/run/result_codec.h): a result decoded is the result
// encoded, every member of every type and every bit of every double (NaN
// payloads and signs, infinities, -0, subnormals), for every verdict.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "support/model_visitors.h"
#include "validate/run/result_codec.h"

namespace warpcheck {
namespace {

std::vector<double> every_kind_of_double() {
    const double inf = std::numeric_limits<double>::infinity();
    return {std::numeric_limits<double>::quiet_NaN(),
            -std::numeric_limits<double>::quiet_NaN(),
            std::bit_cast<double>(uint64_t{0x7ff0000000000123}),  // a signalling NaN with a payload
            std::bit_cast<double>(uint64_t{0xfff8dead0000beef}),
            inf,
            -inf,
            -0.0,
            4.9406564584124654e-324,
            0x1.123456789abcdp-7,
            std::numeric_limits<double>::max()};
}

/// A warp's message need not be valid UTF-8; the codec carries its bytes.
std::vector<std::string> every_kind_of_text() {
    return {"plain", "bad utf-8 \xff\xfe", std::string("nul \0 inside", 12), "\xc3\xa9\n\"\\"};
}

TEST(ResultCodec, DecodedIsEncodedBitForBitForEveryMemberAndVerdict) {
    for (int variant = 0; variant < 4; ++variant) {
        for (std::size_t v = 0; v < EnumNames<Verdict>::names.size(); ++v) {
            testing::FillVisitor fill(variant, every_kind_of_double(), every_kind_of_text());
            CheckResult r;
            fill.fill(r);
            r.verdict = static_cast<Verdict>(v);
            const auto back = decode_result(encode_result(r));
            ASSERT_TRUE(back.has_value()) << "variant " << variant << ", verdict " << v;
            const auto written = testing::flatten(r, false);
            EXPECT_EQ(testing::flatten(*back, false), written) << "variant " << variant << ", verdict " << v;
            EXPECT_GT(written.size(), 100u);
        }
    }
}

TEST(ResultCodec, PartOfAnEncodingIsNoResult) {
    testing::FillVisitor fill(0, every_kind_of_double(), every_kind_of_text());
    CheckResult r;
    fill.fill(r);
    const std::string bytes = encode_result(r);
    for (std::size_t size : {std::size_t{0}, std::size_t{1}, bytes.size() / 2, bytes.size() - 1})
        EXPECT_FALSE(decode_result(bytes.substr(0, size)).has_value()) << size << " of " << bytes.size() << " bytes";
}

}  // namespace
}  // namespace warpcheck
