#include "validate/api/light_case.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <vector>

namespace warpcheck {
namespace {

WarpCaseInfo light_info(WarpCaseInfo info) {
    info.domain = chi2::Domain::sphere();
    return info;
}

/// What every light case is: u in, a direction on the sphere out, with its pdf.
constexpr WarpSignature light_signature(bool has_inverse) {
    return {.input = InputKind::Uniform2D,
            .returns = SampleReturns::PointAndPdf,
            .output_dimension = 3,
            .has_pdf = true,
            .has_inverse = has_inverse,
            .has_eval = false};
}

}  // namespace

LightCase::LightCase(WarpCaseInfo info, LightClaims claims, bool has_inverse)
    : WarpCase(light_info(std::move(info)), light_signature(has_inverse)), claims_(claims) {}

void LightCase::sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const {
    std::vector<LightRecord> records(in.size());
    sample_light(in, records);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t k = 0; k < in.size(); ++k) out[k] = records[k].sampled() ? records[k].wi : WarpOutput{nan, nan, nan};
}

void LightCase::sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                                  std::span<double> value) const {
    std::vector<LightRecord> records(in.size());
    sample_light(in, records);
    for (std::size_t k = 0; k < in.size(); ++k) {
        out[k] = records[k].wi;
        value[k] = static_cast<double>(records[k].pdf);
    }
}

}  // namespace warpcheck

namespace warpcheck {
namespace {

WarpCaseInfo mis_info(WarpCaseInfo info) {
    info.domain = chi2::Domain::sphere();
    return info;
}

/// The one-sample model: (uc, u) in, a direction on the sphere out, with the pdf.
constexpr WarpSignature kMisSignature{.input = InputKind::Uniform3D,
                                      .returns = SampleReturns::PointAndPdf,
                                      .output_dimension = 3,
                                      .has_pdf = true,
                                      .has_inverse = false,
                                      .has_eval = false};

Vector3f vector_of(const WarpOutput& w) { return {w[0], w[1], w[2]}; }

/// lit[i] += L(ref, wi[i]) of every light but the one at index `skip`.
void add_radiance(const std::vector<const LightCase*>& lights, std::size_t skip, std::span<const WarpOutput> wi,
                  std::span<double> lit) {
    std::vector<double> part(wi.size());
    for (std::size_t k = 0; k < lights.size(); ++k) {
        if (k == skip) continue;
        lights[k]->radiance(wi, part);
        for (std::size_t i = 0; i < wi.size(); ++i) lit[i] += part[i];
    }
}

/// f(wo, wi[i]) for each i.
std::vector<double> f_at(const BsdfCase& bsdf, std::span<const WarpOutput> wi) {
    const std::vector<WarpOutput> wo(wi.size(), WarpOutput{bsdf.wo().x, bsdf.wo().y, bsdf.wo().z});
    std::vector<double> f(wi.size());
    bsdf.f(wo, wi, f);
    return f;
}

const BsdfCase& bsdf_part(const std::unique_ptr<WarpCase>& c, const std::string& name) {
    const BsdfCase* b = c ? as_bsdf(*c) : nullptr;
    if (b == nullptr) throw std::invalid_argument("MIS case " + name + ": its first strategy must be a BSDF case");
    if (has(b->claims().lobes, BsdfFlags::Delta))
        throw std::invalid_argument("MIS case " + name + ": the BSDF " + b->name() +
                                    " has delta lobes, which a light's sample never hits (no MIS over them)");
    return *b;
}

}  // namespace

MisCase::MisCase(WarpCaseInfo info, MisClaims claims, std::unique_ptr<WarpCase> bsdf,
                 std::vector<std::unique_ptr<WarpCase>> lights)
    : WarpCase(mis_info(std::move(info)), kMisSignature), claims_(std::move(claims)), bsdf_owner_(std::move(bsdf)),
      light_owners_(std::move(lights)) {
    bsdf_ = &bsdf_part(bsdf_owner_, name());
    if (light_owners_.empty()) throw std::invalid_argument("MIS case " + name() + " needs at least one light");
    const Vector3f normal = bsdf_->phase_function() ? Vector3f{} : Vector3f{0.0f, 0.0f, 1.0f};
    for (const std::unique_ptr<WarpCase>& l : light_owners_) {
        const LightCase* light = l ? as_light(*l) : nullptr;
        if (light == nullptr) throw std::invalid_argument("MIS case " + name() + ": each light must be a light case");
        if (!(light->claims().normal == normal))
            throw std::invalid_argument("MIS case " + name() + ": the light " + light->name() +
                                        (normal == Vector3f{} ? " must have no normal (the phase function's point "
                                                                "lies in a medium)"
                                                              : " must be seen with the BSDF's normal (0, 0, 1)"));
        if (!lights_.empty() && !(light->ref() == lights_.front()->ref()))
            throw std::invalid_argument("MIS case " + name() + ": the lights are seen from different points");
        lights_.push_back(light);
    }
    const MisPdfs& pdfs = claims_.pdfs;
    if (pdfs.lights.size() > lights_.size() || pdfs.lights_batch.size() > lights_.size())
        throw std::invalid_argument("MIS case " + name() + ": more MIS pdfs than lights");
    const auto both = [](const auto& one, const auto& batch) { return static_cast<bool>(one) && static_cast<bool>(batch); };
    if (both(pdfs.bsdf, pdfs.bsdf_batch))
        throw std::invalid_argument("MIS case " + name() + ": the BSDF's MIS pdf is given in both forms (one or batch)");
    for (std::size_t k = 0; k < std::min(pdfs.lights.size(), pdfs.lights_batch.size()); ++k)
        if (both(pdfs.lights[k], pdfs.lights_batch[k]))
            throw std::invalid_argument("MIS case " + name() + ": light " + std::to_string(k + 1) +
                                        "'s MIS pdf is given in both forms (one or batch)");
}

std::string MisCase::strategy_name(std::size_t s) const {
    if (s == 0) return "bsdf " + bsdf_->name();
    return (lights_.size() == 1 ? std::string("light ") : "light " + std::to_string(s) + " ") + lights_[s - 1]->name();
}

void MisCase::sample_strategy(std::size_t s, std::span<const WarpInput> in, std::span<MisRecord> out) const {
    const std::size_t n = in.size();
    std::vector<WarpOutput> wi(n);
    std::vector<double> lit(n, 0.0);
    if (s == 0) {
        std::vector<BsdfRecord> rec(n);
        bsdf_->sample_bsdf(in, rec);
        for (std::size_t i = 0; i < n; ++i) wi[i] = rec[i].wi;
        add_radiance(lights_, lights_.size(), wi, lit);
        for (std::size_t i = 0; i < n; ++i)
            out[i] = {rec[i].wi, rec[i].pdf, static_cast<double>(rec[i].f) * lit[i] * bsdf_->cosine(rec[i].wi)};
        return;
    }
    std::vector<LightRecord> rec(n);
    lights_[s - 1]->sample_light(in, rec);
    for (std::size_t i = 0; i < n; ++i) wi[i] = rec[i].wi, lit[i] = static_cast<double>(rec[i].L);
    add_radiance(lights_, s - 1, wi, lit);
    const std::vector<double> f = f_at(*bsdf_, wi);
    for (std::size_t i = 0; i < n; ++i) out[i] = {rec[i].wi, rec[i].pdf, f[i] * lit[i] * bsdf_->cosine(rec[i].wi)};
}

void MisCase::strategy_pdf(std::size_t s, std::span<const WarpOutput> wi, std::span<double> out) const {
    if (s == 0) bsdf_->pdf(wi, out);
    else lights_[s - 1]->pdf(wi, out);
}

namespace {

/// Strategy s's batch MIS pdf (MisPdfs), or nullptr.
const MisPdfs::BatchPdf* batch_pdf(const MisPdfs& pdfs, std::size_t s) {
    const MisPdfs::BatchPdf* f = s == 0 ? &pdfs.bsdf_batch
                                        : (s - 1 < pdfs.lights_batch.size() ? &pdfs.lights_batch[s - 1] : nullptr);
    return f != nullptr && *f ? f : nullptr;
}

}  // namespace

bool MisCase::has_mis_pdf(std::size_t s) const {
    if (batch_pdf(claims_.pdfs, s) != nullptr) return true;
    if (s == 0) return static_cast<bool>(claims_.pdfs.bsdf);
    return s - 1 < claims_.pdfs.lights.size() && static_cast<bool>(claims_.pdfs.lights[s - 1]);
}

void MisCase::mis_pdf(std::size_t s, std::span<const WarpOutput> wi, std::span<double> out) const {
    if (!has_mis_pdf(s)) return strategy_pdf(s, wi, out);
    if (const MisPdfs::BatchPdf* batch = batch_pdf(claims_.pdfs, s)) {
        if (wi.empty()) return;
        return (*batch)(s == 0 ? bsdf_->wo() : lights_[s - 1]->ref(), wi, out.first(wi.size()));
    }
    if (s == 0) {
        const Vector3f wo = bsdf_->wo();
        for (std::size_t i = 0; i < wi.size(); ++i) out[i] = static_cast<double>(claims_.pdfs.bsdf(wo, vector_of(wi[i])));
        return;
    }
    const Vector3f ref = lights_[s - 1]->ref();
    const auto& pdf = claims_.pdfs.lights[s - 1];
    for (std::size_t i = 0; i < wi.size(); ++i) out[i] = static_cast<double>(pdf(ref, vector_of(wi[i])));
}

void MisCase::integrand(std::span<const WarpOutput> wi, std::span<double> out) const {
    std::vector<double> lit(wi.size(), 0.0);
    add_radiance(lights_, lights_.size(), wi, lit);
    const std::vector<double> f = f_at(*bsdf_, wi);
    for (std::size_t i = 0; i < wi.size(); ++i) out[i] = lit[i] == 0.0 ? 0.0 : f[i] * lit[i] * bsdf_->cosine(wi[i]);
}

double MisCase::weight(double own, std::span<const double> others) const {
    const auto h = [this](double p) { return claims_.heuristic == MisHeuristic::Power ? p * p : p; };
    double sum = h(own);
    for (double p : others) sum += h(p);
    return h(own) / sum;
}

std::size_t MisCase::choose(const WarpInput& in, WarpInput& passed) const {
    const std::size_t k = strategy_count();
    const float scaled = in.u[0] * static_cast<float>(k);
    const std::size_t s = std::min(k - 1, static_cast<std::size_t>(scaled));
    // The BSDF reuses u[0] rescaled to [0, 1), as a renderer reuses a light
    // selection's u; a light reads the two coordinates it did not choose by.
    if (s == 0) passed = WarpInput{{std::min(scaled, 0x1.fffffep-1f), in.u[1], in.u[2]}, 0};
    else passed = WarpInput{{in.u[1], in.u[2], 0.0f}, 0};
    return s;
}

void MisCase::sample_mixture(std::span<const WarpInput> in, std::span<MisRecord> out,
                             std::span<std::size_t> strategy) const {
    // Each strategy samples its share of the inputs in one batch.
    std::vector<std::vector<WarpInput>> passed(strategy_count());
    std::vector<std::vector<std::size_t>> where(strategy_count());
    for (std::size_t i = 0; i < in.size(); ++i) {
        WarpInput p;
        const std::size_t s = choose(in[i], p);
        strategy[i] = s;
        passed[s].push_back(p);
        where[s].push_back(i);
    }
    for (std::size_t s = 0; s < strategy_count(); ++s) {
        std::vector<MisRecord> rec(passed[s].size());
        sample_strategy(s, passed[s], rec);
        for (std::size_t j = 0; j < rec.size(); ++j) out[where[s][j]] = rec[j];
    }
}

void MisCase::sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const {
    std::vector<MisRecord> rec(in.size());
    std::vector<std::size_t> strategy(in.size());
    sample_mixture(in, rec, strategy);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t i = 0; i < in.size(); ++i) out[i] = rec[i].sampled() ? rec[i].wi : WarpOutput{nan, nan, nan};
}

void MisCase::sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                                std::span<double> value) const {
    std::vector<MisRecord> rec(in.size());
    std::vector<std::size_t> strategy(in.size());
    sample_mixture(in, rec, strategy);
    std::vector<WarpOutput> wi(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) wi[i] = out[i] = rec[i].wi;
    // The mixture's pdf as the sum forms it: the returned pdf of the strategy
    // that sampled, the MIS pdfs of the others.
    std::vector<double> sum(in.size(), 0.0), part(in.size());
    for (std::size_t t = 0; t < strategy_count(); ++t) {
        mis_pdf(t, wi, part);
        for (std::size_t i = 0; i < in.size(); ++i)
            if (strategy[i] != t) sum[i] += part[i];
    }
    const double k = static_cast<double>(strategy_count());
    for (std::size_t i = 0; i < in.size(); ++i)
        value[i] = rec[i].sampled() ? (static_cast<double>(rec[i].pdf) + sum[i]) / k : 0.0;
}

void MisCase::pdf(std::span<const WarpOutput> x, std::span<double> out) const {
    std::vector<double> part(x.size());
    std::fill(out.begin(), out.end(), 0.0);
    for (std::size_t t = 0; t < strategy_count(); ++t) {
        mis_pdf(t, x, part);
        for (std::size_t i = 0; i < x.size(); ++i) out[i] += part[i];
    }
    const double k = static_cast<double>(strategy_count());
    for (double& p : out) p /= k;
}

std::unique_ptr<WarpCase> make_mis_case(WarpCaseInfo info, MisClaims claims, std::unique_ptr<WarpCase> bsdf,
                                        std::vector<std::unique_ptr<WarpCase>> lights) {
    auto mis = std::make_unique<MisCase>(std::move(info), std::move(claims), std::move(bsdf), std::move(lights));
    validate_case(*mis);
    return mis;
}

std::unique_ptr<WarpCase> make_mis_case(WarpCaseInfo info, MisClaims claims, std::unique_ptr<WarpCase> bsdf,
                                        std::unique_ptr<WarpCase> light) {
    std::vector<std::unique_ptr<WarpCase>> lights;
    lights.push_back(std::move(light));
    return make_mis_case(std::move(info), std::move(claims), std::move(bsdf), std::move(lights));
}

}  // namespace warpcheck
