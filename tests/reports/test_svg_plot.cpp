#include <cmath>
#include <cstdlib>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "reports/png.h"
#include "reports/svg_plot.h"
#include "reports/text.h"
#include "tests/reports/sample_run.h"
#include "support/temp_dir.h"
#include "tests/reports/xml_check.h"

namespace warpcheck {
namespace {

using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::Not;
using namespace warpcheck::testing;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Plot lines(std::vector<Series> series, bool log_x = false, bool log_y = false) {
    Plot p;
    p.kind = Plot::Kind::Lines;
    p.x_label = "x";
    p.y_label = "y";
    p.log_x = log_x;
    p.log_y = log_y;
    p.series = std::move(series);
    return p;
}

TEST(Text, EscapesMarkupAndRepairsBadText) {
    EXPECT_EQ(escaped("a<b>&\"c\"'d'"), "a&lt;b&gt;&amp;&quot;c&quot;&#39;d&#39;");
    EXPECT_EQ(escaped("caf\xC3\xA9 \xCF\x80"), "caf\xC3\xA9 \xCF\x80");        // UTF-8 stays
    EXPECT_EQ(escaped("x\xFFy"), "x\xEF\xBF\xBDy");                            // a bad byte
    EXPECT_EQ(escaped("\xC0\xAF"), "\xEF\xBF\xBD\xEF\xBF\xBD");                // overlong '/'
    EXPECT_EQ(escaped("\xED\xA0\x80"), "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");  // a surrogate
    EXPECT_EQ(escaped(std::string("a\0b\x1b", 4)), "a\xEF\xBF\xBD" "b\xEF\xBF\xBD");
    EXPECT_EQ(escaped("tab\tnl\n"), "tab\tnl\n");
}

TEST(Text, FormatsNumbersForPeople) {
    EXPECT_EQ(format_number(498), "498");
    EXPECT_EQ(format_number(1452.3), "1452.3");
    EXPECT_EQ(format_number(5.96e-08), "5.96e-08");
    EXPECT_EQ(format_number(kNaN), "NaN");
    EXPECT_EQ(format_number(-std::numeric_limits<double>::infinity()), "-inf");
    EXPECT_EQ(format_grouped(4294967296.0), "4\u202f294\u202f967\u202f296");
    EXPECT_EQ(format_grouped(-12345), "-12\u202f345");
    EXPECT_EQ(format_grouped(1234), "1234");
    EXPECT_EQ(format_grouped(1452.3), "1452.3");
    EXPECT_EQ(format_probability(0.4321), "0.432");
    EXPECT_EQ(format_probability(3.1e-12), "3.10e-12");
    EXPECT_EQ(format_probability(0.0), "< 1e-300");
    EXPECT_EQ(format_seconds(0.042), "42 ms");
    EXPECT_EQ(format_seconds(14.24), "14.2 s");
    EXPECT_EQ(format_seconds(252), "4 min 12 s");
}

TEST(Png, Base64MatchesTheStandardVectors) {
    EXPECT_EQ(base64(""), "");
    EXPECT_EQ(base64("f"), "Zg==");
    EXPECT_EQ(base64("fo"), "Zm8=");
    EXPECT_EQ(base64("foo"), "Zm9v");
    EXPECT_EQ(base64("foobar"), "Zm9vYmFy");
}

TEST(Png, DecodesWithAnIndependentInflater) {
    // 300 x 250 pixels of a pattern, with a transparent first palette entry.
    const int w = 300, h = 250;
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w * h));
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint8_t>(i * 7 % 256);
    std::vector<Rgba> palette(256);
    for (int i = 0; i < 256; ++i) palette[static_cast<std::size_t>(i)] = {static_cast<std::uint8_t>(i), 0, 0, 255};
    palette[0].a = 0;
    const std::string png = encode_palette_png(w, h, pixels, palette);
    ASSERT_EQ(png.substr(0, 8), "\x89PNG\r\n\x1a\n");
    if (std::system("/usr/bin/python3 -c 'import zlib' > /dev/null 2>&1") != 0) GTEST_SKIP() << "no python3 to cross-check";
    TempDir dir;
    std::ofstream(dir.file("x.png"), std::ios::binary) << png;
    // Python's zlib checks the Adler-32 of the stream; the script checks each chunk's CRC.
    const std::string script =
        "import struct, sys, zlib\n"
        "d = open(sys.argv[1], 'rb').read(); i = 8; idat = b''; trns = None\n"
        "while i < len(d):\n"
        "    n, = struct.unpack('>I', d[i:i+4]); t = d[i+4:i+8]; body = d[i+8:i+8+n]\n"
        "    assert struct.unpack('>I', d[i+8+n:i+12+n])[0] == zlib.crc32(t + body), t\n"
        "    if t == b'IHDR': w, h = struct.unpack('>II', body[:8])\n"
        "    if t == b'IDAT': idat += body\n"
        "    if t == b'tRNS': trns = body\n"
        "    i += 12 + n\n"
        "raw = zlib.decompress(idat)\n"
        "assert len(raw) == h * (w + 1)\n"
        "px = b''.join(raw[r*(w+1)+1:(r+1)*(w+1)] for r in range(h))\n"
        "assert all(px[k] == k * 7 % 256 for k in range(w * h))\n"
        "assert trns == b'\\x00', trns  # only the transparent first entry\n";
    std::ofstream(dir.file("check.py")) << script;
    EXPECT_EQ(std::system(("/usr/bin/python3 " + dir.file("check.py") + " " + dir.file("x.png")).c_str()), 0);
}

TEST(SvgPlot, LinePlotHasAxesLegendAndIsWellFormed) {
    const std::string svg = render_svg(lines({{"analytic", {0, 1, 2, 3}, {0, 1, 4, 9}}, {"tabulated", {0, 1, 2, 3}, {0, 1.1, 4.2, 8.7}}}));
    EXPECT_THAT(xml_problem(svg), IsEmpty());
    EXPECT_THAT(svg, HasSubstr(">analytic</text>"));
    EXPECT_THAT(svg, HasSubstr(">tabulated</text>"));
    EXPECT_THAT(svg, HasSubstr(">x</tspan>"));
    EXPECT_THAT(svg, HasSubstr(">10</text>"));  // the y axis ends on a round tick
}

TEST(SvgPlot, LongAxisLabelsWrapInsideThePlot) {
    const Plot p = sample_exhaustive_pass().plots[0];
    const std::string svg = render_svg(p);
    EXPECT_THAT(xml_problem(svg), IsEmpty());
    EXPECT_THAT(svg, HasSubstr("<tspan x=\"0\" dy=\"0\">inputs per float</tspan>"));
    EXPECT_GE(count_of(svg, "dy=\"14\""), 1u) << "the long x label takes two lines";
}

TEST(SvgPlot, LogAxesLabelDecadesAndDropNonPositiveValues) {
    const std::string svg =
        render_svg(lines({{"errors", {1e-9, 1e-8, 0.0, 1e-6}, {1, 100, 5, -3}}}, /*log_x=*/true, /*log_y=*/true));
    EXPECT_THAT(xml_problem(svg), IsEmpty());
    EXPECT_THAT(svg, HasSubstr("10<tspan dy=\"-0.45em\" font-size=\"8\">\xE2\x88\x92" "9</tspan>"));
    EXPECT_THAT(svg, Not(HasSubstr("nan")));
    EXPECT_THAT(svg, Not(HasSubstr("inf")));
}

TEST(SvgPlot, ToleratesEmptyNaNAndMismatchedData) {
    for (Plot::Kind kind : {Plot::Kind::Lines, Plot::Kind::Bars, Plot::Kind::Points}) {
        Plot p = lines({{"empty", {}, {}}, {"nan", {1, 2}, {kNaN, kNaN}}, {"short x", {1}, {1, 2, 3}}, {"one", {5}, {5}}});
        p.kind = kind;
        const std::string svg = render_svg(p);
        EXPECT_THAT(xml_problem(svg), IsEmpty());
        EXPECT_THAT(svg, Not(HasSubstr("nan\"")));
        Plot none;
        none.kind = kind;
        EXPECT_THAT(render_svg(none), HasSubstr("no data to plot"));
    }
}

TEST(SvgPlot, LongSeriesAreThinnedToThePixelColumns) {
    Series s{"noise", {}, {}};
    for (int i = 0; i < 200000; ++i) s.x.push_back(i), s.y.push_back(std::sin(i * 0.37));
    const std::string svg = render_svg(lines({s}));
    EXPECT_LT(svg.size(), 80'000u);
    EXPECT_THAT(xml_problem(svg), IsEmpty());
}

TEST(SvgPlot, HeatmapsShareScalesAndMarkMissingCells) {
    const Plot maps = sample_chi2_fail(8, 16).plots[0];
    SvgOptions options;
    options.id_prefix = "t0";
    const std::string svg = render_svg(maps, options);
    EXPECT_THAT(xml_problem(svg), IsEmpty());
    EXPECT_EQ(count_of(svg, "<image "), 3u);
    EXPECT_EQ(count_of(svg, "<linearGradient "), 2u);  // observed+expected share one, residuals the other
    EXPECT_THAT(svg, HasSubstr(">observed, expected</text>"));
    EXPECT_THAT(svg, HasSubstr("id=\"t0-nan\""));
    EXPECT_THAT(svg, HasSubstr("no value (e.g. pooled)"));
}

TEST(SvgPlot, MinColorLimitKeepsNoisePale) {
    Plot p;
    p.kind = Plot::Kind::Heatmaps;
    Heatmap noise{"residual", 1, 2, 0, 1, 0, 1, {-0.5, 0.5}};
    noise.min_color_limit = 4.0;
    p.heatmaps = {noise};
    const std::string svg = render_svg(p);
    EXPECT_THAT(svg, HasSubstr(">\xE2\x88\x92" "4</text>"));  // the legend reaches -4 .. 4
    EXPECT_THAT(svg, HasSubstr(">4</text>"));
    p.heatmaps[0].min_color_limit = 0.0;
    EXPECT_THAT(render_svg(p), Not(HasSubstr(">4</text>")));
}

TEST(SvgPlot, MalformedHeatmapIsShownNotFatal) {
    Plot p;
    p.kind = Plot::Kind::Heatmaps;
    p.heatmaps.push_back({"broken", 4, 4, 0, 1, 0, 1, {1.0, 2.0}});
    p.heatmaps.push_back({"empty", 0, 0, 0, 1, 0, 1, {}});
    const std::string svg = render_svg(p);
    EXPECT_THAT(xml_problem(svg), IsEmpty());
    EXPECT_THAT(svg, HasSubstr("malformed heatmap: 4 x 4 cells, 2 values"));
}

TEST(SvgPlot, FullSizeHeatmapsStaySmall) {
    // 64 x 128 cells, three maps: the size of the largest chi-square plots.
    const Plot maps = sample_chi2_fail(64, 128).plots[0];
    const std::string svg = render_svg(maps);
    EXPECT_LT(svg.size(), 120'000u);
}

}  // namespace
}  // namespace warpcheck
