#include "validate/checks/bsdf/bsdf_common.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace warpcheck::bsdf {

namespace {

std::vector<WarpOutput> nodes_as_outputs(std::span<const chi2::DomainPoint> points) {
    std::vector<WarpOutput> x(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) x[i] = to_warp_output(points[i]);
    return x;
}

}  // namespace

std::vector<std::array<float, 3>> continuous_pilot(const BsdfCase& bsdf, const CheckContext& ctx, std::size_t count) {
    const std::vector<WarpInput> in = pilot_inputs(ctx, InputKind::Uniform3D, count);
    std::vector<BsdfRecord> records(in.size());
    bsdf.sample_bsdf(in, records);
    std::vector<std::array<float, 3>> pilot;
    for (const BsdfRecord& r : records)
        if (r.sampled() && !r.delta()) pilot.push_back(r.wi);
    return pilot;
}

chi2::BatchPdf pdf_integrand(const BsdfCase& bsdf) {
    return [&bsdf](std::span<const chi2::DomainPoint> points, std::span<double> out) {
        bsdf.pdf(nodes_as_outputs(points), out);
    };
}

chi2::BatchPdf albedo_integrand(const BsdfCase& bsdf, Vector3f wo) {
    return [&bsdf, wo](std::span<const chi2::DomainPoint> points, std::span<double> out) {
        const std::vector<WarpOutput> x = nodes_as_outputs(points);
        const std::vector<WarpOutput> from(x.size(), detail::to_output_of(wo));
        bsdf.f(from, x, out);
        for (std::size_t i = 0; i < x.size(); ++i) out[i] *= bsdf.cosine(x[i]);
    };
}

FamilyPoint family_point(const BsdfCase& bsdf, std::string title, std::string y_label) {
    FamilyPoint p;
    p.family = bsdf.info().family;
    p.title = std::move(title);
    p.x_label = "theta_o (degrees)";
    p.y_label = std::move(y_label);
    p.x = std::acos(std::clamp(static_cast<double>(bsdf.wo().z), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    std::vector<Parameter> others;
    for (const Parameter& q : bsdf.info().params)
        if (q.name == "theta_o") p.x = q.value;
        else others.push_back(q);
    const std::string name = case_name("", others);  // "[alpha=0.05]", or "" without others
    p.group = name.empty() ? name : name.substr(1, name.size() - 2);
    return p;
}

chi2::BinResolution bsdf_resolution(const BsdfCase& bsdf) {
    chi2::BinResolution r = bsdf.info().chi2_resolution;
    if (r.first == 0) r.first = 32;
    if (r.second == 0) r.second = 64;
    return r;
}

}  // namespace warpcheck::bsdf
