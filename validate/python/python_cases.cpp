#include "validate/python/python_cases.h"

#include <span>

#include <fmt/format.h>

namespace warpcheck::python {
namespace {

bool returns_value(SampleReturns r) {
    return r == SampleReturns::PointAndPdf || r == SampleReturns::PointAndWeight || r == SampleReturns::IndexAndRemappedU;
}

/// The two parts of a returned pair, (x, value): a tuple or list of two.
std::pair<py::object, py::object> pair_of(const py::object& r, const std::string& what, const char* value_name) {
    if ((!py::isinstance<py::tuple>(r) && !py::isinstance<py::list>(r)) || py::len(r) != 2)
        throw PythonCallError(fmt::format("{} returned a {}; it must return a pair (x, {}) of arrays", what,
                                          py::str(r.get_type()).cast<std::string>(), value_name));
    return {r[py::int_(0)], r[py::int_(1)]};
}

const char* value_name(SampleReturns r) {
    return r == SampleReturns::PointAndPdf ? "pdf" : r == SampleReturns::PointAndWeight ? "weight" : "u_remapped";
}

/// A float32 array (3,) of a point.
py::array vector3(const std::array<float, 3>& v) {
    py::array_t<float> a(3);
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

/// The same point n times, (n, 3).
py::array repeated(const WarpOutput& v, std::size_t n) {
    const std::vector<WarpOutput> rows(n, v);
    return points_array(rows, 3);
}

/// A case of the registry (a built-in warp) seen through its own functions.
class ForwardingCase final : public WarpCase {
public:
    explicit ForwardingCase(const WarpCase& inner) : WarpCase(inner.info(), inner.signature()), inner_(inner) {}
    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override { inner_.sample(in, out); }
    void sample_planar(const float* u0, const float* u1, float* x, float* y, float* z, std::size_t n) const override {
        inner_.sample_planar(u0, u1, x, y, z, n);
    }
    void sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                           std::span<double> value) const override {
        inner_.sample_with_value(in, out, value);
    }
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override { inner_.pdf(x, out); }
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override { inner_.invert(x, out); }
    void eval(std::span<const WarpOutput> x, std::span<double> out) const override { inner_.eval(x, out); }

private:
    const WarpCase& inner_;
};

}  // namespace

PythonWarpCase::PythonWarpCase(WarpCaseInfo info, const WarpSignature& signature, WarpParts parts,
                               std::optional<std::array<float, 3>> reference_point)
    : WarpCase(std::move(info), signature), parts_(std::move(parts)), reference_point_(reference_point) {}

py::object PythonWarpCase::call_part(const PyRef& part, const char* part_name, py::object argument) const {
    if (reference_point_) return call(part, what(part_name), vector3(*reference_point_), std::move(argument));
    return call(part, what(part_name), std::move(argument));
}

void PythonWarpCase::run_sample(std::span<const WarpInput> in, std::span<WarpOutput> out, std::span<double> value) const {
    const CallGil gil;
    const std::size_t n = in.size();
    py::object points = call_part(parts_.sample, "sample", inputs_array(in, input_kind()));
    py::object values;
    const SampleReturns returns = sample_returns();
    if (returns_value(returns)) std::tie(points, values) = pair_of(points, what("sample"), value_name(returns));
    if (is_discrete()) {
        const std::vector<double> index = read_array(points, n, 1, what("sample") + " (category indices)", true);
        for (std::size_t k = 0; k < n; ++k) out[k] = {static_cast<float>(index[k]), 0.0f, 0.0f};
    } else {
        const auto dims = static_cast<std::size_t>(signature().output_dimension);
        const std::vector<double> x = read_array(points, n, dims, what("sample"));
        for (std::size_t k = 0; k < n; ++k) {
            out[k] = {};
            for (std::size_t c = 0; c < dims; ++c) out[k][c] = static_cast<float>(x[k * dims + c]);  // rounded to float
        }
    }
    if (values && !value.empty()) {
        const std::vector<double> v = read_array(values, n, 1, what("sample") + fmt::format(" ({})", value_name(returns)));
        std::copy(v.begin(), v.end(), value.begin());
    }
}

void PythonWarpCase::sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const { run_sample(in, out, {}); }

void PythonWarpCase::sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                                       std::span<double> value) const {
    if (!returns_value(sample_returns())) return WarpCase::sample_with_value(in, out, value);
    run_sample(in, out, value);
}

namespace {

/// The points a pdf or eval takes: coordinates, or a discrete case's indices (int64).
py::array arguments_of(const WarpCase& warp, std::span<const WarpOutput> x) {
    if (!warp.is_discrete()) return points_array(x, warp.signature().output_dimension);
    py::array_t<int64_t> a(static_cast<py::ssize_t>(x.size()));
    for (std::size_t k = 0; k < x.size(); ++k) a.mutable_data()[k] = static_cast<int64_t>(x[k][0]);
    return a;
}

}  // namespace

void PythonWarpCase::pdf(std::span<const WarpOutput> x, std::span<double> out) const {
    if (!has_pdf()) throw std::logic_error("warp case " + name() + " has no pdf function");
    const CallGil gil;
    const std::vector<double> v = read_array(call_part(parts_.pdf, "pdf", arguments_of(*this, x)), x.size(), 1, what("pdf"));
    std::copy(v.begin(), v.end(), out.begin());
}

void PythonWarpCase::eval(std::span<const WarpOutput> x, std::span<double> out) const {
    if (!signature().has_eval) return WarpCase::eval(x, out);
    const CallGil gil;
    const std::vector<double> v =
        read_array(call_part(parts_.eval, "eval", arguments_of(*this, x)), x.size(), 1, what("eval"));
    std::copy(v.begin(), v.end(), out.begin());
}

void PythonWarpCase::invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const {
    if (!has_inverse()) throw std::logic_error("warp case " + name() + " has no inverse");
    const CallGil gil;
    const py::object r = call_part(parts_.invert, "invert", arguments_of(*this, x));
    const std::size_t n = x.size();
    if (takes_bits(input_kind())) {
        const std::vector<uint64_t> bits = read_bits(r, n, what("invert"));
        for (std::size_t k = 0; k < n; ++k) out[k] = {{}, bits[k]};
        return;
    }
    const auto dims = static_cast<std::size_t>(input_dimension(input_kind()));
    const std::vector<double> u = read_array(r, n, dims, what("invert"));
    for (std::size_t k = 0; k < n; ++k) {
        out[k] = {};
        for (std::size_t c = 0; c < dims; ++c) out[k].u[c] = static_cast<float>(u[k * dims + c]);
    }
}

PythonBsdfCase::PythonBsdfCase(WarpCaseInfo info, BsdfClaims claims, BsdfParts parts)
    : BsdfCase(std::move(info), claims), parts_(std::move(parts)) {}

namespace {

/// The parts of a sample that returns several arrays: a tuple or list of the
/// `keys` in order, the first three required, or a dict of those keys; else
/// the error that `must_return` completes.
std::vector<py::object> sample_parts(const py::object& r, const std::string& what, std::span<const char* const> keys,
                                     const char* must_return) {
    std::vector<py::object> parts(keys.size());
    if (py::isinstance<py::dict>(r)) {
        const auto d = r.cast<py::dict>();
        for (std::size_t k = 0; k < keys.size(); ++k)
            if (d.contains(keys[k])) parts[k] = d[keys[k]];
    } else if ((py::isinstance<py::tuple>(r) || py::isinstance<py::list>(r)) && py::len(r) >= 3 &&
               py::len(r) <= keys.size()) {
        for (std::size_t k = 0; k < py::len(r); ++k) parts[k] = r[py::int_(k)];
    }
    if (!parts[0] || !parts[1] || !parts[2])
        throw PythonCallError(
            fmt::format("{} returned a {}; {}", what, py::str(r.get_type()).cast<std::string>(), must_return));
    return parts;
}

/// The parts of a BSDF sample: a tuple or list (wi, f, pdf[, flags[, eta]]), or a dict of those keys.
std::vector<py::object> bsdf_sample_parts(const py::object& r, const std::string& what) {
    static const char* const kKeys[] = {"wi", "f", "pdf", "flags", "eta"};
    return sample_parts(r, what, kKeys,
                        "it must return (wi, f, pdf[, flags[, eta]]) or a dict with keys wi, f, pdf (and flags, eta)");
}

}  // namespace

void PythonBsdfCase::sample_bsdf(std::span<const WarpInput> in, std::span<BsdfRecord> out) const {
    const CallGil gil;
    const std::size_t n = in.size();
    const std::string what = name() + ": sample";
    py::array_t<float> uc(static_cast<py::ssize_t>(n)), u({static_cast<py::ssize_t>(n), py::ssize_t{2}});
    for (std::size_t k = 0; k < n; ++k) {
        uc.mutable_data()[k] = in[k].u[0];
        u.mutable_data()[2 * k] = in[k].u[1];
        u.mutable_data()[2 * k + 1] = in[k].u[2];
    }
    const Vector3f w = wo();
    const py::array wo_array = vector3({w.x, w.y, w.z});
    const py::object r = phase_function() ? call(parts_.sample, what, wo_array, u) : call(parts_.sample, what, wo_array, uc, u);
    const std::vector<py::object> parts = bsdf_sample_parts(r, what);
    const std::vector<double> wi = read_array(parts[0], n, 3, what + " (wi)");
    const std::vector<double> f = read_array(parts[1], n, 1, what + " (f)");
    const std::vector<double> pdf = read_array(parts[2], n, 1, what + " (pdf)");
    const std::vector<double> flags = parts[3] ? read_array(parts[3], n, 1, what + " (flags)", true) : std::vector<double>{};
    const std::vector<double> eta = parts[4] ? read_array(parts[4], n, 1, what + " (eta)") : std::vector<double>{};
    for (std::size_t k = 0; k < n; ++k) {
        BsdfRecord& rec = out[k];
        rec.wi = {static_cast<float>(wi[3 * k]), static_cast<float>(wi[3 * k + 1]), static_cast<float>(wi[3 * k + 2])};
        rec.f = static_cast<float>(f[k]);
        rec.pdf = static_cast<float>(pdf[k]);
        rec.eta = eta.empty() ? 1.0f : static_cast<float>(eta[k]);
        if (!flags.empty()) rec.flags = static_cast<BsdfFlags>(static_cast<uint8_t>(flags[k]));
        else if (phase_function()) rec.flags = BsdfFlags::Continuous;
        else rec.flags = BsdfFlags::Continuous | (rec.wi[2] * w.z > 0.0f ? BsdfFlags::Reflection : BsdfFlags::Transmission);
    }
}

void PythonBsdfCase::f(std::span<const WarpOutput> a, std::span<const WarpOutput> b, std::span<double> out) const {
    const CallGil gil;
    const std::string what = name() + (phase_function() ? ": p" : ": f");
    const std::vector<double> v = read_array(call(parts_.f, what, points_array(a, 3), points_array(b, 3)), a.size(), 1, what);
    std::copy(v.begin(), v.end(), out.begin());
}

void PythonBsdfCase::pdf(std::span<const WarpOutput> x, std::span<double> out) const {
    const CallGil gil;
    const std::string what = name() + ": pdf";
    const Vector3f w = wo();
    const std::vector<double> v =
        read_array(call(parts_.pdf, what, repeated({w.x, w.y, w.z}, x.size()), points_array(x, 3)), x.size(), 1, what);
    std::copy(v.begin(), v.end(), out.begin());
}

WarpSpec::WarpSpec(WarpCaseInfo info, WarpSignature signature, WarpParts parts,
                   std::vector<std::array<float, 3>> reference_points)
    : info_(std::move(info)), signature_(signature), parts_(std::move(parts)), reference_points_(std::move(reference_points)) {
    (void)make();  // refused here, where it is declared, if it contradicts itself
}

std::vector<std::unique_ptr<WarpCase>> WarpSpec::make() const {
    std::vector<std::unique_ptr<WarpCase>> cases;
    if (reference_points_.empty()) {
        cases.push_back(std::make_unique<PythonWarpCase>(info_, signature_, parts_));
    } else {
        for (const auto& p : reference_points_) {
            WarpCaseInfo info = info_;
            info.params.push_back({"px", p[0]});
            info.params.push_back({"py", p[1]});
            info.params.push_back({"pz", p[2]});
            cases.push_back(std::make_unique<PythonWarpCase>(std::move(info), signature_, parts_, p));
        }
    }
    for (const auto& c : cases) validate_case(*c);
    return cases;
}

BsdfSpec::BsdfSpec(WarpCaseInfo info, BsdfClaims claims, BsdfParts parts, std::vector<double> theta_o)
    : info_(std::move(info)), claims_(claims), parts_(std::move(parts)), theta_o_(std::move(theta_o)) {
    if (theta_o_.empty()) throw std::invalid_argument("BSDF " + info_.family + ": give at least one theta_o");
    (void)make();
}

std::vector<std::unique_ptr<WarpCase>> BsdfSpec::make() const {
    std::vector<std::unique_ptr<WarpCase>> cases;
    for (double theta : theta_o_) {
        WarpCaseInfo info = info_;
        info.params.push_back({"theta_o", theta});
        BsdfClaims claims = claims_;
        claims.wo = bsdf_direction(theta);
        cases.push_back(std::make_unique<PythonBsdfCase>(std::move(info), claims, parts_));
        validate_case(*cases.back());
    }
    return cases;
}

PythonLightCase::PythonLightCase(WarpCaseInfo info, LightClaims claims, LightParts parts)
    : LightCase(std::move(info), claims, false), parts_(std::move(parts)) {}

namespace {

/// The parts of a light sample: a tuple or list (wi, pdf, L[, distance]), or a dict of those keys.
std::vector<py::object> light_sample_parts(const py::object& r, const std::string& what) {
    static const char* const kKeys[] = {"wi", "pdf", "L", "distance"};
    return sample_parts(r, what, kKeys,
                        "a light with L must return (wi, pdf, L[, distance]) or a dict with keys wi, pdf, L (and "
                        "distance)");
}

}  // namespace

void PythonLightCase::sample_light(std::span<const WarpInput> in, std::span<LightRecord> out) const {
    const CallGil gil;
    const std::size_t n = in.size();
    const std::string what = name() + ": sample";
    const Vector3f p = ref();
    const py::object r = call(parts_.sample, what, vector3({p.x, p.y, p.z}), inputs_array(in, InputKind::Uniform2D));
    const std::vector<py::object> parts = light_sample_parts(r, what);
    const std::vector<double> wi = read_array(parts[0], n, 3, what + " (wi)");
    const std::vector<double> pdf = read_array(parts[1], n, 1, what + " (pdf)");
    const std::vector<double> L = read_array(parts[2], n, 1, what + " (L)");
    const std::vector<double> d = parts[3] ? read_array(parts[3], n, 1, what + " (distance)") : std::vector<double>{};
    for (std::size_t k = 0; k < n; ++k)
        out[k] = {{static_cast<float>(wi[3 * k]), static_cast<float>(wi[3 * k + 1]), static_cast<float>(wi[3 * k + 2])},
                  static_cast<float>(pdf[k]), static_cast<float>(L[k]), d.empty() ? 0.0f : static_cast<float>(d[k])};
}

std::vector<double> PythonLightCase::call_directions(const PyRef& part, const char* part_name,
                                                     std::span<const WarpOutput> wi) const {
    const CallGil gil;
    const std::string what = name() + ": " + part_name;
    const Vector3f p = ref();
    return read_array(call(part, what, vector3({p.x, p.y, p.z}), points_array(wi, 3)), wi.size(), 1, what);
}

void PythonLightCase::radiance(std::span<const WarpOutput> wi, std::span<double> out) const {
    const std::vector<double> v = call_directions(parts_.L, "L", wi);
    std::copy(v.begin(), v.end(), out.begin());
}

void PythonLightCase::pdf(std::span<const WarpOutput> x, std::span<double> out) const {
    const std::vector<double> v = call_directions(parts_.pdf, "pdf", x);
    std::copy(v.begin(), v.end(), out.begin());
}

LightSpec::LightSpec(WarpCaseInfo info, LightParts parts, std::vector<std::array<float, 3>> reference_points,
                     std::array<float, 3> normal)
    : info_(std::move(info)), parts_(std::move(parts)), reference_points_(std::move(reference_points)),
      normal_(normal) {
    if (reference_points_.empty()) throw std::invalid_argument("light " + info_.family + ": give at least one reference point");
    (void)make();
}

std::vector<std::unique_ptr<WarpCase>> LightSpec::make() const {
    std::vector<std::unique_ptr<WarpCase>> cases;
    for (const auto& p : reference_points_) {
        WarpCaseInfo info = info_;
        info.params.push_back({"px", p[0]});
        info.params.push_back({"py", p[1]});
        info.params.push_back({"pz", p[2]});
        const LightClaims claims{.ref = {p[0], p[1], p[2]}, .normal = {normal_[0], normal_[1], normal_[2]}};
        cases.push_back(std::make_unique<PythonLightCase>(std::move(info), claims, parts_));
        validate_case(*cases.back());
    }
    return cases;
}

namespace {

/// A Python MIS pdf as MisPdfs' batch form: called as the BSDF's pdf (wo
/// repeated, (n, 3)) or as a light's (ref, (3,)), its values checked as theirs.
MisPdfs::BatchPdf batch_mis_pdf(PyRef fn, std::string what, bool bsdf) {
    if (!fn.given()) return {};
    return [fn = std::move(fn), what = std::move(what), bsdf](Vector3f origin, std::span<const WarpOutput> wi,
                                                             std::span<double> out) {
        const CallGil gil;
        const py::object first = bsdf ? py::object(repeated({origin.x, origin.y, origin.z}, wi.size()))
                                      : py::object(vector3({origin.x, origin.y, origin.z}));
        const std::vector<double> v = read_array(call(fn, what, first, points_array(wi, 3)), wi.size(), 1, what);
        std::copy(v.begin(), v.end(), out.begin());
    };
}

}  // namespace

MisSpec::MisSpec(WarpCaseInfo info, MisHeuristic heuristic, std::shared_ptr<const BsdfSpec> bsdf,
                 std::vector<std::shared_ptr<const LightSpec>> lights, PyRef bsdf_mis_pdf,
                 std::vector<PyRef> light_mis_pdfs)
    : info_(std::move(info)), heuristic_(heuristic), bsdf_(std::move(bsdf)), lights_(std::move(lights)),
      bsdf_mis_pdf_(std::move(bsdf_mis_pdf)), light_mis_pdfs_(std::move(light_mis_pdfs)) {
    const std::string who = "MIS " + info_.family;
    if (!bsdf_) throw std::invalid_argument(who + ": the BSDF must be a Bsdf of Python callables");
    if (lights_.empty()) throw std::invalid_argument(who + ": give at least one light");
    for (const auto& l : lights_) {
        if (!l) throw std::invalid_argument(who + ": each light must be a Light of Python callables with L");
        if (l->reference_points().size() != lights_.front()->reference_points().size())
            throw std::invalid_argument(who + ": the lights give different numbers of reference points");
    }
    if (light_mis_pdfs_.size() > lights_.size())
        throw std::invalid_argument(who + ": more MIS pdfs than lights");
    (void)make();  // refused here if the parts do not fit (make_mis_case)
}

std::vector<std::unique_ptr<WarpCase>> MisSpec::make() const {
    std::vector<std::unique_ptr<WarpCase>> cases;
    const std::size_t directions = bsdf_->theta_o().size(), points = lights_.front()->reference_points().size();
    for (std::size_t d = 0; d < directions; ++d) {
        for (std::size_t p = 0; p < points; ++p) {
            WarpCaseInfo info = info_;
            const std::array<float, 3>& ref = lights_.front()->reference_points()[p];
            info.params.push_back({"theta_o", bsdf_->theta_o()[d]});
            info.params.push_back({"px", ref[0]});
            info.params.push_back({"py", ref[1]});
            info.params.push_back({"pz", ref[2]});
            MisClaims claims{.heuristic = heuristic_};
            claims.pdfs.bsdf_batch = batch_mis_pdf(bsdf_mis_pdf_, info_.family + ": bsdf_mis_pdf", true);
            for (std::size_t k = 0; k < light_mis_pdfs_.size(); ++k)
                claims.pdfs.lights_batch.push_back(
                    batch_mis_pdf(light_mis_pdfs_[k], info_.family + ": light " + std::to_string(k + 1) + " mis_pdf",
                                  false));
            std::vector<std::unique_ptr<WarpCase>> lights;
            for (const auto& l : lights_) lights.push_back(std::move(l->make()[p]));
            cases.push_back(make_mis_case(std::move(info), std::move(claims), std::move(bsdf_->make()[d]),
                                          std::move(lights)));
        }
    }
    return cases;
}

std::vector<std::unique_ptr<WarpCase>> RegisteredSpec::make() const {
    std::vector<std::unique_ptr<WarpCase>> cases;
    cases.push_back(std::make_unique<ForwardingCase>(warp_));
    return cases;
}

}  // namespace warpcheck::python
