#include "validate/bsdf/bsdf_common.h"

namespace warpcheck::bsdf {

namespace {

std::vector<WarpOutput> nodes_as_outputs(std::span<const chi2::DomainPoint> points) {
    std::vector<WarpOutput> x(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) x[i] = to_warp_output(points[i]);
    return x;
}

}  // namespace

chi2::BatchPdf pdf_integrand(const BsdfCase& bsdf) {
    return [&bsdf](std::span<const chi2::DomainPoint> points, std::span<double> out) {
        bsdf.pdf(nodes_as_outputs(points), out);
    };
}

chi2::BatchPdf albedo_integrand(const BsdfCase& bsdf, bool energy) {
    return [&bsdf, energy](std::span<const chi2::DomainPoint> points, std::span<double> out) {
        const std::vector<WarpOutput> x = nodes_as_outputs(points);
        bsdf.f_cos(x, out);
        if (energy)
            for (std::size_t i = 0; i < x.size(); ++i) out[i] *= bsdf.energy_factor(x[i]);
    };
}

chi2::BinResolution bsdf_resolution(const BsdfCase& bsdf) {
    chi2::BinResolution r = bsdf.info().chi2_resolution;
    if (r.first == 0) r.first = 32;
    if (r.second == 0) r.second = 64;
    return r;
}

}  // namespace warpcheck::bsdf
