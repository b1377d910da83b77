// "light_support": pdf(ref, w) > 0 exactly where the light's own intersection
// finds light, L(ref, w) > 0. A lit direction of pdf 0 is one the sampler
// never draws: its light is missing from every estimate (a sphere light
// sampled over a cone narrower than the sphere, an environment map shifted by
// half a texel). A dark direction of pdf > 0 is mass the pdf claims where
// there is no light: the pdf MIS uses disagrees with the geometry. Not
// statistical; the probes are deterministic for a seed.
//
// Where it looks: kSphereProbes directions spread over the whole sphere, and
// kCapProbes in the cap around where the sampler puts its mass (the pilot's
// mean direction, out to twice the pilot's widest angle from it), so a small
// light is probed across and around it. A lit region smaller than 1/2^16 of
// the sphere and beyond that cap can go unseen; the row's figures say where
// it looked.
//
// Float rounding: the pdf's test (a cosine against a cone's, an intersection
// in float) and the light's intersection may disagree within a float step of
// the silhouette. A disagreement is excused where a neighbour of the probe
// (kFloatNeighbours of them, `step` away) is on the other side of the
// boundary, and the excused probes are bounded by the share a band that wide
// around the light can hold, so a sampler off by more than the band fails.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "validate/api/light_case.h"
#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/float_probe.h"
#include "validate/checks/shared/formatting.h"
#include "validate/checks/shared/input_chunks.h"
#include "validate/checks/light/light_checks.h"
#include "validate/checks/light/light_pilot.h"

namespace warpcheck::light {
namespace {

constexpr std::size_t kSphereProbes = std::size_t{1} << 16;
constexpr std::size_t kCapProbes = std::size_t{1} << 16;
constexpr std::size_t kPilotSamples = 4096;
/// The probes' own streams: past the pilot's (kPilotChunkBase) and any check's.
constexpr uint64_t kProbeChunk = kPilotChunkBase + (uint64_t{1} << 32);
/// Excused probes allowed beyond twice the band's expected count: the band's
/// count is Poisson, and P(Poisson(4) > 16) < 1e-5.
constexpr double kExcusedFloor = 16.0;

struct Cap {
    WarpOutput axis{0.0f, 0.0f, 1.0f};
    double angle = std::numbers::pi;  ///< half-angle
    bool sampled = false;             ///< whether the pilot drew any sample (else the whole sphere)
    std::size_t lit_samples = 0;      ///< the pilot's samples along which the light's own L(ref, w) > 0
};

/// The cap around the pilot's mass: its mean direction, out to twice its widest angle.
Cap pilot_cap(const LightCase& light, const CheckContext& ctx) {
    double m[3] = {0.0, 0.0, 0.0};
    std::vector<WarpOutput> w;
    for (const LightRecord& r : light_pilot(light, ctx, kPilotSamples)) {
        w.push_back(r.wi);
        for (int k = 0; k < 3; ++k) m[k] += r.wi[k];
    }
    const double len = std::hypot(m[0], m[1], m[2]);
    if (w.empty() || !(len > 0.0)) return {};
    Cap cap;
    cap.sampled = true;
    cap.axis = {static_cast<float>(m[0] / len), static_cast<float>(m[1] / len), static_cast<float>(m[2] / len)};
    double widest = 0.0;
    for (const WarpOutput& x : w) {
        const double c = (x[0] * m[0] + x[1] * m[1] + x[2] * m[2]) / len;
        widest = std::max(widest, std::acos(std::clamp(c, -1.0, 1.0)));
    }
    cap.angle = std::min(std::numbers::pi, 2.0 * widest + 0x1p-20);
    std::vector<double> L(w.size());
    light.radiance(w, L);
    cap.lit_samples = static_cast<std::size_t>(std::count_if(L.begin(), L.end(), [](double v) { return v > 0.0; }));
    return cap;
}

/// A unit direction uniform in the cap, from two uniforms (cosine uniform in [cos angle, 1]).
WarpOutput in_cap(const Cap& cap, double u0, double u1) {
    const double one_minus_cos = u0 * (1.0 - std::cos(cap.angle));
    const double cos_t = 1.0 - one_minus_cos, sin_t = std::sqrt(std::max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
    const double phi = 2.0 * std::numbers::pi * u1;
    const double a[3] = {cap.axis[0], cap.axis[1], cap.axis[2]};
    // An orthonormal frame around the axis (Duff et al. 2017).
    const double sign = std::copysign(1.0, a[2]), p = -1.0 / (sign + a[2]), q = a[0] * a[1] * p;
    const double t[3] = {1.0 + sign * a[0] * a[0] * p, sign * q, -sign * a[0]};
    const double b[3] = {q, sign + a[1] * a[1] * p, -a[1]};
    WarpOutput out;
    for (int k = 0; k < 3; ++k)
        out[k] = static_cast<float>(sin_t * (std::cos(phi) * t[k] + std::sin(phi) * b[k]) + cos_t * a[k]);
    return out;
}

struct ProbeExample {
    WarpOutput w{};
    double L = 0.0, pdf = 0.0;
};

struct SupportStats {
    uint64_t probes = 0, lit = 0, excused = 0;
    Tally<ProbeExample> lit_without_pdf, pdf_without_light, invalid;
    void merge(const SupportStats& o) {
        probes += o.probes;
        lit += o.lit;
        excused += o.excused;
        lit_without_pdf.merge(o.lit_without_pdf);
        pdf_without_light.merge(o.pdf_without_light);
        invalid.merge(o.invalid);
    }
};

/// Whether a neighbour `step` away lies on the other side of the boundary the probe disagrees across.
bool at_boundary(const LightCase& light, const WarpOutput& w, bool lit, bool positive, double step) {
    const std::vector<WarpOutput> n = float_neighbours(w, step);
    std::vector<double> L(n.size()), pdf(n.size());
    light.radiance(n, L);
    light.pdf(n, pdf);
    for (std::size_t k = 0; k < n.size(); ++k)
        if ((L[k] > 0.0) != lit || (pdf[k] > 0.0) != positive) return true;
    return false;
}

SupportStats probe(const LightCase& light, const CheckContext& ctx, const Cap& cap, double step) {
    const std::size_t chunks = (kSphereProbes + kCapProbes) / kInputChunkSize;
    std::vector<SupportStats> parts(chunks);
    ctx.parallel_for(chunks, [&](std::size_t c) {
        ctx.throw_if_cancelled();
        Pcg32 rng = ctx.chunk_rng(kProbeChunk + c);
        const bool sphere = c < kSphereProbes / kInputChunkSize;
        std::vector<WarpOutput> w(kInputChunkSize);
        for (WarpOutput& x : w) {
            const double u0 = rng.next_double(), u1 = rng.next_double();
            x = in_cap(sphere ? Cap{} : cap, u0, u1);
        }
        std::vector<double> L(w.size()), pdf(w.size());
        light.radiance(w, L);
        light.pdf(w, pdf);
        SupportStats& s = parts[c];
        for (std::size_t i = 0; i < w.size(); ++i) {
            const uint64_t index = c * kInputChunkSize + i;
            ++s.probes;
            const ProbeExample e{w[i], L[i], pdf[i]};
            if (!std::isfinite(L[i]) || !std::isfinite(pdf[i]) || L[i] < 0.0 || pdf[i] < 0.0) {
                s.invalid.add(index, e);
                continue;
            }
            const bool lit = L[i] > 0.0, positive = pdf[i] > 0.0;
            if (lit) ++s.lit;
            if (lit == positive) continue;
            if (at_boundary(light, w[i], lit, positive, step)) ++s.excused;
            else if (lit) s.lit_without_pdf.add(index, e);
            else s.pdf_without_light.add(index, e);
        }
    });
    return merge_in_order(parts);
}

std::string describe_probe(const ProbeExample& e) {
    return fmt::format("w {}: L(ref, w) {:.6g}, pdf(ref, w) {:.6g}", format_output(e.w, 3), e.L, e.pdf);
}

/// Where no probe found light, the pilot's samples must have: else nothing lit was seen at all.
void found_light_line(const CheckResult& r, std::vector<JudgedQuantity>& out) {
    const auto lit = r.figure("lit_probes"), pilot = r.figure("lit_pilot_samples");
    if (!lit || !pilot) return;
    out.push_back({"probes that found light (or, with none, the pilot's samples that did)",
                   judged_number(*lit > 0.0 ? *lit : *pilot), "> 0",
                   *lit > 0.0 || *pilot > 0.0 ? JudgedQuantity::State::Within : JudgedQuantity::State::Beyond});
}

class LightSupportCheck final : public Check {
public:
    std::string name() const override { return "light_support"; }
    JudgedRules judged_rules() const override {
        return {.figures = {{"lit_without_pdf", "lit directions with pdf 0", FigureRule::Zero},
                            {"pdf_without_light", "directions that miss the light with pdf > 0", FigureRule::Zero},
                            {"invalid", "probes with a non-finite pdf or L", FigureRule::Zero},
                            {"excused_at_boundary", "probes that disagree within a float step of a boundary",
                             FigureRule::AtMost, "excused_limit"}},
                .bounds = found_light_line};
    }
    CheckLegend legend() const override {
        return {name(), "pdf(ref, w) > 0 exactly where the light's own L(ref, w) > 0, probed over the whole sphere "
                "and around where the sampler puts its mass: a lit direction of pdf 0 or a dark one of pdf > 0 "
                "fails; disagreements within a float step of the silhouette are excused and bounded by the share "
                "such a band holds.",
                ""};
    }
    std::string description() const override {
        return "light: pdf(ref, w) > 0 exactly where the light's own L(ref, w) > 0, probed over the sphere and "
               "around the sampled cap";
    }
    Applicability applicability(const WarpCase& warp) const override {
        return Applicability::when(as_light(warp) != nullptr);
    }
    CheckResult run(const WarpCase& warp, const CheckContext& ctx) const override {
        const LightCase& light = *as_light(warp);
        const Cap cap = pilot_cap(light, ctx);
        // A cosine near 1 has float steps of 2^-24: at the light's silhouette,
        // about half the cap's angle from its axis, four of them span
        // 2^-22 / sin(angle / 2) radians; directions themselves resolve to
        // 2^-20 (float_neighbours' step).
        const double radius = std::max(std::sin(0.5 * cap.angle), 0x1p-20);
        const double step = kFloatStep + 0x1p-22 / radius;
        const SupportStats s = probe(light, ctx, cap, step);
        // Twice the probes a band of half-width `step` along a boundary no
        // longer than the cap's inner circle (2 pi radius) holds: a convex
        // light inside the cap has no longer silhouette.
        const double band = 4.0 * std::numbers::pi * radius * step;
        const double cap_measure = 2.0 * std::numbers::pi * (1.0 - std::cos(cap.angle));
        const double expected = static_cast<double>(kCapProbes) * std::min(1.0, band / cap_measure) +
                                static_cast<double>(kSphereProbes) * std::min(1.0, band / (4.0 * std::numbers::pi));
        const double limit = 2.0 * expected + kExcusedFloor;
        CheckResult r;
        r.samples = s.probes;
        r.figures = {{"probes", static_cast<double>(s.probes)},
                     {"lit_probes", static_cast<double>(s.lit)},
                     {"cap_angle", cap.angle},
                     {"boundary_step", step},
                     {"lit_without_pdf", static_cast<double>(s.lit_without_pdf.count)},
                     {"pdf_without_light", static_cast<double>(s.pdf_without_light.count)},
                     {"invalid", static_cast<double>(s.invalid.count)},
                     {"excused_at_boundary", static_cast<double>(s.excused)},
                     {"excused_limit", limit},
                     {"lit_pilot_samples", static_cast<double>(cap.lit_samples)}};
        r.summary = fmt::format("{} lit of {} probes, cap {:.3g} rad", s.lit, s.probes, cap.angle);
        std::vector<std::string> failures;
        if (s.invalid.count > 0)
            failures.push_back(fmt::format("{} probes with a non-finite or negative L or pdf (first: {})",
                                           s.invalid.count, describe_probe(*s.invalid.first)));
        if (s.lit_without_pdf.count > 0)
            failures.push_back(fmt::format("{} lit directions have pdf 0: the sampler never draws them, so their "
                                           "light is missing from every estimate (first: {})",
                                           s.lit_without_pdf.count, describe_probe(*s.lit_without_pdf.first)));
        if (s.pdf_without_light.count > 0)
            failures.push_back(fmt::format("{} directions that miss the light have pdf > 0: the pdf claims mass "
                                           "where the light is not (first: {})",
                                           s.pdf_without_light.count, describe_probe(*s.pdf_without_light.first)));
        if (!(static_cast<double>(s.excused) <= limit))
            failures.push_back(fmt::format("{} probes disagree within {:.3g} rad of a boundary: more than the {:.0f} "
                                           "a band that wide around the light holds", s.excused, step, limit));
        if (s.lit == 0 && !cap.sampled && failures.empty()) {
            // Both sides agree that there is no light to see (a planar light
            // seen edge-on within float rounding): nothing was compared.
            r.verdict = Verdict::NotApplicable;
            r.summary = "not applicable: the light is not visible from ref";
            r.message = fmt::format("the sampler declined every pilot input and none of {} probes over the sphere "
                                    "found light: the light is not visible from ref, so no support was compared",
                                    s.probes);
            return r;
        }
        // No probe lit, but the light's own L finds light along the sampler's
        // directions: the lit region is thinner than the probes resolve (a
        // sliver of a far light seen nearly edge-on), so only half the rule
        // (no pdf where there is no light) was tested: said, not failed.
        if (s.lit == 0 && cap.lit_samples > 0)
            r.weak = fmt::format("no probe of {} landed on the light, whose lit region is too thin for them ({} of "
                                 "the pilot's samples find its light): lit directions of pdf 0 were not looked for",
                                 s.probes, cap.lit_samples);
        else if (s.lit == 0)
            failures.push_back("no probe found light: L(ref, w) is 0 over the sphere and around the samples");
        r.verdict = failures.empty() ? Verdict::Pass : Verdict::Fail;
        if (!failures.empty()) {
            r.summary = fmt::format("support differs at {} of {} probes",
                                    s.lit_without_pdf.count + s.pdf_without_light.count + s.invalid.count, s.probes);
            r.message = join_reasons(failures);
        } else if (s.excused > 0) {
            r.message = fmt::format("{} probes within {:.3g} rad of the light's silhouette excused (limit {:.0f})",
                                    s.excused, step, limit);
        }
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_light_support_check() { return std::make_unique<LightSupportCheck>(); }

}  // namespace warpcheck::light
