// `validate --fuzz` and `--fuzz-case` from the command line: a clean family
// exits 0 and writes every point's rows to --json with --fuzz-case rerun
// lines; a finding's rerun line reruns it; bad usage exits 2 with the reason.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "support/run_command.h"

namespace warpcheck {
namespace {

using testing::run_validate;

TEST(CliFuzz, ACleanFamilyExitsZeroAndWritesEveryPointsRowsWithFuzzCaseReruns) {
    const std::string json = ::testing::TempDir() + "cli_fuzz_lambertian.json";
    const auto r = run_validate("--fuzz --filter lambertian --fuzz-points 4 --json " + json);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("fuzz: 1 families"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(": 0 findings, 0 refusals"), std::string::npos) << r.output;
    std::ifstream in(json);
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_NE(text.str().find("\"check\":\"bsdf_energy\""), std::string::npos) << text.str().substr(0, 400);
    EXPECT_NE(text.str().find("--fuzz-case 'lambertian[R=0,theta_o=0]'"), std::string::npos);
    EXPECT_EQ(text.str().find("--filter '"), std::string::npos) << "a row's rerun names a case no grid registered";
}

TEST(CliFuzz, AFuzzCaseRunsTheChecksAtTheNamedParameters) {
    const auto r = run_validate("--fuzz-case 'rough_conductor[alpha=0.0001,theta_o=89.5]' --check bsdf_weight --samples 20000");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("rough_conductor[alpha=0.0001,theta_o=89.5]"), std::string::npos) << r.output;
}

TEST(CliFuzz, AFailingFuzzCasesRerunLineIsAFuzzCaseLine) {
    // Beyond the family's declared range (10^-5 degrees off the horizon): a float limit it fails.
    const std::string name = "rough_conductor_aniso[ax=0.0001,ay=0.0001,theta_o=89.99999,phi_o=0.05]";
    const auto r = run_validate("--fuzz-case '" + name + "' --check bsdf_weight --samples 20000");
    ASSERT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("--fuzz-case '" + name + "' --check bsdf_weight"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("--filter '"), std::string::npos) << r.output;
}

TEST(CliFuzz, BadUsageExitsTwoWithTheReason) {
    for (const auto& [args, reason] : std::vector<std::pair<std::string, std::string>>{
             {"--fuzz --all", "--fuzz runs on its own"},
             {"--fuzz --fuzz-points 20000", "more than 10000"},
             {"--fuzz --filter no_such_family", "no family selected by --filter declares a parameter range"},
             {"--fuzz --check no_such_check", "no_such_check"},
             {"--fuzz-case 'no_such_family[a=1]'", "no family 'no_such_family'"},
             {"--fuzz-case 'rough_conductor[alpha=0.3]'", "no value for theta_o"},
             {"--fuzz-case 'rough_conductor[alpha=7e9,theta_o=3]'", "refuses these parameters"},
             {"--fuzz-case 'lambertian[R=0.5,theta_o=3]' --all", "takes no --all or --filter"}}) {
        const auto r = run_validate(args);
        EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find(reason), std::string::npos) << args << "\n" << r.output;
    }
}

}  // namespace
}  // namespace warpcheck
