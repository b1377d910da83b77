// Reading numbers as people type them, stating limits in words, and "did you
// mean" suggestions (validate/cli/cli_input.h), and the shortest decimal of a
// float parameter in a case name.
#include <cstdlib>

#include <gtest/gtest.h>

#include "validate/checks/check.h"
#include "validate/cli/cli_input.h"
#include "validate/api/warp_case.h"

namespace warpcheck {
namespace {

uint64_t count(const char* text) {
    const ParsedCount c = parse_count(text);
    EXPECT_EQ(c.problem, "") << text;
    return c.value;
}

std::string count_problem(const char* text) { return parse_count(text).problem; }

TEST(CliInput, CountsAsPeopleWriteThem) {
    EXPECT_EQ(count("1000000"), 1'000'000u);
    EXPECT_EQ(count("1_000_000"), 1'000'000u);
    EXPECT_EQ(count("1'000'000"), 1'000'000u);
    EXPECT_EQ(count("1e6"), 1'000'000u);
    EXPECT_EQ(count("1E6"), 1'000'000u);
    EXPECT_EQ(count("2.5e6"), 2'500'000u);
    EXPECT_EQ(count("10M"), 10'000'000u);
    EXPECT_EQ(count("1.5k"), 1500u);
    EXPECT_EQ(count("4G"), 4'000'000'000u);
    EXPECT_EQ(count("1e+3"), 1000u);
    EXPECT_EQ(count("1000e-3"), 1u);
    EXPECT_EQ(count("0"), 0u);
    EXPECT_EQ(count("0.0"), 0u);
    EXPECT_EQ(count("007"), 7u);
    EXPECT_EQ(count("18446744073709551615"), UINT64_MAX);
    EXPECT_EQ(count("1.8e19"), 18'000'000'000'000'000'000u);
}

TEST(CliInput, WhatIsNotACount) {
    for (const char* text : {"", "lots", "1e6x", "10m", "1__000", "_1", "1_", "-5", "+5", "1e", "e6", "1.5.2",
                             "1 000", "0x10", "1e-", "nan", "inf", "1kk"})
        EXPECT_EQ(count_problem(text), std::string("'") + text + "' is not a count (write it as 1000000, 1_000_000, "
                                                                 "1e6 or 1M)")
            << text;
    EXPECT_EQ(count_problem("1.5"), "'1.5' is not a whole number");
    EXPECT_EQ(count_problem("1e-3"), "'1e-3' is not a whole number");
    EXPECT_EQ(count_problem("18446744073709551616"), "'18446744073709551616' is too large (at most "
                                                     "18,446,744,073,709,551,615)");
    EXPECT_EQ(count_problem("1e20"), "'1e20' is too large (at most 18,446,744,073,709,551,615)");
    EXPECT_EQ(count_problem("1e9999"), "'1e9999' is too large (at most 18,446,744,073,709,551,615)");
}

TEST(CliInput, RangesInWords) {
    EXPECT_EQ(parse_count_in("100", kMinSamples, kMaxSamples).problem,
              "100 is out of range: give 1,000 to 10,000,000,000");
    EXPECT_EQ(parse_count_in("2e10", kMinSamples, kMaxSamples).problem,
              "20,000,000,000 is out of range: give 1,000 to 10,000,000,000");
    EXPECT_EQ(parse_count_in("1e6", kMinSamples, kMaxSamples).value, 1'000'000u);
    EXPECT_EQ(parse_real_in("0.7", kMinAlpha, kMaxAlpha).problem, "0.7 is out of range: give 1e-12 to 0.5");
    EXPECT_EQ(parse_real_in("nan", kMinAlpha, kMaxAlpha).problem, "'nan' is not a finite number");
    EXPECT_EQ(parse_real_in("0.05x", kMinAlpha, kMaxAlpha).problem, "'0.05x' is not a finite number");
    EXPECT_EQ(parse_real_in("", kMinAlpha, kMaxAlpha).problem, "'' is not a finite number");
    EXPECT_DOUBLE_EQ(parse_real_in("5e-3", kMinAlpha, kMaxAlpha).value, 0.005);
    EXPECT_EQ(format_limit(86400.0), "86400");
    EXPECT_EQ(format_limit(0.1), "0.1");
    EXPECT_EQ(format_count(1000), "1,000");
    EXPECT_EQ(format_count(999), "999");
}

TEST(CliInput, EditDistances) {
    EXPECT_EQ(edit_distance("samples", "samples"), 0u);
    EXPECT_EQ(edit_distance("sampels", "samples"), 1u) << "a transposition is one edit";
    EXPECT_EQ(edit_distance("chi3", "chi2"), 1u);
    EXPECT_EQ(edit_distance("", "abc"), 3u);
    EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
    EXPECT_EQ(substring_edit_distance("hemisphre", "uniform_hemisphere"), 1u);
    EXPECT_EQ(substring_edit_distance("cone", "uniform_cone[cos_theta_max=0.3]"), 0u);
    EXPECT_EQ(substring_edit_distance("xyz", "ab"), 3u);
}

TEST(CliInput, Suggestions) {
    const std::vector<std::string> options = {"--all", "--alpha", "--samples", "--seed", "--filter"};
    EXPECT_EQ(closest_names("--sampels", options), std::vector<std::string>{"--samples"});
    EXPECT_EQ(closest_names("--al", options), std::vector<std::string>{"--all"});
    EXPECT_TRUE(closest_names("--bogus", options).empty()) << "nothing near enough: no suggestion";
    const std::vector<std::string> families = {"uniform_hemisphere", "cosine_hemisphere", "uniform_cone"};
    EXPECT_EQ(closest_names("hemisphre", families, true),
              (std::vector<std::string>{"cosine_hemisphere", "uniform_hemisphere"}));
    EXPECT_EQ(closest_names("powr", {"power_no_inverse", "power"}, true),
              (std::vector<std::string>{"power", "power_no_inverse"}))
        << "equally close as substrings: the nearer whole name first";
    EXPECT_EQ(closest_names("unifrom_cone", families, true), std::vector<std::string>{"uniform_cone"});
    EXPECT_EQ(did_you_mean({}), "");
    EXPECT_EQ(did_you_mean({"a"}), " (did you mean 'a'?)");
    EXPECT_EQ(did_you_mean({"a", "b", "c"}), " (did you mean 'a', 'b' or 'c'?)");
}

TEST(CliInput, SettingsFromTheEnvironment) {
    RunOptions run;
    ::setenv("WARPCHECK_SEED", "7", 1);
    ::setenv("WARPCHECK_SAMPLES", "2.5M", 1);
    ::setenv("WARPCHECK_ALPHA", "0.05", 1);
    EXPECT_EQ(apply_environment_settings(run), "");
    EXPECT_EQ(run.seed, 7u);
    EXPECT_EQ(run.samples, 2'500'000u);
    EXPECT_DOUBLE_EQ(run.alpha, 0.05);
    ::setenv("WARPCHECK_SAMPLES", "lots", 1);
    EXPECT_EQ(apply_environment_settings(run),
              "WARPCHECK_SAMPLES='lots' is not a count (write it as 1000000, 1_000_000, 1e6 or 1M)");
    ::setenv("WARPCHECK_SAMPLES", "10", 1);
    EXPECT_EQ(apply_environment_settings(run), "WARPCHECK_SAMPLES='10': 10 is out of range: give 1,000 to 10,000,000,000");
    ::setenv("WARPCHECK_SAMPLES", "", 1);  // empty: unset
    ::setenv("WARPCHECK_ALPHA", "2", 1);
    EXPECT_EQ(apply_environment_settings(run), "WARPCHECK_ALPHA='2': 2 is out of range: give 1e-12 to 0.5");
    for (const char* name : {"WARPCHECK_SEED", "WARPCHECK_SAMPLES", "WARPCHECK_ALPHA"}) ::unsetenv(name);
}

// A float parameter reads as the float it is; a double keeps the digits that
// tell it apart. Reading the name's number back as a float gives the parameter.
TEST(CaseNames, FloatParametersReadAsTheirShortestDecimal) {
    EXPECT_EQ(case_name("uniform_cone", {{"cos_theta_max", 0.3f}}), "uniform_cone[cos_theta_max=0.3]");
    EXPECT_EQ(case_name("c", {{"a", 0.1f}, {"b", 1e-6f}, {"n", 4.0f}}), "c[a=0.1,b=1e-06,n=4]");
    EXPECT_EQ(case_name("c", {{"a", 0.3}}), "c[a=0.3]");
    EXPECT_EQ(case_name("c", {{"a", 0.30000001}}), "c[a=0.30000001]") << "a double that is no float keeps its digits";
    EXPECT_EQ(parameter_value(1e10), "10000000000") << "never longer than the double's own shortest form";
    EXPECT_EQ(parameter_value(16777216.0), "16777216");
    EXPECT_EQ(parameter_value(1e300), "1e+300");
    EXPECT_EQ(parameter_value(std::nan("")), "nan");
    EXPECT_EQ(parameter_value(-0.75f), "-0.75");
    EXPECT_EQ(std::strtof(parameter_value(0.3f).c_str(), nullptr), 0.3f);
    EXPECT_EQ(std::strtof(parameter_value(2.3509886e-38f).c_str(), nullptr), 2.3509886e-38f);
}

}  // namespace
}  // namespace warpcheck
