// "bsdf_delta": the delta lobes (a mirror, a smooth interface's refraction).
// A delta sample claims, as its pdf, the probability of choosing its lobe, and
// its direction is fixed by wo. Rules:
//  - statistical: the share of draws that chose each lobe against the
//    probability its samples claim (two-sided exact binomial test; the lobes'
//    p-values combined by Sidak, so the check is one test of the run's family);
//  - each lobe's claimed probability is one number at a given wo: its samples
//    may differ by float rounding only (relative kClaimSpread);
//  - a reflection goes to the mirror direction (-wo.x, -wo.y, wo.z) within
//    kReflectionTolerance;
//  - a transmission reports eta = eta(wi) / eta(wo) as the case claims it
//    (claims.eta below over above, within kEtaTolerance of bsdf_common.h) and goes where Snell's
//    law with that eta sends it, within transmission_tolerance (edge inputs too).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "chi2/min_p.h"
#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/checks/bsdf/bsdf_common.h"
#include "validate/checks/bsdf/bsdf_statistics.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/formatting.h"
#include "validate/checks/shared/power_level.h"

namespace warpcheck::bsdf {
namespace {

/// A mirror about the macro normal negates x and y: exact in float, or a few
/// roundings when written as 2 (wo.n) n - wo; 2^-20 (8 float ulps of 1) is far
/// below any wrong direction.
constexpr double kReflectionTolerance = 0x1p-20;
/// How much one lobe's claimed probabilities may spread, relative: 2^-16
/// (a Fresnel term in float, whose rounding does not depend on the input).
constexpr double kClaimSpread = 0x1p-16;

/// Snell's law in float: the components carry a few roundings (2^-20), and
/// cos theta_t = sqrt(1 - sin^2 theta_t) turns an error e of sin^2 (a few
/// ulps, 2^-21) into e / (2 cos theta_t): the tolerance grows near the
/// critical angle, where a wrong eta still moves the direction by far more.
double transmission_tolerance(double cos_t) { return 0x1p-20 + 0x1p-21 / std::max(std::abs(cos_t), 0x1p-20); }

/// Where a delta lobe sends wo: the mirror, or Snell with eta = eta(wi) / eta(wo).
/// False when Snell admits no refraction (beyond the critical angle).
bool expected_direction(const BsdfCase& bsdf, int lobe, double eta, std::array<double, 3>& w, double& cos_t) {
    const Vector3f wo = bsdf.wo();
    const double x = wo.x, y = wo.y, z = wo.z;
    if (lobe == 0) {
        w = {-x, -y, z};
        cos_t = 1.0;
        return true;
    }
    const double sin2_t = (x * x + y * y) / (eta * eta);
    if (!(sin2_t < 1.0)) return false;
    cos_t = std::sqrt(1.0 - sin2_t);
    w = {-x / eta, -y / eta, z > 0.0 ? -cos_t : cos_t};
    return true;
}

struct DeltaExample {
    WarpInput input;
    BsdfRecord record;
    double error = 0.0;
};

struct DeltaStats {
    DeltaTally tally;  ///< random draws only
    uint64_t draws = 0;
    std::array<double, kDeltaLobes> max_error{};
    Tally<DeltaExample> off_direction, wrong_eta, no_refraction;
    void merge(const DeltaStats& o) {
        tally.merge(o.tally);
        draws += o.draws;
        for (int k = 0; k < kDeltaLobes; ++k)
            max_error[static_cast<std::size_t>(k)] =
                max_nan_wins(max_error[static_cast<std::size_t>(k)], o.max_error[static_cast<std::size_t>(k)]);
        off_direction.merge(o.off_direction);
        wrong_eta.merge(o.wrong_eta);
        no_refraction.merge(o.no_refraction);
    }
};

void judge_delta_direction(const BsdfCase& bsdf, DeltaStats& s, uint64_t index, const DeltaExample& base) {
    const BsdfRecord& r = base.record;
    const int lobe = DeltaTally::lobe_of(bsdf, r);
    if (lobe == 1 && !(std::abs(r.eta / claimed_eta(bsdf) - 1.0) <= kEtaTolerance)) s.wrong_eta.add(index, base);
    std::array<double, 3> w{};
    double cos_t = 1.0;
    if (!expected_direction(bsdf, lobe, r.eta, w, cos_t)) {
        s.no_refraction.add(index, base);
        return;
    }
    DeltaExample e = base;
    e.error = std::hypot(r.wi[0] - w[0], r.wi[1] - w[1], r.wi[2] - w[2]);
    double& worst = s.max_error[static_cast<std::size_t>(lobe)];
    worst = max_nan_wins(worst, e.error);
    const double tol = lobe == 0 ? kReflectionTolerance : transmission_tolerance(cos_t);
    if (!(e.error <= tol)) s.off_direction.add(index, e);
}

DeltaStats compute_delta(const BsdfCase& bsdf, const CheckContext& ctx) {
    const auto parts = map_bsdf_chunks<DeltaStats>(
        ctx, bsdf, ctx.options().samples, true,
        [&](std::size_t chunk, std::span<const WarpInput> in, std::span<const BsdfRecord> rec) {
            DeltaStats s;
            if (chunk > 0) s.draws = rec.size();
            for (std::size_t i = 0; i < rec.size(); ++i) {
                if (!rec[i].sampled() || !rec[i].delta()) continue;
                if (chunk > 0) s.tally.add(bsdf, rec[i]);  // the binomial test takes random draws only
                judge_delta_direction(bsdf, s, chunk * kInputChunkSize + i, DeltaExample{in[i], rec[i], 0.0});
            }
            return s;
        });
    return merge_in_order(parts);
}

struct LobeTest {
    bool tested = false;
    double p_value = 1.0, spread = 0.0, detectable = 0.0;
};

std::array<LobeTest, kDeltaLobes> lobe_tests(const DeltaStats& s, double level) {
    std::array<LobeTest, kDeltaLobes> out{};
    for (int k = 0; k < kDeltaLobes; ++k) {
        const DeltaTally::Lobe& l = s.tally.lobes[static_cast<std::size_t>(k)];
        LobeTest& t = out[static_cast<std::size_t>(k)];
        if (l.count == 0) continue;
        t.tested = true;
        t.spread = (l.pdf_max - l.pdf_min) / l.pdf_max;
        t.p_value = binomial_band_p(l.count, s.draws, l.pdf_min, l.pdf_max);
        const double p = l.claimed();
        t.detectable = detectable_shift_in_standard_errors(level) * std::sqrt(p * (1.0 - p) / static_cast<double>(s.draws));
    }
    return out;
}

std::string describe_delta(const DeltaExample& e) {
    return fmt::format("input {}: wi ({:.9g}, {:.9g}, {:.9g}), eta {:.9g}, pdf {:.9g}",
                       format_input(e.input, InputKind::Uniform3D), e.record.wi[0], e.record.wi[1], e.record.wi[2],
                       e.record.eta, e.record.pdf);
}

std::vector<std::string> failures(const BsdfCase& bsdf, const DeltaStats& s, const std::array<LobeTest, kDeltaLobes>& t) {
    std::vector<std::string> out;
    for (int k = 0; k < kDeltaLobes; ++k) {
        const LobeTest& lt = t[static_cast<std::size_t>(k)];
        if (lt.tested && !(lt.spread <= kClaimSpread))
            out.push_back(fmt::format("the {} lobe's samples claim probabilities from {:.9g} to {:.9g} (one wo, "
                                      "one lobe: one probability)", delta_lobe_name(k),
                                      s.tally.lobes[static_cast<std::size_t>(k)].pdf_min,
                                      s.tally.lobes[static_cast<std::size_t>(k)].pdf_max));
    }
    if (s.wrong_eta.count > 0)
        out.push_back(fmt::format("{} transmissions report an eta that is not eta(wi) / eta(wo) = {:.9g} of the claims "
                                  "(first: {})", s.wrong_eta.count, claimed_eta(bsdf), describe_delta(*s.wrong_eta.first)));
    if (s.no_refraction.count > 0)
        out.push_back(fmt::format("{} transmissions beyond the critical angle of their own eta (first: {})",
                                  s.no_refraction.count, describe_delta(*s.no_refraction.first)));
    if (s.off_direction.count > 0)
        out.push_back(fmt::format("{} delta samples off their lobe's direction (mirror, or Snell with the sample's "
                                  "eta) by up to {:.3g} (first: {}, off by {:.3g})", s.off_direction.count,
                                  std::max(s.max_error[0], s.max_error[1]), describe_delta(*s.off_direction.first),
                                  s.off_direction.first->error));
    return out;
}

Table lobe_table(const DeltaStats& s, const std::array<LobeTest, kDeltaLobes>& t) {
    Table table{"Delta lobes",
                {"lobe", "samples", "share", "claimed probability", "p-value", "90% power: probability error",
                 "max direction error", "mean weight"},
                {}};
    for (int k = 0; k < kDeltaLobes; ++k) {
        const DeltaTally::Lobe& l = s.tally.lobes[static_cast<std::size_t>(k)];
        const LobeTest& lt = t[static_cast<std::size_t>(k)];
        if (!lt.tested) continue;
        table.rows.push_back({delta_lobe_name(k), std::to_string(l.count),
                              fmt::format("{:.6g}", static_cast<double>(l.count) / static_cast<double>(s.draws)),
                              fmt::format("{:.6g}", l.claimed()), fmt::format("{:.3g}", lt.p_value),
                              fmt::format("{:.3g}", lt.detectable), fmt::format("{:.3g}", s.max_error[static_cast<std::size_t>(k)]),
                              fmt::format("{:.6g}", l.mean_weight())});
    }
    return table;
}

void add_figures(CheckResult& r, const DeltaStats& s, const std::array<LobeTest, kDeltaLobes>& t, double level) {
    r.samples = s.draws;
    r.figures = {{"samples", static_cast<double>(s.draws)}, {"power_level", level},
                 {"off_direction", static_cast<double>(s.off_direction.count)},
                 {"wrong_eta", static_cast<double>(s.wrong_eta.count)}};
    const char* keys[kDeltaLobes] = {"reflection", "transmission"};
    for (int k = 0; k < kDeltaLobes; ++k) {
        const DeltaTally::Lobe& l = s.tally.lobes[static_cast<std::size_t>(k)];
        const LobeTest& lt = t[static_cast<std::size_t>(k)];
        const std::string key = keys[k];
        r.figures.insert(r.figures.end(), {{key + "_samples", static_cast<double>(l.count)},
                                           {key + "_claimed", l.claimed()},
                                           {key + "_p_value", lt.p_value},
                                           {key + "_power_probability_error", lt.detectable},
                                           {key + "_max_direction_error", s.max_error[static_cast<std::size_t>(k)]}});
    }
}

class BsdfDeltaCheck final : public BsdfCheck {
public:
    std::string name() const override { return "bsdf_delta"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"off_direction", "delta samples off their mirror or Snell direction", FigureRule::Zero},
                            {"wrong_eta", "delta samples whose eta is not the case's", FigureRule::Zero}},
                .p_value = "p-value: the smallest lobe's, \u0160id\u00e1k-corrected over the lobes tested"};
    }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "Each delta lobe's share of draws against the probability its samples claim (exact "
                "binomial), and its direction (mirror, Snell) and eta within float rounding.",
                "The smallest lobe's p-value, \u0160id\u00e1k-corrected over the lobes tested."};
    }
    std::string description() const override {
        return "BSDF: each delta lobe's share of draws against its claimed probability (binomial, Sidak-corrected), "
               "its direction exact (mirror; Snell with the sample's eta) and its eta as claimed";
    }

protected:
    Applicability bsdf_applicability(const BsdfCase& b) const override {
        return Applicability::when(has(b.claims().lobes, BsdfFlags::Delta));
    }

    CheckResult run_bsdf(const BsdfCase& bsdf, const CheckContext& ctx) const override {
        const DeltaStats s = compute_delta(bsdf, ctx);
        const int tested = (s.tally.lobes[0].count > 0) + (s.tally.lobes[1].count > 0);
        const double level = power_level(ctx.options(), std::max(tested, 1));
        const auto tests = lobe_tests(s, level);
        CheckResult r;
        add_figures(r, s, tests, level);
        std::vector<double> p;
        for (const LobeTest& t : tests)
            if (t.tested) p.push_back(t.p_value);
        r.p_value = p.empty() ? 1.0 : chi2::sidak_min_p(p);
        r.summary = fmt::format("delta share R {:.6g} claimed {:.6g}, T {:.6g} claimed {:.6g}; max dir. error {:.3g}",
                                static_cast<double>(s.tally.lobes[0].count) / static_cast<double>(s.draws),
                                s.tally.lobes[0].claimed(),
                                static_cast<double>(s.tally.lobes[1].count) / static_cast<double>(s.draws),
                                s.tally.lobes[1].claimed(), std::max(s.max_error[0], s.max_error[1]));
        const std::vector<std::string> f = failures(bsdf, s, tests);
        r.verdict = f.empty() ? Verdict::Pass : Verdict::Fail;
        if (!f.empty()) {
            r.summary = f.front();
            r.message = join_reasons(f);
        }
        r.tables.push_back(lobe_table(s, tests));
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_bsdf_delta_check() { return std::make_unique<BsdfDeltaCheck>(); }

}  // namespace warpcheck::bsdf
