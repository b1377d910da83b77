// The tabulated check's rules for correct float code that is hard for them
// (issue 22), each with a wrong twin of the same hardness that still fails:
// where the inversion method applies (monotone in u: claimed or measured),
// the reference table in double, what a float warp can reach, chance-free tail
// rules, and NaN as a failure with its own words.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "sampling/float_bits.h"
#include "support/builtin_case.h"
#include "support/check_harness.h"
#include "validate/checks/checks.h"
#include "validate/checks/tabulated/tabulated_reference.h"
#include "validate/api/register17.h"
#include "validate/api/registry.h"
#include "sampling/math.h"

namespace warpcheck {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using testing::run_check;

constexpr std::array<uint64_t, 3> kTabulatedSeeds = {1, 2, 3};

WarpCaseInfo interval_info(const std::string& family, double a = 0.0, double b = 1.0,
                           Inversion inversion = Inversion::Measure) {
    WarpCaseInfo info;
    info.family = family;
    info.description = "tabulated rule test";
    info.domain = chi2::Domain::interval(a, b);
    info.inversion = inversion;
    return info;
}

// --- Where the inversion method applies ------------------------------------

/// A two-component mixture chosen by u: with probability 0.3 the density 2x
/// (sqrt), otherwise 2(1 - x); x falls from ~1 to 0 at u = 0.3. `weight` is
/// the probability sample gives the first component (0.3: correct).
std::unique_ptr<WarpCase> mixture(float weight = 0.3f, Inversion inversion = Inversion::Measure) {
    return make_warp_case(
        interval_info("mixture_chosen_by_u", 0.0, 1.0, inversion),
        warp_of([weight](float u) {
                    if (u < weight) return std::sqrt(u / weight);
                    return 1.0f - std::sqrt(1.0f - (u - weight) / (1.0f - weight));
                })
            .with_pdf([](float x) { return x >= 0.0f && x <= 1.0f ? 0.6f * x + 1.4f * (1.0f - x) : 0.0f; }));
}

/// A 1D piecewise-constant density {0.1, 0.3, 0.2, 0.4} on four buckets of
/// [0, 1], drawn through an alias table (column, then the column's own bucket
/// or its alias), as renderers draw light lists: correct, and not monotone.
std::unique_ptr<WarpCase> alias_table_1d() {
    static constexpr std::array<float, 4> kProb = {0.4f, 0.6f, 0.8f, 1.0f};
    static constexpr std::array<int, 4> kAlias = {1, 3, 3, 3};
    static constexpr std::array<float, 4> kPdf = {0.4f, 1.2f, 0.8f, 1.6f};
    return make_warp_case(
        interval_info("alias_table_1d"),
        warp_of([](float u) {
                    const int column = std::min(static_cast<int>(u * 4.0f), 3);
                    const float r = u * 4.0f - static_cast<float>(column);
                    const float p = kProb[static_cast<std::size_t>(column)];
                    const bool own = r < p;
                    const int bucket = own ? column : kAlias[static_cast<std::size_t>(column)];
                    const float v = own ? r / p : (r - p) / (1.0f - p);
                    return std::min((static_cast<float>(bucket) + v) * 0.25f, kOneMinusEpsilon);
                })
            .with_pdf([](float x) {
                          if (!(x >= 0.0f && x <= 1.0f)) return 0.0f;
                          return kPdf[static_cast<std::size_t>(std::min(static_cast<int>(x * 4.0f), 3))];
                      }));
}

TEST(TabulatedMonotonicity, SamplersThatAreNotMonotoneInUAreNotApplicableWithWhere) {
    const auto check = make_tabulated_check();
    for (uint64_t seed : kTabulatedSeeds) {
        const CheckResult mix = run_check(*check, *mixture(), 200'000, 2, seed);
        EXPECT_EQ(mix.verdict, Verdict::NotApplicable) << mix.summary;
        EXPECT_THAT(mix.summary, HasSubstr("sample is not monotone in u: x falls from "));
        EXPECT_THAT(mix.summary, HasSubstr("at u = 0.3"));
        EXPECT_GT(*mix.figure("monotonicity_largest_step_back"), 0.99);
        const CheckResult alias = run_check(*check, *alias_table_1d(), 200'000, 2, seed);
        EXPECT_EQ(alias.verdict, Verdict::NotApplicable) << alias.summary;
        EXPECT_THAT(alias.summary, HasSubstr("not monotone in u"));
    }
    // Their distributions are still tested, and a wrong mixture fails there.
    const auto chi2 = make_chi2_check();
    EXPECT_EQ(run_check(*chi2, *mixture()).verdict, Verdict::Pass);
    EXPECT_EQ(run_check(*chi2, *alias_table_1d()).verdict, Verdict::Pass);
    EXPECT_EQ(run_check(*chi2, *mixture(0.32f)).verdict, Verdict::Fail);
}

TEST(TabulatedMonotonicity, AMonotoneSamplerIsMeasuredSoAndStillJudged) {
    // x = 1 - sqrt(u) draws 2 (1 - x) decreasing in u: measured decreasing and
    // compared that way (it failed as an increasing view before); its wrong
    // twin (u^0.502) fails the comparison.
    const auto check = make_tabulated_check();
    const auto pdf = [](float x) { return x >= 0.0f && x <= 1.0f ? 2.0f * (1.0f - x) : 0.0f; };
    const auto good =
        make_warp_case(interval_info("decreasing_ramp"),
            warp_of([](float u) { return 1.0f - std::sqrt(u); }).with_pdf(pdf));
    const auto bad =
        make_warp_case(interval_info("decreasing_ramp_off"),
            warp_of([](float u) { return 1.0f - std::pow(u, 0.502f); }).with_pdf(pdf));
    for (uint64_t seed : kTabulatedSeeds) {
        const CheckResult r = run_check(*check, *good, 200'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
        EXPECT_EQ(*r.figure("monotonicity_increasing"), 0.0);
        const CheckResult w = run_check(*check, *bad, 200'000, 2, seed);
        EXPECT_EQ(w.verdict, Verdict::Fail);
        EXPECT_GT(*w.figure("x_failures"), 0.0);
    }
}

TEST(TabulatedMonotonicity, FloatNoiseOnAFlatStretchIsExcusedAndCountedAFoldIsNot) {
    // A lerp across [1, 1.0001] in float: consecutive grid inputs move x by
    // 1.5e-9, far below a float step of 1 (1.2e-7), so the two roundings of
    // (1 - u) a + u b make x step back by an ulp here and there. The twin
    // mirrors u on [0.5, 0.52): the same distribution, folded by 2e-6 (beyond
    // the 16-ulp allowance): not monotone.
    const float b = 1.0001f;
    const double width = static_cast<double>(b) - 1.0;
    const auto lerp = [b](float u) { return (1.0f - u) * 1.0f + u * b; };
    const auto pdf = [b, width](float x) { return x >= 1.0f && x <= b ? 1.0 / width : 0.0; };
    const auto noisy = make_warp_case(interval_info("flat_lerp", 1.0, b), warp_of(lerp).with_pdf(pdf));
    const auto folded = make_warp_case(interval_info("flat_lerp_folded", 1.0, b),
        warp_of([lerp](float u) {
            return lerp(u >= 0.5f && u < 0.52f ? 1.02f - u : u);
        })
            .with_pdf(pdf));
    const auto check = make_tabulated_check();
    for (uint64_t seed : kTabulatedSeeds) {
        const CheckResult r = run_check(*check, *noisy, 200'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
        EXPECT_GT(*r.figure("monotonicity_behind_within_noise"), 0.0);
        EXPECT_LE(*r.figure("monotonicity_largest_step_back"), *r.figure("monotonicity_noise_allowance"));
        EXPECT_EQ(run_check(*check, *folded, 200'000, 2, seed).verdict, Verdict::NotApplicable);
    }
}

TEST(TabulatedMonotonicity, DeclaredNotAnInversionSamplerIsNotApplicableWithoutRunning) {
    const auto check = make_tabulated_check();
    const auto declared = mixture(0.3f, Inversion::NotInversion);
    EXPECT_FALSE(check->applies_to(*declared));
    EXPECT_THAT(check->not_applicable_because(*declared), HasSubstr("not the inversion method"));
    EXPECT_TRUE(check->not_applicable_because(*mixture()).empty());
    // Run anyway (as a direct call would): n/a, not a comparison.
    EXPECT_EQ(run_check(*check, *declared).verdict, Verdict::NotApplicable);
}

TEST(TabulatedMonotonicity, AClaimThatIsNotMonotoneStillFailsAndSaysWhere) {
    const CheckResult r = run_check(*make_tabulated_check(), *mixture(0.3f, Inversion::Claimed));
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_THAT(r.message, HasSubstr("claims x is increasing in u, but on a grid of inputs x falls from"));
    EXPECT_FALSE(r.figure("monotonicity_grid_inputs"));  // claimed: not measured
}

TEST(TabulatedMonotonicity, Cxx17CasesCanDeclareIt) {
    Registry registry;
    cxx17::CaseInfo info;
    info.family = "cxx17_not_inversion";
    info.domain = cxx17::Domain::interval(0.0, 1.0);
    info.inversion = cxx17::Inversion::NotInversion;
    struct Uniform {
        float sample(float u) const { return u; }
        double pdf(float) const { return 1.0; }
    };
    cxx17::add_case(registry, info, Uniform{});
    EXPECT_EQ(registry.cases().at(0)->info().inversion, Inversion::NotInversion);
}

// --- The reference table in double --------------------------------------------

TEST(TabulatedReferenceTable, ALobeBelowTheSmallestFloatKeepsItsQuantiles) {
    // c e^{c (x - 1)} with c = 200 falls below 1.4e-45 (the smallest float) for
    // x < 0.457 and stays positive in double (2.8e-85 at 0): a float table
    // began at 0.457, so its quantile at u = 0 was 0.457 instead of 0.
    const double c = 200.0;
    const TabulatedReference ref([c](double x) { return c * std::exp(c * (x - 1.0)) / -std::expm1(-c); }, 0.0, 1.0,
                                 1.0);
    EXPECT_EQ(ref.sample(0.0).x, 0.0);
    EXPECT_NEAR(ref.sample(1e-60).x, 1.0 + std::log(1e-60) / c, 1.0 / TabulatedReference::kBuckets);
    // In the built-in cos^50 lobe, the float table's quantile at u = 0 was 0.13.
    const CheckResult r = run_check(*make_tabulated_check(),
                                    testing::builtin_case("cosine_power_hemisphere[exponent=50]"), 200'000);
    EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
    EXPECT_LT(*r.figure("cos_theta_max_x_error"), 1e-6);
}

/// The inputs a table lookup is tried at: the ends, every 97th guide boundary
/// g / 2^16 and the floats around it, each edge's CDF value itself (an exact
/// tie with the table) and its neighbours, and a spread of others.
std::vector<double> lookup_inputs(const TabulatedReference& ref) {
    std::vector<double> u = {0.0, 0x1p-60, 0.5, 1.0 - 0x1p-53, 1.0};
    const int n = TabulatedReference::kBuckets;
    for (int g = 0; g <= n; g += 97) {
        const double v = static_cast<double>(g) / n;
        u.insert(u.end(), {v, std::nextafter(v, 0.0), std::nextafter(v, 2.0)});
    }
    for (int k = 0; k <= n; k += 13) {
        const double c = ref.cdf(static_cast<double>(k) / n);  // the table's CDF at edge k: exact on [0, 1]
        u.insert(u.end(), {c, std::nextafter(c, 0.0), std::nextafter(c, 2.0)});
    }
    for (int i = 0; i < 5000; ++i) u.push_back(std::fmod(i * 0.6180339887498949, 1.0));
    std::erase_if(u, [](double v) { return !(v >= 0.0 && v <= 1.0); });
    return u;
}

/// The table's CDF at its edges: on [0, 1], cdf(k / n) is exactly the value at edge k.
std::vector<double> edge_cdf(const TabulatedReference& ref) {
    const int n = TabulatedReference::kBuckets;
    std::vector<double> edges(n + 1);
    for (int k = 0; k <= n; ++k) edges[static_cast<std::size_t>(k)] = ref.cdf(static_cast<double>(k) / n);
    return edges;
}

/// The bucket std::upper_bound over the whole table finds for u.
int whole_table_bucket(const std::vector<double>& edges, double u) {
    const auto it = std::upper_bound(edges.begin(), edges.end(), u);
    return std::clamp(static_cast<int>(it - edges.begin()) - 1, 0, TabulatedReference::kBuckets - 1);
}

TEST(TabulatedReferenceTable, AGuidedLookupFindsTheBucketOfASearchOfTheWholeTable) {
    // A lobe whose mass lies in a few hundred buckets (thousands of guide
    // cells in one bucket), a density with a gap of zero mass (runs of equal
    // edges), and one negative on a stretch (a CDF that steps back: no guide).
    const std::vector<std::function<double(double)>> densities = {
        [](double x) { return 2000.0 * std::exp(2000.0 * (x - 1.0)); },
        [](double x) { return x > 0.3 && x < 0.6 ? 0.0 : 1.0 / 0.7; },
        [](double x) { return x > 0.4 && x < 0.45 ? -1.0 : 1.0; },
    };
    for (std::size_t d = 0; d < densities.size(); ++d) {
        const TabulatedReference ref(densities[d], 0.0, 1.0, 1.0);
        const std::vector<double> edges = edge_cdf(ref);
        for (double v : lookup_inputs(ref))
            ASSERT_EQ(ref.sample(v).offset, whole_table_bucket(edges, v)) << "density " << d << ", u = " << v;
    }
}

TEST(TabulatedReferenceTable, ABatchOfLookupsGivesWhatOneAtATimeGives) {
    const TabulatedReference ref([](double x) { return 11.0 * std::pow(x, 10.0); }, 0.0, 1.0, 1.0);
    std::vector<double> u = lookup_inputs(ref), x(u.size());
    for (std::size_t i = 0; i < u.size(); ++i) x[i] = 1.3 * u[(i * 7) % u.size()] - 0.15;  // some outside [0, 1]
    u[3] = std::numeric_limits<double>::quiet_NaN();  // a tail input: only the envelope is looked up
    x[5] = std::numeric_limits<double>::quiet_NaN();
    std::vector<TabulatedReference::Lookup> batch(u.size());
    ref.lookup(u, x, batch);
    for (std::size_t i = 0; i < u.size(); ++i) {
        const TabulatedReference::Envelope e = ref.envelope(x[i]);
        EXPECT_EQ(batch[i].envelope.lo, e.lo);
        EXPECT_EQ(batch[i].envelope.hi, e.hi);
        EXPECT_EQ(batch[i].envelope.table_pdf, e.table_pdf);
        if (std::isnan(u[i])) continue;
        const TabulatedReference::Sample s = ref.sample(u[i]);
        ASSERT_EQ(batch[i].sample.x, s.x) << "u = " << u[i];
        EXPECT_EQ(batch[i].sample.offset, s.offset);
        EXPECT_EQ(batch[i].x_tolerance, ref.x_tolerance(s.offset, u[i]));
    }
}

// --- What a float warp can reach ----------------------------------------------

/// The cos^n Phong lobe about +z (n = 1000 unless given), with z =
/// u.x^(1/(drawn + 1)) kept below `z_max` (1 - 2^-24: clamped below 1 as
/// renderers keep a frame off the pole, which leaves the last float step, 6e-5
/// of the mass of cos^1000, unreached; lower: a sampler that never reaches the
/// mass above z_max). `drawn` other than n: the sampler draws the wrong lobe.
std::unique_ptr<WarpCase> clamped_phong(const std::string& family, float z_max, double n = 1000.0,
                                        double drawn = 0.0) {
    const auto exponent = static_cast<float>(1.0 / ((drawn > 0.0 ? drawn : n) + 1.0));
    MonotoneMarginal view;
    view.label = "cos theta";
    view.coordinate = [](const WarpOutput& o) { return static_cast<double>(o[2]); };
    view.pdf = [n](double z) { return (n + 1.0) * std::pow(z, n); };
    return make_warp_case(
        {.family = family, .domain = chi2::Domain::hemisphere(), .views = {view}},
        warp_of([z_max, exponent](Point2f u) {
            const float z = std::fmin(std::pow(u.x, exponent), z_max);
            const float r = std::sqrt(std::fmax(0.0f, 1.0f - z * z)), phi = kTwoPi * u.y;
            return Vector3f{r * std::cos(phi), r * std::sin(phi), z};
        })
            .with_pdf([n](Vector3f w) {
                return w.z >= 0.0f ? static_cast<float>((n + 1.0) / (2.0 * std::numbers::pi) * std::pow(w.z, n)) : 0.0f;
            }));
}

TEST(TabulatedReferenceTable, AtTheEndsOfUTheCdfUncertaintyReachesTheEndsOfTheRange) {
    // cos^10000 is 0 in double below z = 0.928, and the table's mass begins
    // there; u.x = 0 rightly gives z = 0, whose CDF is within delta of the
    // table's at u = 0. The twin draws cos^11000: off on x in the body.
    const auto check = make_tabulated_check();
    const auto good = clamped_phong("phong_10000", 1.0f, 10000.0);
    const auto bad = clamped_phong("phong_10000_draws_11000", 1.0f, 10000.0, 11000.0);
    for (uint64_t seed : kTabulatedSeeds) {
        const CheckResult r = run_check(*check, *good, 200'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
        EXPECT_GT(*r.figure("samples_where_both_densities_are_0"), 0.0);
        const CheckResult w = run_check(*check, *bad, 200'000, 2, seed);
        EXPECT_EQ(w.verdict, Verdict::Fail);
        EXPECT_GT(*w.figure("x_failures"), 1000.0);
    }
}

TEST(TabulatedReach, ASharpLobeClampedBelowOnePassesOneMissingItsTopThousandthFails) {
    const auto check = make_tabulated_check();
    const auto good = clamped_phong("phong_1000_clamped_below_1", kOneMinusEpsilon);
    const float z_short = static_cast<float>(std::pow(1.0 - 1e-3, 1.0 / 1001.0));  // 1e-3 of the mass above
    const auto bad = clamped_phong("phong_1000_never_above_top_thousandth", z_short);
    for (uint64_t seed : kTabulatedSeeds) {
        const CheckResult r = run_check(*check, *good, 200'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
        EXPECT_GT(*r.figure("mass_outside_reach"), 5e-5);  // the last float step below 1
        EXPECT_LE(*r.figure("mass_outside_reach"), *r.figure("mass_outside_reach_tolerance"));
        const CheckResult w = run_check(*check, *bad, 200'000, 2, seed);
        EXPECT_EQ(w.verdict, Verdict::Fail);
        EXPECT_NEAR(*w.figure("mass_outside_reach"), 1e-3, 1e-4);
        EXPECT_THAT(w.message, HasSubstr("reach only"));
    }
}

TEST(TabulatedReach, SamplesWhereBothDensitiesAreZeroAreStillJudgedOnX) {
    // Where the warp's and the table's densities are both 0 they agree (the
    // lobe above samples z = 0 at u.x = 0); a sampler that puts samples into a
    // zero-density gap still fails, on x, away from the gap's own CDF level.
    const auto gap_pdf = [](float x) { return (x >= 0.0f && x <= 0.4f) || (x >= 0.6f && x <= 1.0f) ? 1.25f : 0.0f; };
    const auto gap_sample = [](float u) {
        const float x = 0.8f * u;
        return x > 0.4f ? x + 0.2f : x;
    };
    const auto good = make_warp_case(interval_info("gap"), warp_of(gap_sample).with_pdf(gap_pdf));
    const auto bad = make_warp_case(interval_info("gap_filled"),
        warp_of([gap_sample](float u) {
            return u >= 0.49f && u < 0.51f ? 0.5f : gap_sample(u);
        })
            .with_pdf(gap_pdf));
    const auto check = make_tabulated_check();
    for (uint64_t seed : kTabulatedSeeds) {
        EXPECT_EQ(run_check(*check, *good, 200'000, 2, seed).verdict, Verdict::Pass);
        const CheckResult w = run_check(*check, *bad, 200'000, 2, seed);
        EXPECT_EQ(w.verdict, Verdict::Fail);
        EXPECT_GT(*w.figure("x_failures"), 3000.0);  // ~2% of 2e5 inputs
        EXPECT_GT(*w.figure("samples_where_both_densities_are_0"), 3000.0);
    }
    const CheckResult phong =
        run_check(*check, *clamped_phong("phong_1000_clamped_below_1", kOneMinusEpsilon), 200'000);
    EXPECT_GT(*phong.figure("samples_where_both_densities_are_0"), 0.0);
}

TEST(TabulatedReach, StrictGrantsNoFloatStep) {
    const auto good = clamped_phong("phong_1000_clamped_below_1", kOneMinusEpsilon);
    const auto check = make_tabulated_check();
    RunOptions options;
    options.samples = 200'000;
    options.threads = 2;
    options.strict = true;
    options.check_time_budget = testing::kTestTimeBudget;
    const CheckResult r = run_jobs({Job{good.get(), check.get()}}, options).results.at(0);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_THAT(r.message, HasSubstr("not granted under --strict"));
    EXPECT_LT(*r.figure("mass_outside_reach_tolerance"), 1e-6);
    EXPECT_GT(*r.figure("mass_of_float_steps_beyond_reach"), 5e-5);
}

/// c e^{c (x - 1)} on [0.99, 1] with c = 10^4, by inversion in float and then
/// kept below `x_max`: a density concentrated at its upper end, whose last
/// float step below 1 holds 6e-4 of the mass.
std::unique_ptr<WarpCase> end_lobe(const std::string& family, float x_max) {
    constexpr float c = 1e4f, a = 0.99f;
    const float tail = std::exp(-c * (1.0f - a));  // 3.7e-44, a denormal
    const double norm = -std::expm1(-static_cast<double>(c) * (1.0 - static_cast<double>(a)));
    return make_warp_case(
        interval_info(family, a, 1.0),
        warp_of([=](float u) { return std::clamp(1.0f + std::log(u + (1.0f - u) * tail) / c, a, x_max); })
            .with_pdf([=](float x) { return x >= a && x <= 1.0f ? c * std::exp(c * (static_cast<double>(x) - 1.0)) / norm : 0.0; }));
}

TEST(TabulatedReach, ADensityConcentratedAtItsEndReachesItsLastFloat) {
    const auto check = make_tabulated_check();
    const auto good = end_lobe("end_lobe_clamped_below_1", kOneMinusEpsilon);
    const auto bad = end_lobe("end_lobe_three_floats_short", 1.0f - 3.0f * 0x1p-24f);  // 1.8e-3 unreached
    for (uint64_t seed : kTabulatedSeeds) {
        const CheckResult r = run_check(*check, *good, 200'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
        EXPECT_GT(*r.figure("mass_of_float_steps_beyond_reach"), 5e-4);
        const CheckResult w = run_check(*check, *bad, 200'000, 2, seed);
        EXPECT_EQ(w.verdict, Verdict::Fail);
        EXPECT_THAT(w.message, HasSubstr("reach only"));
    }
}

// --- Chance: the tail rule ----------------------------------------------------

/// The logistic of tests/external_example/my_warps17.cpp (mu -3, s 0.25, a view
/// truncated where 1e-4 of the mass lies beyond each end), sampled as renderers
/// write it, in float: mu - s log(1/u - 1). `cut` keeps x below hi - cut (a
/// sampler that misses its upper tail).
struct FloatLogistic {
    static constexpr float mu = -3.0f, s = 0.25f;
    static double lo() { return mu - s * std::log(1e4 - 1.0); }
    static double hi() { return mu + s * std::log(1e4 - 1.0); }
    static float sample(float u) { return mu - s * std::log(1.0f / u - 1.0f); }
    static double pdf(float x) {
        const double e = std::exp(-std::abs(x - mu) / s);
        return e / (s * (1 + e) * (1 + e));
    }
};

std::unique_ptr<WarpCase> float_logistic(const std::string& family, float cut = 0.0f) {
    WarpCaseInfo info = interval_info(family);
    info.domain = chi2::Domain::real_line();
    MonotoneMarginal view;
    view.lo = FloatLogistic::lo();
    view.hi = FloatLogistic::hi();
    view.lower_tail_mass = view.tail_mass = 1e-4;
    view.label = "x";
    info.views = {view};
    const float top = static_cast<float>(FloatLogistic::hi()) - cut;
    return make_warp_case(
        info,
        warp_of([cut, top](float u) { return cut > 0.0f ? std::fmin(FloatLogistic::sample(u), top) : FloatLogistic::sample(u); })
            .with_pdf([](float x) { return FloatLogistic::pdf(x); }));
}

TEST(TabulatedTails, TheInputNextToTheTruncationGetsTheBodysAllowance) {
    // The one input float just above u = 1 - 1e-4 (in the upper tail): 1/u - 1
    // rounds there by a float step of u, and x lands 7.5e-5 short of hi, beyond
    // the float slack (5e-6) the tail rule allowed, within the CDF allowance
    // (9e-4) a body input next to it gets. Drawn with probability 2^-24 per
    // input, it failed about one run in 17 at 10^6 samples.
    const TabulatedReference ref([](double x) { return FloatLogistic::pdf(static_cast<float>(x)); },
                                 FloatLogistic::lo(), FloatLogistic::hi(), 1.0 - 2e-4);
    const float u = 0.999900043f;
    ASSERT_GE(static_cast<double>(u), 1e-4 + (1.0 - 2e-4));
    const double x = FloatLogistic::sample(u);
    EXPECT_LT(x, FloatLogistic::hi() - ref.x_slack());
    EXPECT_GE(x, FloatLogistic::hi() - ref.tail_allowance(true));
    EXPECT_LT(ref.tail_allowance(true), 2e-3);
}

TEST(TabulatedTails, AFloatLogisticPassesOnEverySeedAndOneMissingItsTailFails) {
    // With the float slack alone as the tail's allowance, seeds 1 and 11 of
    // these failed ("1 of 613 inputs in the tails ... land inside the
    // truncation points"): each drew the input of the test above.
    const auto check = make_tabulated_check();
    const auto good = float_logistic("float_logistic[mu=-3,s=0.25]");
    for (uint64_t seed = 1; seed <= 20; ++seed) {
        const CheckResult r = run_check(*check, *good, 1'000'000, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Pass) << "seed " << seed << ": " << r.message;
    }
    const auto bad = float_logistic("logistic_float_short_tail", 0.01f);
    for (uint64_t seed : kTabulatedSeeds) {
        const CheckResult w = run_check(*check, *bad, 200'000, 2, seed);
        EXPECT_EQ(w.verdict, Verdict::Fail);
        EXPECT_GT(*w.figure("tail_failures"), 0.0);
    }
}

// --- NaN is a failure, in words that say so ------------------------------------

TEST(TabulatedNaN, AWarpThatReturnsNaNEverywhereFailsAndSaysSo) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const auto warp = make_warp_case(interval_info("nan_everywhere"),
        warp_of([nan](float) { return nan; }).with_pdf([nan](float) { return nan; }));
    const CheckResult r = run_check(*make_tabulated_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail) << r.message;
    EXPECT_THAT(r.message, HasSubstr("the density is NaN at all"));
    EXPECT_THAT(r.message, HasSubstr("sample is NaN at all"));
    EXPECT_THAT(r.message, Not(HasSubstr("discontinuous")));
    EXPECT_EQ(r.summary, "density NaN everywhere");
}

TEST(TabulatedNaN, NaNSamplesOfADeclaredViewFailWithTheirCount) {
    MonotoneMarginal view;
    view.label = "cos theta";
    view.coordinate = [](const WarpOutput& o) { return static_cast<double>(o[2]); };
    view.pdf = [](double) { return 1.0; };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const auto warp =
        make_warp_case({.family = "nan_hemisphere", .domain = chi2::Domain::hemisphere(), .views = {view}},
                       warp_of([nan](Point2f) { return Vector3f{nan, nan, nan}; })
                           .with_pdf([nan](Vector3f) { return nan; }));
    const CheckResult r = run_check(*make_tabulated_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail);
    EXPECT_THAT(r.message, HasSubstr("every sample is NaN"));
    EXPECT_EQ(r.summary, "every sample NaN");
}

TEST(TabulatedNaN, ADensityThatIsNaNSomewhereFailsNotErrors) {
    const auto warp = make_warp_case(interval_info("nan_pdf_above_0.7"),
        warp_of([](float u) { return u; })
            .with_pdf([](float x) {
                return x > 0.7f ? std::numeric_limits<float>::quiet_NaN() : 1.0f;
            }));
    const CheckResult r = run_check(*make_tabulated_check(), *warp);
    EXPECT_EQ(r.verdict, Verdict::Fail) << r.message;
    EXPECT_THAT(r.message, HasSubstr("the density is NaN at"));
    EXPECT_THAT(r.message, HasSubstr("(first at x = 0.70"));
}

TEST(TabulatedNaN, PassingRowsOfHardCorrectWarpsPrintNoNaN) {
    const auto check = make_tabulated_check();
    const std::array<std::unique_ptr<WarpCase>, 3> warps = {
        clamped_phong("phong", kOneMinusEpsilon), end_lobe("end", kOneMinusEpsilon), float_logistic("logistic")};
    for (const auto& warp : warps) {
        const CheckResult r = run_check(*check, *warp);
        EXPECT_EQ(r.verdict, Verdict::Pass) << r.message;
        EXPECT_THAT(r.summary, Not(HasSubstr("nan")));
        EXPECT_THAT(r.summary, Not(HasSubstr("inf")));
    }
}

}  // namespace
}  // namespace warpcheck
