// Warp, BSDF and light cases whose parts are Python callables on NumPy batches,
// behind the same WarpCase interface as a C++ warp: every check, the runner and
// the reports take them as they are. A batch is one call: the checks' chunks
// (4096 to 65536 inputs) are the arrays the callables see, so the cost of the
// call is paid per chunk. Each call takes the GIL; the check threads wait for
// it in turn (NumPy releases it inside its own loops), and the figures do not
// depend on the order in which they get it, because every chunk's inputs and
// the merge of the results are fixed (validate/checks/shared/input_chunks.h).
//
// The shapes (n inputs in a batch):
//   warp:   sample(u) -> x, or (x, value) when it returns its pdf or weight,
//           or indices (n,) for a discrete choice;  pdf(x) -> (n,);
//           invert(x) -> u;  eval(x) -> (n,).
//           u: float32 (n,) in 1D, (n, 2) in 2D; raw bits uint32/uint64 (n,).
//           x: (n,) on a line, (n, 2) in the plane, (n, 3) on the sphere.
//   light:  the same with the reference point first: sample(ref, u) ->
//           (wi, pdf), pdf(ref, wi) -> (n,), ref a float32 array (3,); with
//           its own intersection L(ref, wi) -> (n,), a light case proper
//           (light_case.h): sample(ref, u) -> (wi, pdf, L[, distance]).
//   BSDF:   sample(wo, uc, u) -> (wi, f, pdf[, flags[, eta]]) (a phase
//           function: sample(wo, u)), f(wo, wi) -> (n,), pdf(wo, wi) -> (n,):
//           wo (3,) in sample, wo and wi (n, 3) in f and pdf (f is also called
//           with its arguments swapped, for reciprocity).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "validate/api/bsdf_case.h"
#include "validate/api/light_case.h"
#include "validate/api/warp_case.h"
#include "validate/python/python_calls.h"

namespace warpcheck::python {

struct WarpParts {
    PyRef sample, pdf, invert, eval;
};

class PythonWarpCase final : public WarpCase {
public:
    /// `reference_point`: a light's, passed before every other argument.
    PythonWarpCase(WarpCaseInfo info, const WarpSignature& signature, WarpParts parts,
                   std::optional<std::array<float, 3>> reference_point = std::nullopt);

    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override;
    void sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                           std::span<double> value) const override;
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override;
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override;
    void eval(std::span<const WarpOutput> x, std::span<double> out) const override;

private:
    void run_sample(std::span<const WarpInput> in, std::span<WarpOutput> out, std::span<double> value) const;
    py::object call_part(const PyRef& part, const char* part_name, py::object argument) const;
    std::string what(const char* part) const { return name() + ": " + part; }

    WarpParts parts_;
    std::optional<std::array<float, 3>> reference_point_;
};

struct BsdfParts {
    PyRef sample, f, pdf;
};

class PythonBsdfCase final : public BsdfCase {
public:
    PythonBsdfCase(WarpCaseInfo info, BsdfClaims claims, BsdfParts parts);

    void sample_bsdf(std::span<const WarpInput> in, std::span<BsdfRecord> out) const override;
    void f(std::span<const WarpOutput> a, std::span<const WarpOutput> b, std::span<double> out) const override;
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override;

private:
    BsdfParts parts_;
};

struct LightParts {
    PyRef sample, pdf, L;
};

/// A light of Python callables seen from one reference point, with its own
/// intersection L(ref, wi): the light checks take it.
class PythonLightCase final : public LightCase {
public:
    PythonLightCase(WarpCaseInfo info, LightClaims claims, LightParts parts);

    void sample_light(std::span<const WarpInput> in, std::span<LightRecord> out) const override;
    void radiance(std::span<const WarpOutput> wi, std::span<double> out) const override;
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override;
    void invert(std::span<const WarpOutput>, std::span<WarpInput>) const override {
        throw std::logic_error("light case " + name() + " has no inverse");
    }

private:
    std::vector<double> call_directions(const PyRef& part, const char* part_name, std::span<const WarpOutput> wi) const;

    LightParts parts_;
};

/// What a Python object that describes cases makes: one case, or one per
/// point of its grid (a BSDF's outgoing directions, a light's reference points).
class CaseSpec {
public:
    virtual ~CaseSpec() = default;
    virtual std::vector<std::unique_ptr<WarpCase>> make() const = 0;
};

/// A warp (or, with reference points, a light) of Python callables.
class WarpSpec final : public CaseSpec {
public:
    /// Refused (std::invalid_argument, ValueError in Python) when the
    /// declaration contradicts itself, as make_warp_case refuses a C++ case.
    WarpSpec(WarpCaseInfo info, WarpSignature signature, WarpParts parts,
             std::vector<std::array<float, 3>> reference_points = {});
    std::vector<std::unique_ptr<WarpCase>> make() const override;

private:
    WarpCaseInfo info_;
    WarpSignature signature_;
    WarpParts parts_;
    std::vector<std::array<float, 3>> reference_points_;
};

/// A light of Python callables with L, at each of its reference points.
class LightSpec final : public CaseSpec {
public:
    LightSpec(WarpCaseInfo info, LightParts parts, std::vector<std::array<float, 3>> reference_points,
              std::array<float, 3> normal);
    std::vector<std::unique_ptr<WarpCase>> make() const override;
    const std::vector<std::array<float, 3>>& reference_points() const { return reference_points_; }

private:
    WarpCaseInfo info_;
    LightParts parts_;
    std::vector<std::array<float, 3>> reference_points_;
    std::array<float, 3> normal_;
};

/// A BSDF of Python callables over a list of outgoing directions (theta_o in
/// degrees, in the plane phi = 0), one case each, named family[...,theta_o=T].
class BsdfSpec final : public CaseSpec {
public:
    BsdfSpec(WarpCaseInfo info, BsdfClaims claims, BsdfParts parts, std::vector<double> theta_o);
    std::vector<std::unique_ptr<WarpCase>> make() const override;
    const std::vector<double>& theta_o() const { return theta_o_; }

private:
    WarpCaseInfo info_;
    BsdfClaims claims_;
    BsdfParts parts_;
    std::vector<double> theta_o_;
};

/// An MIS case of Python parts (make_mis_case): a BSDF spec and one or more
/// light specs with L, one MIS case per pair of the BSDF's outgoing direction
/// and the lights' k-th reference point (every light gives the same number),
/// named family[...,theta_o=T,px=..,py=..,pz=..]. The MIS pdfs, where given,
/// are Python batch callables in the BSDF's and the lights' pdf forms:
/// bsdf_mis_pdf(wo, wi) with wo and wi (n, 3), a light's mis_pdf(ref, wi) with
/// ref (3,) (MisPdfs::bsdf_batch and lights_batch); None: the case's own pdf.
class MisSpec final : public CaseSpec {
public:
    MisSpec(WarpCaseInfo info, MisHeuristic heuristic, std::shared_ptr<const BsdfSpec> bsdf,
            std::vector<std::shared_ptr<const LightSpec>> lights, PyRef bsdf_mis_pdf, std::vector<PyRef> light_mis_pdfs);
    std::vector<std::unique_ptr<WarpCase>> make() const override;

private:
    WarpCaseInfo info_;
    MisHeuristic heuristic_;
    std::shared_ptr<const BsdfSpec> bsdf_;
    std::vector<std::shared_ptr<const LightSpec>> lights_;
    PyRef bsdf_mis_pdf_;
    std::vector<PyRef> light_mis_pdfs_;
};

/// A case of the C++ registry (a built-in warp), by reference: its own
/// functions, not Python's. BSDFs are not offered this way.
class RegisteredSpec final : public CaseSpec {
public:
    explicit RegisteredSpec(const WarpCase& warp) : warp_(warp) {}
    const WarpCase& warp() const { return warp_; }
    std::vector<std::unique_ptr<WarpCase>> make() const override;

private:
    const WarpCase& warp_;
};

}  // namespace warpcheck::python
