// "bsdf_spectral": the secondary channels of a spectral BSDF's samples
// (validate/api/bsdf_case.h, make_spectral_bsdf_case). Each channel case runs
// every BSDF check on its hero channel (its f and pdf; per channel, its rows
// in the run's Sidak family); this check holds the values a sample carries
// for the other channels to what f() and pdf() say there, since a renderer
// weights each of them by them:
//  - every channel's f and pdf finite and not negative;
//  - a secondary channel's pdf either 0 (the channel terminated, counted:
//    pbrt-v4's dispersion) or, like its f, in the hero's proportion that f()
//    and pdf() give at wi: f[c] / f[h] against f_c(wo, wi) / f_h(wo, wi), and
//    pdf[c] / pdf[h] against pdf_c / pdf_h, within 2^-12 relative (as
//    bsdf_weight's). A ratio at one wi cancels what the channels share (the
//    microfacet's D and G, whose float rounding bsdf_weight excuses when a
//    sampled microfacet and the one recomputed from wi differ), and leaves
//    each channel's own factor (a Fresnel term), computed twice from one wi
//    within a few roundings; a channel's term 0.5% off misses by 20 times it;
//  - where the hero's value or f()'s is 0 (no ratio), the secondary against
//    f_c(wo, wi) itself, within 2^-12; a terminated channel's f is not
//    compared (its weight is dropped);
//  - the hero record every other check of the case sees (an object's
//  sample_hero, its fast path, where it has one) bit for bit the spectral
//  sample's hero channel;
//  - draws without a sample and delta samples (no f() to compare) counted.
// Exact (no p-value): it fails on any sample beyond its tolerance.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/checks/bsdf/bsdf_common.h"
#include "validate/checks/shared/evidence.h"

namespace warpcheck::bsdf {
namespace spectral_detail {

/// The tolerance of a secondary channel's ratio to the hero: 2^-12 relative
/// (32 float roundings), as bsdf_weight's.
constexpr double kTolerance = 0x1p-12;

struct Tally {
    uint64_t draws = 0, compared = 0, terminated = 0, delta = 0, unsampled = 0;
    uint64_t bad_value = 0, f_mismatch = 0, pdf_mismatch = 0, direct = 0, hero_mismatch = 0;
    double worst_f = 0.0, worst_pdf = 0.0;
    std::string first;
    void merge(const Tally& o) {
        draws += o.draws, compared += o.compared, terminated += o.terminated;
        delta += o.delta, unsampled += o.unsampled, bad_value += o.bad_value;
        f_mismatch += o.f_mismatch, pdf_mismatch += o.pdf_mismatch, direct += o.direct;
        hero_mismatch += o.hero_mismatch;
        worst_f = std::max(worst_f, o.worst_f), worst_pdf = std::max(worst_pdf, o.worst_pdf);
        if (first.empty()) first = o.first;
    }
};

/// |a / b - 1|, 0 where both are 0, infinite where only b is (NaN stays NaN).
double relative_miss(double a, double b) {
    if (a == b) return 0.0;
    return std::abs(a / b - 1.0);
}

struct Draw {
    const WarpInput* in;
    WarpOutput wi;
    std::span<const float> f, pdf;
    BsdfFlags flags;
};

void note(Tally& t, uint64_t& count, const Draw& d, int channel, const char* what, double got, double want) {
    ++count;
    if (t.first.empty())
        t.first = fmt::format("{} in channel {} at u = ({:.9g}, {:.9g}, {:.9g}), wi ({:.9g}, {:.9g}, {:.9g}): {:.9g}, "
                              "f() and pdf() say {:.9g}",
                              what, channel, d.in->u[0], d.in->u[1], d.in->u[2], d.wi[0], d.wi[1], d.wi[2], got, want);
}

/// Whether the case's hero record (sample_bsdf, what the other checks test:
/// a sample_hero where the object has one) is, bit for bit, the spectral
/// sample's hero channel (NaN equal to NaN).
bool same_hero(const BsdfRecord& r, const Draw& d, int hero) {
    const auto h = static_cast<std::size_t>(hero);
    const auto same = [](float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); };
    return same(r.wi[0], d.wi[0]) && same(r.wi[1], d.wi[1]) && same(r.wi[2], d.wi[2]) && same(r.f, d.f[h]) &&
           same(r.pdf, d.pdf[h]) && r.flags == d.flags;
}

/// How far a secondary value misses: its ratio to the hero against f()'s
/// ratio, or (no ratio: a hero or f() value of 0) itself against f().
double miss(double value, double hero, double want, double want_hero, uint64_t& direct) {
    if (hero > 0.0 && want_hero > 0.0) return relative_miss(value / hero, want / want_hero);
    ++direct;
    return relative_miss(value, want);
}

/// One draw's rules; fv and pv hold f() and pdf() of every channel at its wi.
void compare_draw(const SpectralChannels& s, const Draw& d, std::span<float> fv, std::span<float> pv, Tally& t) {
    const int n = s.channels(), h = s.hero();
    const auto hu = static_cast<std::size_t>(h);
    for (int c = 0; c < n; ++c) {
        const float f = d.f[static_cast<std::size_t>(c)], p = d.pdf[static_cast<std::size_t>(c)];
        if (!(f >= 0.0f && std::isfinite(f) && p >= 0.0f && std::isfinite(p)))
            note(t, t.bad_value, d, c, "f or pdf not finite and not negative", f, NAN);
    }
    if (!(d.pdf[hu] > 0.0f)) return void(++t.unsampled);
    if (has(d.flags, BsdfFlags::Delta)) return void(++t.delta);
    s.values_all(d.wi, fv, pv);
    ++t.compared;
    for (int c = 0; c < n; ++c) {
        if (c == h) continue;
        const auto cu = static_cast<std::size_t>(c);
        if (d.pdf[cu] == 0.0f) {
            ++t.terminated;
            continue;
        }
        const double mf = miss(d.f[cu], d.f[hu], fv[cu], fv[hu], t.direct);
        t.worst_f = std::max(t.worst_f, std::isnan(mf) ? HUGE_VAL : mf);
        if (!(mf <= kTolerance)) note(t, t.f_mismatch, d, c, "a secondary channel's f", d.f[cu], fv[cu]);
        const double mp = miss(d.pdf[cu], d.pdf[hu], pv[cu], pv[hu], t.direct);
        t.worst_pdf = std::max(t.worst_pdf, std::isnan(mp) ? HUGE_VAL : mp);
        if (!(mp <= kTolerance)) note(t, t.pdf_mismatch, d, c, "a secondary channel's pdf", d.pdf[cu], pv[cu]);
    }
}

Tally tally(const BsdfCase& bsdf, const SpectralChannels& s, const CheckContext& ctx) {
    const auto n = static_cast<std::size_t>(s.channels());
    const auto parts = map_input_chunks<Tally>(
        ctx, InputKind::Uniform3D, ctx.options().samples, true, [&](std::size_t, std::span<const WarpInput> in) {
            std::vector<WarpOutput> wi(in.size());
            std::vector<float> f(in.size() * n), pdf(in.size() * n);
            std::vector<BsdfFlags> flags(in.size());
            s.sample_all(in, wi, f, pdf, flags);
            std::vector<BsdfRecord> hero(in.size());  // what every other check of the case sees
            bsdf.sample_bsdf(in, hero);
            std::vector<float> fv(n), pv(n);  // f() and pdf() at one wi, reused across the chunk
            Tally t;
            for (std::size_t k = 0; k < in.size(); ++k) {
                ++t.draws;
                const Draw d{&in[k], wi[k], std::span<const float>(f).subspan(k * n, n),
                             std::span<const float>(pdf).subspan(k * n, n), flags[k]};
                if (!same_hero(hero[k], d, s.hero()))
                    note(t, t.hero_mismatch, d, s.hero(), "the hero's sample differs from the spectral sample's hero",
                         hero[k].f, d.f[static_cast<std::size_t>(s.hero())]);
                compare_draw(s, d, fv, pv, t);
            }
            return t;
        });
    return merge_in_order(parts);
}

void judge(CheckResult& r, const Tally& t, int channels, int hero) {
    const uint64_t wrong = t.bad_value + t.f_mismatch + t.pdf_mismatch + t.hero_mismatch;
    r.message = fmt::format("{} channels, hero {}: {} draws compared ({} without a sample, {} delta); secondary "
                            "channels' f in the hero's proportion within {:.3g} at worst, pdf within {:.3g} ({} "
                            "terminated, {} values compared without a ratio: the hero's or f()'s 0)",
                            channels, hero, t.compared, t.unsampled, t.delta, t.worst_f, t.worst_pdf, t.terminated,
                            t.direct);
    r.verdict = Verdict::Pass;
    r.summary = fmt::format("secondary channels agree with f() and pdf() ({} compared, {} terminated)", t.compared,
                            t.terminated);
    if (wrong > 0) {
        r.verdict = Verdict::Fail;
        r.summary = fmt::format("{} secondary values disagree with f() or pdf(): {}", wrong, t.first);
        r.message = fmt::format("{} not finite or negative, {} f and {} pdf beyond 2^-12, {} hero samples unlike the "
                                "spectral sample's; first: {}. ",
                                t.bad_value, t.f_mismatch, t.pdf_mismatch, t.hero_mismatch, t.first) +
                    r.message;
    }
}

class BsdfSpectralCheck final : public BsdfCheck {
public:
    std::string name() const override { return "bsdf_spectral"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"bad_values", "channel values not finite or negative", FigureRule::Zero},
                 {"f_mismatches", "secondary channels' f beyond the tolerance", FigureRule::Zero},
                 {"pdf_mismatches", "secondary channels' pdf beyond the tolerance", FigureRule::Zero},
                 {"hero_mismatches", "hero samples unlike the spectral sample's hero channel", FigureRule::Zero},
                 {"max_f_relative_difference", "largest relative difference of a secondary f", FigureRule::Counted},
                 {"terminated", "secondary channels terminated (pdf 0)", FigureRule::Counted},
                 {"compared_without_ratio", "secondary values compared without a ratio (a hero value of 0)", FigureRule::Counted}}};
    }
    CheckLegend legend() const override {
        return {name(), "A spectral BSDF's channel case: at every sample, each secondary channel's f and pdf against "
                "f() and pdf() at its wi (a pdf of 0: terminated), each in the hero's proportion that f() and pdf() "
                "give there, within 2^-12 relative.",
                ""};
    }
    std::string description() const override {
        return "spectral BSDF: each sample's secondary channels' f and pdf against f() and pdf() there (0: "
               "terminated)";
    }

protected:
    Applicability bsdf_applicability(const BsdfCase& b) const override {
        const SpectralChannels* s = as_spectral(b);
        return Applicability::when(s != nullptr && s->channels() > 1);
    }

    CheckResult run_bsdf(const BsdfCase& bsdf, const CheckContext& ctx) const override {
        const SpectralChannels& s = *as_spectral(bsdf);
        const Tally t = tally(bsdf, s, ctx);
        CheckResult r;
        r.samples = t.draws;
        r.figures = {{"samples", static_cast<double>(t.draws)},
                     {"channels", static_cast<double>(s.channels())},
                     {"hero", static_cast<double>(s.hero())},
                     {"compared", static_cast<double>(t.compared)},
                     {"terminated", static_cast<double>(t.terminated)},
                     {"delta_samples", static_cast<double>(t.delta)},
                     {"bad_values", static_cast<double>(t.bad_value)},
                     {"f_mismatches", static_cast<double>(t.f_mismatch)},
                     {"pdf_mismatches", static_cast<double>(t.pdf_mismatch)},
                     {"max_f_relative_difference", t.worst_f},
                     {"max_pdf_relative_difference", t.worst_pdf},
                     {"compared_without_ratio", static_cast<double>(t.direct)},
                     {"hero_mismatches", static_cast<double>(t.hero_mismatch)},
                     {"tolerance", kTolerance}};
        judge(r, t, s.channels(), s.hero());
        return r;
    }
};

}  // namespace spectral_detail

std::unique_ptr<Check> make_bsdf_spectral_check() { return std::make_unique<spectral_detail::BsdfSpectralCheck>(); }

}  // namespace warpcheck::bsdf
