// repeatability and bsdf_repeatability (validate/checks/repeatability/): every
// built-in case gives the same bits twice on several seeds; a sampler with
// state its inputs do not carry fails, though its law is right (chi2 passes
// it), and a cache that is hard for the rule (hits that depend on the order
// of calls) passes when it checks its whole key, while a memo keyed on part
// of its input fails;
// a stochastic BSDF's f estimates are counted, not judged, while its
// directions are; a NaN, though its bits repeat, fails; a batched sampler
// whose tail rounds otherwise than its body passes, and one with state across
// batches fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <span>
#include <stdexcept>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "sampling/bsdf_conductor.h"
#include "sampling/bsdf_layered.h"
#include "sampling/hemisphere.h"
#include "support/check_harness.h"
#include "validate/api/bsdf_case.h"
#include "validate/api/registry.h"
#include "validate/checks/checks.h"
#include "validate/checks/repeatability/repeatability_check.h"
#include "validate/run/runner.h"

namespace warpcheck {
namespace {

using testing::figure_of;
using testing::run_check;

WarpCaseInfo hemisphere_info(const char* family) {
    return {family, {}, "test warp", InputKind::Uniform2D, chi2::Domain::hemisphere()};
}

/// The fractional part of x + k phi (phi the golden ratio's fraction), below 1 in float.
float shifted(float x, uint32_t k) {
    const double v = static_cast<double>(x) + 0.6180339887498949 * static_cast<double>(k);
    return std::min(static_cast<float>(v - std::floor(v)), 0x1.fffffep-1f);
}

/// The cosine hemisphere fed u.x moved by k phi (mod 1) on its k-th call: each
/// sample is still cosine distributed, but its input does not decide it.
std::unique_ptr<WarpCase> cosine_with_own_sequence() {
    auto calls = std::make_shared<std::atomic<uint32_t>>(0);
    return make_warp_case(hemisphere_info("cosine_own_sequence"),
                          warp_of([calls](Point2f u) {
                              return CosineHemisphere{}.sample({shifted(u.x, calls->fetch_add(1)), u.y});
                          }).with_pdf([](Vector3f v) { return CosineHemisphere{}.pdf(v); }));
}

/// The cosine hemisphere behind a per-thread direct-mapped cache of 4096
/// entries indexed by u.x's leading bits, an entry used only for the input it
/// was computed for: hits depend on which inputs came before (hard for the
/// rule), outputs do not (correct).
std::unique_ptr<WarpCase> cached_cosine() {
    return make_warp_case(hemisphere_info("cosine_cached"),
                          warp_of([](Point2f u) {
                              struct Entry {
                                  bool valid = false;
                                  Point2f u{};
                                  Vector3f out{};
                              };
                              thread_local std::array<Entry, 4096> cache{};
                              Entry& e = cache[static_cast<std::size_t>(u.x * 4096.0f) & 4095u];
                              if (e.valid && e.u.x == u.x && e.u.y == u.y) return e.out;
                              e = {true, u, CosineHemisphere{}.sample(u)};
                              return e.out;
                          }).with_pdf([](Vector3f v) { return CosineHemisphere{}.pdf(v); }));
}

/// Its wrong twin: a per-thread memo of the last call, reused when u.x falls
/// in the same 1/256 of [0, 1) (a coherence cache keyed on part of its input):
/// about 1 call in 256 gets the previous call's output, which depends on the
/// order of calls. (A direct-mapped cache keyed by slot alone is no twin: once
/// every slot is filled it never changes, so its stale outputs repeat; that
/// law error is chi2's to see.)
std::unique_ptr<WarpCase> last_call_memo_cosine() {
    return make_warp_case(hemisphere_info("cosine_last_call_memo"),
                          warp_of([](Point2f u) {
                              thread_local bool valid = false;
                              thread_local int slot = -1;
                              thread_local Vector3f out{};
                              const int s = static_cast<int>(u.x * 256.0f);
                              if (valid && s == slot) return out;
                              valid = true, slot = s, out = CosineHemisphere{}.sample(u);
                              return out;
                          }).with_pdf([](Vector3f v) { return CosineHemisphere{}.pdf(v); }));
}

/// The cosine hemisphere as a batched sampler of 32 lanes (16 floats unrolled
/// twice) with a scalar tail: the tail computes cos theta as sqrt(1 - u.x) in
/// double, the body in float, so the same input gets other bits in the tail
/// than in the body (correct, and hard for the rule: only batch shape keeps
/// them apart). `carry`: the twin, whose body adds to u.y a residue that
/// depends on how many batches came before (state across calls).
class LanedCosine final : public WarpCase {
public:
    explicit LanedCosine(bool carry)
        : WarpCase(hemisphere_info(carry ? "cosine_laned_carry" : "cosine_laned"),
                   {.input = InputKind::Uniform2D, .output_dimension = 3}),
          carry_(carry) {}
    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override {
        const std::size_t body = in.size() - in.size() % 32;
        const uint32_t batch = calls_.load();
        for (std::size_t i = 0; i < in.size(); ++i) {
            const float ux = in[i].u[0];
            float uy = in[i].u[1];
            if (carry_ && i < body) uy = std::min(uy + 0x1p-20f * static_cast<float>(batch % 3), 0x1.fffffep-1f);
            const double cos_theta = i < body ? static_cast<double>(std::sqrt(1.0f - ux)) : std::sqrt(1.0 - ux);
            const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
            const double phi = 2.0 * 3.14159265358979323846 * static_cast<double>(uy);
            out[i] = {static_cast<float>(sin_theta * std::cos(phi)), static_cast<float>(sin_theta * std::sin(phi)),
                      static_cast<float>(cos_theta)};
        }
        (void)calls_.fetch_add(1);
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override {
        for (std::size_t i = 0; i < x.size(); ++i) out[i] = x[i][2] > 0.0f ? x[i][2] / 3.14159265358979323846 : 0.0;
    }
    void invert(std::span<const WarpOutput>, std::span<WarpInput>) const override {
        throw std::logic_error("no inverse");
    }

private:
    bool carry_;
    mutable std::atomic<uint32_t> calls_{0};
};

// Batch shape kept: a batched sampler whose body and tail give one input
// different bits passes (on batches whose size is not a multiple of 32, the
// edge chunk's); the same sampler shifting u.y by a count of the batches
// before fails.
TEST(Repeatability, ABatchedSamplersTailPassesAndStateAcrossBatchesFails) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult ok = run_check(*make_repeatability_check(), LanedCosine(false), 1 << 16, 2, seed);
        EXPECT_EQ(ok.verdict, Verdict::Pass) << ok.message;
        const CheckResult bad = run_check(*make_repeatability_check(), LanedCosine(true), 1 << 16, 2, seed);
        EXPECT_EQ(bad.verdict, Verdict::Fail) << bad.message;
    }
}

TEST(Repeatability, EveryBuiltinCaseGivesTheSameBitsOnThreeSeeds) {
    Registry registry;
    register_builtin_cases(registry);
    const auto warps = make_repeatability_check(), bsdfs = make_bsdf_repeatability_check();
    int rows = 0;
    for (uint64_t seed = 1; seed <= 3; ++seed)
        for (const auto& c : registry.cases()) {
            const Check& check = as_bsdf(*c) ? *bsdfs : *warps;
            // 2^14 random inputs a seed (validate runs 2^16): three seeds of
            // every case in a quarter of the time.
            const CheckResult r = run_check(check, *c, 1 << 14, 2, seed);
            ++rows;
            EXPECT_EQ(r.verdict, Verdict::Pass) << c->name() << " seed " << seed << ": " << r.message;
            EXPECT_EQ(figure_of(r, "differing_inputs"), 0.0) << c->name();
            EXPECT_GT(figure_of(r, "inputs"), 16384.0) << c->name();  // the random inputs and the edges
        }
    EXPECT_GT(rows, 3 * 100);
}

// The law is right, so the distribution test passes it; its outputs do not
// repeat, so this check fails it, naming the sample's point.
TEST(Repeatability, ASamplerWithItsOwnSequenceFailsThoughItsLawIsRight) {
    const auto warp = cosine_with_own_sequence();
    const CheckResult chi2 = run_check(*make_chi2_check(), *warp);
    EXPECT_EQ(chi2.verdict, Verdict::Pass) << chi2.message;
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult r = run_check(*make_repeatability_check(), *warp, 1 << 16, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Fail) << r.message;
        EXPECT_GT(figure_of(r, "differing_points"), 60000.0);
        EXPECT_NE(r.message.find("keeps state"), std::string::npos) << r.message;
        EXPECT_NE(r.message.find(" then "), std::string::npos) << r.message;
    }
}

// The hard correct case and its wrong twin: caches hit in a different order
// on the second pass; only the one that checks its whole key gives the same
// bits.
TEST(Repeatability, ACacheThatChecksItsWholeKeyPassesAndOneThatDoesNotFails) {
    const auto good = cached_cosine(), bad = last_call_memo_cosine();
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult g = run_check(*make_repeatability_check(), *good, 1 << 16, 2, seed);
        EXPECT_EQ(g.verdict, Verdict::Pass) << g.message;
        const CheckResult b = run_check(*make_repeatability_check(), *bad, 1 << 16, 2, seed);
        EXPECT_EQ(b.verdict, Verdict::Fail) << b.message;
        EXPECT_GT(figure_of(b, "differing_inputs"), 100.0);
    }
}

CoatedBsdf<RoughConductor> coated_gold() { return CoatedBsdf(RoughConductor(TrowbridgeReitz(0.3f), 0.2f, 3.0f), 1.5f); }

/// A stochastic coated BSDF whose sampled f estimates take a factor in
/// [0.5, 1.5) from its own sequence (`in_f`), or whose directions do (otherwise).
std::unique_ptr<WarpCase> coated_with_own_sequence(bool in_f) {
    const Vector3f wo = bsdf_direction(40.0);
    auto calls = std::make_shared<std::atomic<uint32_t>>(0);
    const auto bsdf = coated_gold();
    return make_bsdf_case({.family = in_f ? "coated_own_f_sequence" : "coated_own_wi_sequence"},
                          {.wo = wo, .lobes = bsdf.flags(), .stochastic = true},
                          bsdf_of([bsdf, calls, in_f](Vector3f w, float uc, Point2f u) {
                              const uint32_t k = calls->fetch_add(1);
                              if (in_f) {
                                  BsdfSample s = bsdf.sample(w, uc, u);
                                  s.f *= 0.5f + shifted(0.5f, k);
                                  return s;
                              }
                              return bsdf.sample(w, uc, {shifted(u.x, k), u.y});
                          })
                              .with_f([bsdf](Vector3f a, Vector3f b) { return bsdf.f(a, b); })
                              .with_pdf([bsdf](Vector3f a, Vector3f b) { return bsdf.pdf(a, b); }));
}

TEST(Repeatability, AStochasticBsdfsEstimatesAreCountedAndItsDirectionsJudged) {
    const auto check = make_bsdf_repeatability_check();
    const CheckResult f = run_check(*check, *coated_with_own_sequence(true), 1 << 16);
    EXPECT_EQ(f.verdict, Verdict::Pass) << f.message;
    EXPECT_GT(figure_of(f, "excused_values"), 1000.0);
    EXPECT_NE(f.summary.find("not judged"), std::string::npos) << f.summary;
    const CheckResult wi = run_check(*check, *coated_with_own_sequence(false), 1 << 16);
    EXPECT_EQ(wi.verdict, Verdict::Fail) << wi.message;
    EXPECT_GT(figure_of(wi, "differing_points"), 1000.0);
}

/// The cosine hemisphere, NaN wherever u.x < `below` (its own bits each time).
std::unique_ptr<WarpCase> cosine_nan_below(float below) {
    return make_warp_case(hemisphere_info("cosine_nan_slice"),
                          warp_of([below](Point2f u) {
                              const float nan = std::numeric_limits<float>::quiet_NaN();
                              return u.x < below ? Vector3f{nan, nan, nan} : CosineHemisphere{}.sample(u);
                          }).with_pdf([](Vector3f v) { return CosineHemisphere{}.pdf(v); }));
}

// A NaN equals nothing, its own bits included: a sampler that is NaN on a
// thin slice of its inputs (1 in 1000: about 65 of the 2^16) gives the same
// NaN both times and still fails, counted as such; with the slice empty the
// same code passes.
TEST(Repeatability, ANaNThatRepeatsItsBitsStillFails) {
    for (uint64_t seed = 1; seed <= 3; ++seed) {
        const CheckResult r = run_check(*make_repeatability_check(), *cosine_nan_below(1e-3f), 1 << 16, 2, seed);
        EXPECT_EQ(r.verdict, Verdict::Fail) << r.message;
        EXPECT_GT(figure_of(r, "nan_inputs"), 20.0) << r.message;
        EXPECT_EQ(figure_of(r, "nan_inputs"), figure_of(r, "differing_inputs"));
        EXPECT_NE(r.message.find("cannot be shown to repeat"), std::string::npos) << r.message;
        const CheckResult ok = run_check(*make_repeatability_check(), *cosine_nan_below(0.0f), 1 << 16, 2, seed);
        EXPECT_EQ(ok.verdict, Verdict::Pass) << ok.message;
        EXPECT_EQ(figure_of(ok, "nan_inputs"), 0.0);
    }
}

// The row's judged line holds differing_inputs to zero.
TEST(Repeatability, TheJudgedLineHoldsTheCountToZero) {
    const CheckResult r = run_check(*make_repeatability_check(), *cosine_with_own_sequence(), 1 << 16);
    ASSERT_FALSE(r.judged.empty());
    bool found = false;
    for (const JudgedQuantity& q : r.judged)
        if (q.quantity.find("changed when computed again") != std::string::npos) {
            found = true;
            EXPECT_EQ(q.state, JudgedQuantity::State::Beyond);
        }
    EXPECT_TRUE(found);
}

}  // namespace
}  // namespace warpcheck
