// Known-bad BSDFs: the bugs renderers ship, each a built-in of
// sampling/bsdf_*.h with one thing wrong, marked as a known flaw (they run
// with --include-flawed or when named) and each caught by the check named in
// bsdf_flawed_catalogue(); tests/validate/checks/bsdf/test_bsdf.cpp holds each to that
// check and to passing the checks its bug does not touch.
#include <algorithm>
#include <cmath>
#include <utility>

#include "sampling/bsdf_conductor.h"
#include "sampling/bsdf_dielectric.h"
#include "sampling/bsdf_diffuse.h"
#include "sampling/bsdf_layered.h"
#include "sampling/bsdf_plastic.h"
#include "sampling/bsdf_spectral.h"
#include "validate/api/bsdf_case.h"
#include "validate/api/registry.h"
#include "validate/cases/bsdf_flawed.h"

namespace warpcheck {
namespace {

constexpr float kFlawedGoldEta = 0.2f, kFlawedGoldK = 3.0f, kFlawedGlass = 1.5f;

WarpCaseInfo flawed_info(std::string family, std::vector<Parameter> params, std::string description) {
    return {.family = std::move(family), .params = std::move(params), .description = std::move(description)};
}

/// Weight missing the cosine: the sample's f is f / |cos theta_i|, so that
/// the weight f |cos| / pdf is what a renderer that forgot the cosine gets.
std::unique_ptr<WarpCase> weight_without_cosine() {
    const RoughConductor c(TrowbridgeReitz(0.3f), kFlawedGoldEta, kFlawedGoldK);
    return make_bsdf_case(
        flawed_info("rough_conductor_weight_no_cos", {{"alpha", 0.3}, {"theta_o", 60}},
                    "rough conductor whose sampled weight misses |cos theta_i|"),
        {.wo = bsdf_direction(60), .lobes = c.flags()},
        bsdf_of([c](Vector3f wo, float uc, Point2f u) {
                    BsdfSample s = c.sample(wo, uc, u);
                    if (s.pdf > 0.0f) s.f /= std::abs(s.wi.z);
                    return s;
                })
            .with_f([c](Vector3f wo, Vector3f wi) { return c.f(wo, wi); })
            .with_pdf([c](Vector3f wo, Vector3f wi) { return c.pdf(wo, wi); }));
}

/// Refraction by 1 / eta instead of eta (the sample still reports eta).
std::unique_ptr<WarpCase> eta_swapped() {
    const SmoothDielectric d(kFlawedGlass);
    return make_bsdf_case(
        flawed_info("smooth_dielectric_eta_swapped", {{"eta", 1.5}, {"theta_o", 30}},
                    "smooth dielectric refracting with 1 / eta in place of eta"),
        {.wo = bsdf_direction(30), .lobes = d.flags(), .eta = kFlawedGlass},
        bsdf_of([d](Vector3f wo, float uc, Point2f u) {
            BsdfSample s = d.sample(wo, uc, u);
            float etap = 1.0f;
            Vector3f wt;
            if (has(s.flags, BsdfFlags::Transmission) && refract(wo, {0.0f, 0.0f, 1.0f}, 1.0f / kFlawedGlass, etap, wt))
                s.wi = wt;
            return s;
        })
            .with_f([d](Vector3f wo, Vector3f wi) { return d.f(wo, wi); })
            .with_pdf([d](Vector3f wo, Vector3f wi) { return d.pdf(wo, wi); }));
}

/// Transmissions from inside the glass report the material's eta where the
/// relative eta(wi) / eta(wo) = 1 / eta is meant (a renderer then scales the
/// path by eta^2 where it means 1 / eta^2); direction, f, pdf and the weight
/// are right.
std::unique_ptr<WarpCase> eta_not_relative_from_inside() {
    const RoughDielectric d(TrowbridgeReitz(0.1f), kFlawedGlass);
    return make_bsdf_case(
        flawed_info("rough_dielectric_eta_not_relative", {{"alpha", 0.1}, {"eta", 1.5}, {"theta_o", 150}},
                    "rough dielectric whose transmissions from inside report eta, not eta(wi) / eta(wo)"),
        {.wo = bsdf_direction(150), .lobes = d.flags(), .eta = kFlawedGlass},
        bsdf_of([d](Vector3f wo, float uc, Point2f u) {
            BsdfSample s = d.sample(wo, uc, u);
            if (has(s.flags, BsdfFlags::Transmission)) s.eta = kFlawedGlass;
            return s;
        })
            .with_f([d](Vector3f wo, Vector3f wi) { return d.f(wo, wi); })
            .with_pdf([d](Vector3f wo, Vector3f wi) { return d.pdf(wo, wi); }));
}

/// A diffuse + glossy mixture whose pdf() gives each lobe the other's
/// probability: (Ps cos / pi + (1 - Ps) pdf_spec); the sampler's choice is right.
std::unique_ptr<WarpCase> mixture_wrong_lobe_pdf() {
    const Plastic p(0.8f, kFlawedGlass, 0.2f);
    const TrowbridgeReitz tr(0.2f);
    auto pdf = [p, tr](Vector3f wo, Vector3f wi) {
        if (!same_hemisphere(wo, wi)) return 0.0f;
        const float ps = p.specular_probability(wo);
        float value = ps * std::abs(wi.z) * kInvPi;
        const Vector3f up_o{wo.x, wo.y, std::abs(wo.z)}, h = up_o + Vector3f{wi.x, wi.y, std::abs(wi.z)};
        if (dot(h, h) > 0.0f) {
            const Vector3f wm = normalize(h);
            const float cos_om = dot(up_o, wm);
            if (cos_om > 0.0f) value += (1.0f - ps) * visible_normal_pdf(tr, up_o, wm) / (4.0f * cos_om);
        }
        return value;
    };
    return make_bsdf_case(
        flawed_info("plastic_wrong_lobe_pdf", {{"alpha", 0.2}, {"theta_o", 60}},
                    "diffuse + glossy mixture whose pdf weights each lobe by the other's probability"),
        {.wo = bsdf_direction(60), .lobes = p.flags()},
        bsdf_of([p, pdf](Vector3f wo, float uc, Point2f u) {
                    BsdfSample s = p.sample(wo, uc, u);
                    if (s.pdf > 0.0f) s.pdf = pdf(wo, s.wi);
                    return s;
                })
            .with_f([p](Vector3f wo, Vector3f wi) { return p.f(wo, wi); })
            .with_pdf(pdf));
}

/// The delta reflection chosen with probability F but claiming 1 - F (and
/// refraction the reverse), its value scaled to keep the weight.
std::unique_ptr<WarpCase> lobe_probability_swapped() {
    const SmoothDielectric d(kFlawedGlass);
    return make_bsdf_case(
        flawed_info("smooth_dielectric_lobe_swapped", {{"eta", 1.5}, {"theta_o", 60}},
                    "smooth dielectric choosing reflection with probability F but weighting it as if 1 - F"),
        {.wo = bsdf_direction(60), .lobes = d.flags(), .eta = kFlawedGlass},
        bsdf_of([d](Vector3f wo, float uc, Point2f u) {
                    BsdfSample s = d.sample(wo, uc, u);
                    if (s.pdf > 0.0f) {
                        const float claimed = 1.0f - s.pdf;
                        s.f *= claimed / s.pdf;
                        s.pdf = claimed;
                    }
                    return s;
                })
            .with_f([d](Vector3f wo, Vector3f wi) { return d.f(wo, wi); })
            .with_pdf([d](Vector3f wo, Vector3f wi) { return d.pdf(wo, wi); }));
}

/// A Lambertian-like f that is brighter towards the normal on the wi side
/// only: f = R / pi (0.7 + 0.6 |cos theta_i|), sampled and evaluated alike.
std::unique_ptr<WarpCase> not_reciprocal() {
    auto f = [](Vector3f wo, Vector3f wi) {
        return same_hemisphere(wo, wi) ? 0.5f * kInvPi * (0.7f + 0.6f * std::abs(wi.z)) : 0.0f;
    };
    const Lambertian l(0.5f);
    return make_bsdf_case(
        flawed_info("lambertian_not_reciprocal", {{"R", 0.5}, {"theta_o", 60}},
                    "diffuse f = R / pi (0.7 + 0.6 |cos theta_i|): not symmetric in wo and wi"),
        {.wo = bsdf_direction(60), .lobes = l.flags()},
        bsdf_of([l, f](Vector3f wo, float uc, Point2f u) {
                    BsdfSample s = l.sample(wo, uc, u);
                    if (s.pdf > 0.0f) s.f = f(wo, s.wi);
                    return s;
                })
            .with_f(f)
            .with_pdf([l](Vector3f wo, Vector3f wi) { return l.pdf(wo, wi); }));
}

/// A white Lambertian 2% brighter where wo or wi is within 10 degrees of the
/// horizon: reciprocal, sampled and evaluated alike, with albedo 1.02 at
/// grazing wo.
std::unique_ptr<WarpCase> energy_gain_at_grazing() {
    auto f = [](Vector3f wo, Vector3f wi) {
        if (!same_hemisphere(wo, wi)) return 0.0f;
        const float grazing = 0.17364818f;  // cos 80 degrees
        return (std::min(std::abs(wo.z), std::abs(wi.z)) < grazing ? 1.02f : 1.0f) * kInvPi;
    };
    const Lambertian l(1.0f);
    return make_bsdf_case(
        flawed_info("lambertian_energy_gain", {{"R", 1}, {"theta_o", 85}},
                    "white diffuse 2% brighter within 10 degrees of the horizon: albedo 1.02 at grazing"),
        {.wo = bsdf_direction(85), .lobes = l.flags()},
        bsdf_of([l, f](Vector3f wo, float uc, Point2f u) {
                    BsdfSample s = l.sample(wo, uc, u);
                    if (s.pdf > 0.0f) s.f = f(wo, s.wi);
                    return s;
                })
            .with_f(f)
            .with_pdf([l](Vector3f wo, Vector3f wi) { return l.pdf(wo, wi); }));
}

/// Visible normals sampled as seen from wo mirrored about the normal
/// (-wo.x, -wo.y, wo.z); f and pdf evaluated right at the wi it returns.
std::unique_ptr<WarpCase> visible_normals_wrong_side() {
    const TrowbridgeReitz tr(0.3f);
    const RoughConductor c(tr, kFlawedGoldEta, kFlawedGoldK);
    return make_bsdf_case(
        flawed_info("rough_conductor_vndf_wrong_side", {{"alpha", 0.3}, {"theta_o", 60}},
                    "rough conductor sampling the normals visible from the mirror of wo"),
        {.wo = bsdf_direction(60), .lobes = c.flags()},
        bsdf_of([c, tr](Vector3f wo, float, Point2f u) -> BsdfSample {
                    const Vector3f wm = tr.visible_normals({-wo.x, -wo.y, wo.z}).sample(u);
                    if (!has_side(wm)) return {};
                    const Vector3f wi = reflect(wo, wm);
                    const float pdf = c.pdf(wo, wi);
                    if (!(wi.z > 0.0f) || !(pdf > 0.0f)) return {};
                    return {wi, c.f(wo, wi), pdf, c.flags()};
                })
            .with_f([c](Vector3f wo, Vector3f wi) { return c.f(wo, wi); })
            .with_pdf([c](Vector3f wo, Vector3f wi) { return c.pdf(wo, wi); }));
}

/// A sharp conductor seen at 85 degrees whose visible normals are sampled
/// with alpha 1% too large (a roughness remapped twice, or the sampler fed
/// the unclamped value), each sample reporting f() and pdf() at its wi: the
/// weights agree and the lobe lands almost where it should.
std::unique_ptr<WarpCase> roughness_one_percent_off() {
    return sampled_by(flawed_info("rough_conductor_alpha_1pct_wide", {{"alpha", 0.05}, {"theta_o", 85}},
                                  "rough conductor sampling its visible normals with alpha 0.0505 instead of 0.05"),
                      bsdf_direction(85), RoughConductor(TrowbridgeReitz(0.05f), kFlawedGoldEta, kFlawedGoldK),
                      RoughConductor(TrowbridgeReitz(0.0505f), kFlawedGoldEta, kFlawedGoldK));
}

/// A coated BSDF (stochastic) with one term of its walk wrong.
template <typename Base>
std::unique_ptr<WarpCase> coated_flawed(std::string family, std::vector<Parameter> params, double theta_o, Base base,
                                        CoatFlaw flaw, std::string description) {
    return make_bsdf_case(flawed_info(std::move(family), std::move(params), std::move(description)),
                          {.wo = bsdf_direction(theta_o), .stochastic = true},
                          CoatedBsdf(std::move(base), kFlawedGlass, 0, flaw));
}

std::unique_ptr<WarpCase> coated_diffuse_schlick() {
    return coated_flawed("coated_diffuse_schlick_in_f", {{"R", 0.8}, {"theta_o", 60}}, 60, Lambertian(0.8f),
                         CoatFlaw::SchlickInF,
                         "coated diffuse whose f takes the coat's transmittance from Schlick's approximation, its "
                         "sampler from the exact Fresnel term");
}

std::unique_ptr<WarpCase> coated_diffuse_albedo() {
    return coated_flawed("coated_diffuse_albedo_in_sample", {{"R", 0.8}, {"theta_o", 30}}, 30, Lambertian(0.8f),
                         CoatFlaw::AlbedoInSample, "coated diffuse whose sampler scales the base's albedo by 1.02");
}

std::unique_ptr<WarpCase> coated_conductor_jacobian() {
    return coated_flawed("coated_conductor_jacobian_in_f", {{"alpha", 0.3}, {"theta_o", 30}}, 30,
                         RoughConductor(TrowbridgeReitz(0.3f), kFlawedGoldEta, kFlawedGoldK), CoatFlaw::JacobianInF,
                         "coated conductor whose f drops the 1 / eta^2 of the paths that bounce inside the coat");
}

std::unique_ptr<WarpCase> coated_diffuse_schlick_at_entry() {
    return coated_flawed("coated_diffuse_schlick_at_entry", {{"R", 0.8}, {"theta_o", 80}}, 80, Lambertian(0.8f),
                         CoatFlaw::SchlickAtEntry,
                         "coated diffuse whose coat transmittance is Schlick's where light enters and exact where it "
                         "leaves, in f and sampler alike: not reciprocal");
}

/// A spectral BSDF's channel case at theta_o 30 with one thing wrong.
template <typename B>
std::unique_ptr<WarpCase> spectral_flawed(std::string family, int hero, B bsdf, std::string description) {
    return make_spectral_bsdf_case(
        flawed_info(std::move(family), {{"alpha", 0.3}, {"theta_o", 30}, {"hero", static_cast<double>(hero)}}, std::move(description)),
        {.wo = bsdf_direction(30)}, std::move(bsdf), hero);
}

RgbConductor green_high_conductor() {
    return RgbConductor(TrowbridgeReitz(0.3f), kGoldRgbEta, kGoldRgbK, SpectralFlaw::GreenWeightHigh);
}

std::unique_ptr<WarpCase> rgb_green_high_seen_from_red() {
    return spectral_flawed("rgb_conductor_green_weight_high", 0, green_high_conductor(),
                           "RGB conductor whose sampled green value is 0.5% high (red the hero)");
}

std::unique_ptr<WarpCase> rgb_green_high_seen_from_green() {
    return spectral_flawed("rgb_conductor_green_weight_high", 1, green_high_conductor(),
                           "RGB conductor whose sampled green value is 0.5% high (green the hero)");
}

DispersiveDielectric<3> dispersive_glass(SpectralFlaw flaw) {
    return DispersiveDielectric<3>(TrowbridgeReitz(0.3f), {1.495f, 1.5f, 1.506f}, flaw);
}

std::unique_ptr<WarpCase> dispersion_not_terminated() {
    return spectral_flawed("dispersive_dielectric_not_terminated", 0,
                           dispersive_glass(SpectralFlaw::SecondaryNotTerminated),
                           "dispersive glass whose transmissions give the secondary wavelengths the hero's pdf");
}

std::unique_ptr<WarpCase> dispersion_with_hero_eta() {
    return spectral_flawed("dispersive_dielectric_hero_eta", 0, dispersive_glass(SpectralFlaw::SecondaryWithHeroEta),
                           "dispersive glass whose secondary wavelengths' f is evaluated with the hero's eta");
}

}  // namespace

std::vector<FlawedBsdf> bsdf_flawed_catalogue() {
    return {
        // The mean weight is then the albedo of f / |cos|, not of f.
        {weight_without_cosine, "bsdf_weight", "the sampled weight misses |cos theta_i|", {"bsdf_albedo"}},
        // The weights are right for the direction it claims, so the albedo holds.
        {eta_swapped, "bsdf_delta", "refracts with 1 / eta in place of eta"},
        // Only the reported eta is wrong: every other check sees a correct BSDF.
        {eta_not_relative_from_inside, "bsdf_weight", "continuous transmissions from inside report eta, not 1 / eta"},
        // Weights f |cos| / pdf with the wrong pdf: the mean weight is off too,
        // and the samples' marginals are not pdf()'s.
        {mixture_wrong_lobe_pdf, "bsdf_chi2", "pdf() gives each lobe of the mixture the other's probability",
         {"bsdf_albedo", "bsdf_unbinned"}},
        // Each lobe's weight is scaled by its claimed over its true probability.
        {lobe_probability_swapped, "bsdf_delta", "chooses reflection with probability F, claims 1 - F",
         {"bsdf_albedo"}},
        {not_reciprocal, "bsdf_reciprocity", "f(wo, wi) != f(wi, wo)"},
        {energy_gain_at_grazing, "bsdf_albedo", "albedo 1.02 at grazing: creates energy"},
        // Weights against the right pdf of the wrong distribution: the mean is
        // off, and so are the marginals.
        {visible_normals_wrong_side, "bsdf_chi2", "visible normals sampled from the wrong side of wo",
         {"bsdf_albedo", "bsdf_unbinned"}},
        // Every sample a little off: bsdf_chi2's cells average it away (p 0.09).
        {roughness_one_percent_off, "bsdf_unbinned", "visible normals sampled with alpha 1% too large"},
        // Layered (stochastic): each wrong in expectation only.
        {coated_diffuse_schlick, "bsdf_expectation", "f's coat transmittance by Schlick, the sampler's exact"},
        {coated_diffuse_albedo, "bsdf_expectation", "the sampler scales the base's albedo by 1.02"},
        {coated_conductor_jacobian, "bsdf_expectation", "f drops 1 / eta^2 on the paths inside the coat"},
        // Right in expectation for the weights, wrong only by reciprocity.
        {coated_diffuse_schlick_at_entry, "bsdf_expectation",
         "the coat's transmittance by Schlick where light enters, exact where it leaves: not reciprocal"},
        // Spectral: a channel's value wrong as a secondary (only bsdf_spectral
        // sees it) and as the hero (its weight, its albedo, and every
        // secondary's allowance widened at every draw).
        {rgb_green_high_seen_from_red, "bsdf_spectral", "green's sampled value 0.5% high, red the hero"},
        {rgb_green_high_seen_from_green, "bsdf_weight", "green's sampled value 0.5% high, green the hero",
         {"bsdf_albedo", "bsdf_spectral"}},
        {dispersion_not_terminated, "bsdf_spectral", "a dispersive refraction keeps its secondary wavelengths"},
        {dispersion_with_hero_eta, "bsdf_spectral", "secondary wavelengths' f with the hero's eta"},
    };
}

void register_flawed_bsdf_cases(Registry& registry) {
    for (const FlawedBsdf& flawed : bsdf_flawed_catalogue()) {
        std::unique_ptr<WarpCase> bsdf = flawed.make();
        const std::string name = bsdf->name();
        registry.add_case(std::move(bsdf));
        registry.mark_known_flaw(name, flawed.flaw + " (caught by " + flawed.caught_by + ")");
    }
}

}  // namespace warpcheck
