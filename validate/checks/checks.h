// Factories of the checks that ship with warpcheck; register_builtin_checks adds them all.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "chi2/chi2_test.h"
#include "validate/checks/check.h"

namespace warpcheck {

/// "roundtrip": invert(sample(u)) == u over a seeded stream plus edge inputs.
std::unique_ptr<Check> make_roundtrip_check();
/// "consistency": every sample lies in the domain and has a finite, positive pdf.
std::unique_ptr<Check> make_consistency_check();
/// "exhaustive": every input of a float sampler's grid (all 2^32 for 32 bits),
/// counted exactly per output float against the uniform measure.
std::unique_ptr<Check> make_exhaustive_check();
/// "binade": for 64-bit float samplers, chi-square of the mass per binade and
/// of the significand parity within binades (sees a 257/255 alternation).
std::unique_ptr<Check> make_binade_check();
/// "exhaustive_roundtrip": for 1D warps, every float u of [0,1): invert(sample(u))
/// against u, monotonicity of sample, finite positive pdf. Only with --exhaustive.
std::unique_ptr<Check> make_exhaustive_roundtrip_check();
/// "chi2": Pearson chi-square test of samples against the pdf integrated over cells.
std::unique_ptr<Check> make_chi2_check();
/// The chi-square check's scalar sample source: chunk c drawn from
/// ctx.chunk_rng(c) by draw_inputs and warped by WarpCase::sample (the
/// histogram the lane path of validate/lanes/lane_sampling.h must match).
chi2::SampleChunk chi2_sample_chunks(const WarpCase& warp, const CheckContext& ctx);
/// The chi-square check's vector path on this processor: "avx512" or "avx2"
/// where the lanes run (validate/lanes/lane_sampling.h), else "scalar".
const char* chi2_vector_path();

/// "tabulated": for 1D warps and the monotone 1D views of a case (WarpCaseInfo::views),
/// sample(u) and the density against the inversion method on a 65536-bucket
/// PiecewiseConstant1D of the density, with bucket-derived tolerances.
std::unique_ptr<Check> make_tabulated_check();
/// "unbinned": KS, Kuiper and Anderson-Darling tests of every marginal against its CDF from the pdf.
std::unique_ptr<Check> make_unbinned_check();
/// What the unbinned tests take: the outputs of a chunk of inputs, in input
/// order (a warp's samples, or only some of them: a BSDF's continuous ones),
/// and the integral of the case's pdf over its domain that the tabulated
/// marginals must reproduce, with its error bound (1 for a warp's density).
struct UnbinnedSource {
    std::function<void(std::span<const WarpInput> in, std::vector<WarpOutput>& out)> draw;
    double total = 1.0;
    double total_error = 0.0;
    /// How far from unit length, relative, the direction is that the pdf
    /// compares its input with (a BSDF's wo: |len(wo) - 1|). A half vector
    /// wi + wo seen from grazing cancels to a few 1e-6, so a lobe 1e-4 wide
    /// moves by ~0.4% of its width when wo is 2^-26 longer than wi, and its
    /// CDF by ~0.2%: the CDF is tabulated again with the pdf's directions
    /// this much longer and shorter, and the difference carried into the test.
    double length_mismatch = 0.0;
};
/// The unbinned check's run on the outputs the source draws, tested against
/// the marginal CDFs of warp.pdf normalised by their integral.
CheckResult run_unbinned(const WarpCase& warp, const CheckContext& ctx, const UnbinnedSource& source);
/// What the unbinned check judges (its rows' judged lines): each judged
/// test's p-value at the Sidak level over the judged tests.
JudgedRules unbinned_judged_rules();
/// "sample_pdf": the pdf that sample returns (PdfSample) equals pdf(x) at every sample.
std::unique_ptr<Check> make_sample_pdf_check();
/// "weight": the weight that sample returns (WeightedSample) equals eval(x) / pdf(x) at every sample.
std::unique_ptr<Check> make_weight_check();
/// "weight_mean": the mean weight against the integral of eval over the domain (t-test).
std::unique_ptr<Check> make_weight_mean_check();
/// "inverse_pdf_mean": for a sampler that returns its pdf and has no pdf
/// function, the mean of 1/pdf against the declared support's measure
/// (WarpCaseInfo::support_measure), or one-sided against the domain's (t-test).
std::unique_ptr<Check> make_inverse_pdf_mean_check();
/// "pmf": a discrete case's pmf is finite, non-negative and sums to 1.
std::unique_ptr<Check> make_pmf_check();
/// "discrete_chi2": a discrete case's indices are categories, none of pmf 0 is
/// chosen, and the counts fit the pmf (Pearson with pooling).
std::unique_ptr<Check> make_discrete_chi2_check();
/// "remapped_u": the u a discrete sampler returns for reuse is in [0,1) and uniform.
std::unique_ptr<Check> make_remapped_u_check();

}  // namespace warpcheck
