// "bsdf_unbinned": the unbinned tests of the unbinned check (unbinned_check.cpp)
// on the continuous lobes' wi, reflection and transmission together: the
// marginals of phi_i and cos theta_i of the whole sphere against their CDFs
// tabulated from pdf(wo, .) and normalised by its integral T, which is the
// law of a continuous sample given that it landed (as bsdf_chi2 tests it
// binned; whether T is right is bsdf_chi2's landing rule). Draws without a
// sample and delta samples are left out, so the tests see exactly the draws
// bsdf_chi2's cells see.
//
// Everything else is the unbinned check's, unchanged: Anderson-Darling on
// cos theta_i, Kuiper and Anderson-Darling on the azimuth phi_i (a lobe
// across phi = 0, as a reflection at phi_o = 0 is, is one deviation to
// Kuiper); each sample tested within its +-2 float-step band, tie-aware,
// where float resolution and the CDF's error together could move the CDF by
// more than 0.1 / sqrt(N) (a sharp lobe's cos theta_i near 1, a lobe at the
// horizon); one p-value per case, Sidak over its tests, judged by the runner
// at the run's level like every statistical test. Binning throws away where
// in a cell a sample fell: a roughness or a g that is off by a percent moves
// every sample a little and a 1024-strip CDF sees it where 32 x 64 cells
// average it away.
#include <cmath>
#include <vector>

#include "validate/checks/bsdf/bsdf_checks.h"
#include "validate/checks/bsdf/bsdf_common.h"
#include "validate/checks/checks.h"
#include "validate/checks/shared/direction_length.h"

namespace warpcheck::bsdf {
namespace {

/// The wi of the continuous samples among a chunk's draws, in input order.
void continuous_directions(const BsdfCase& bsdf, std::span<const WarpInput> in, std::vector<WarpOutput>& out) {
    thread_local std::vector<BsdfRecord> records;  // kept per thread, as map_bsdf_chunks does
    records.resize(in.size());
    bsdf.sample_bsdf(in, records);
    out.clear();
    for (const BsdfRecord& r : records)
        if (r.sampled() && !r.delta()) out.push_back(r.wi);
}

/// The cells of pdf_integral: 16 azimuths by 32 heights, a quarter of
/// bsdf_chi2's, for a quarter of the cost (10 to 25 ms): the verified bound
/// stays near 1e-5 on the sharpest built-in lobes, a tenth of the 0.1 / sqrt(N)
/// = 1e-4 below which the tests ignore a CDF's error, and reported.
constexpr chi2::BinResolution kIntegralCells{16, 32};

/// T, the integral of pdf(wo, .) over the sphere (less than 1 where the
/// sampler gives up or delta lobes take a share), by the verified cubature
/// (chi2/quadrature.h), independent of the marginals' strips: what each
/// marginal's tabulation must reproduce, so that a peak its strips' nodes
/// missed shows as a CDF error (the unbinned check holds a warp's to 1).
chi2::CellIntegrals pdf_integral(const BsdfCase& bsdf, const CheckContext& ctx) {
    const chi2::Binning cells(bsdf.domain(), kIntegralCells);
    chi2::QuadratureOptions q;
    q.sample_count = ctx.options().samples;
    q.verify = true;
    return chi2::integrate_cells(cells, pdf_integrand(bsdf), q, ctx.executor());
}

class BsdfUnbinnedCheck final : public BsdfCheck {
public:
    std::string name() const override { return "bsdf_unbinned"; }
    JudgedRules judged_rules() const override { return unbinned_judged_rules(); }
    bool statistical() const override { return true; }
    CheckLegend legend() const override {
        return {name(), "The continuous lobes' phi_i and cos theta_i against their CDFs from pdf(wo, .): the "
                "unbinned check's Anderson\u2013Darling on both and Kuiper on the azimuth, each sample within its "
                "float band where that matters.",
                "1 \u2212 (1 \u2212 min p)^k, \u0160id\u00e1k over the k judged tests."};
    }
    std::string description() const override {
        return "BSDF: Kuiper and Anderson-Darling tests of the continuous lobes' phi_i and cos theta_i against their "
               "CDFs from pdf(wo, .), allowing for float resolution and the CDF's error (Sidak over the tests)";
    }

protected:
    Applicability bsdf_applicability(const BsdfCase& b) const override {
        if (!has(b.claims().lobes, BsdfFlags::Continuous)) return Applicability::not_about_such_cases();
        return unless_stochastic(b, "its sampler's density is not its pdf(), whose values");
    }

    CheckResult run_bsdf(const BsdfCase& bsdf, const CheckContext& ctx) const override {
        UnbinnedSource source;
        source.draw = [&bsdf](std::span<const WarpInput> in, std::vector<WarpOutput>& out) {
            continuous_directions(bsdf, in, out);
        };
        const chi2::CellIntegrals t = pdf_integral(bsdf, ctx);
        source.total = t.total;
        source.total_error = t.error_total;
        source.length_mismatch = length_error(detail::to_output_of(bsdf.claims().wo));
        CheckResult r = run_unbinned(bsdf, ctx, source);
        r.figures.push_back({"pdf_integral", t.total});
        r.figures.push_back({"pdf_integral_error", t.error_total});
        return r;
    }
};

}  // namespace

std::unique_ptr<Check> make_bsdf_unbinned_check() { return std::make_unique<BsdfUnbinnedCheck>(); }

}  // namespace warpcheck::bsdf
