// The case description in Python: Domain, View, Warp, light() and Bsdf, the
// same fields as C++'s WarpCaseInfo, BsdfClaims and MonotoneMarginal, named as
// there (validate/api/README.md), checked by the same validate_case.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "validate/python/python_cases.h"

namespace warpcheck::python {
namespace {

template <typename Enum>
Enum choice(const std::string& value, const std::map<std::string, Enum>& choices, const char* what) {
    const auto it = choices.find(value);
    if (it != choices.end()) return it->second;
    std::string names;
    for (const auto& [name, e] : choices) names += (names.empty() ? "" : ", ") + ("'" + name + "'");
    throw py::value_error(fmt::format("{}: '{}' is not one of {}", what, value, names));
}

InputKind input_kind(const std::string& s) {
    return choice<InputKind>(s,
                             {{"uniform1d", InputKind::Uniform1D},
                              {"uniform2d", InputKind::Uniform2D},
                              {"bits32", InputKind::Bits32},
                              {"bits64", InputKind::Bits64}},
                             "input");
}

SampleReturns sample_returns(const std::string& s) {
    return choice<SampleReturns>(s,
                                 {{"point", SampleReturns::Point},
                                  {"pdf", SampleReturns::PointAndPdf},
                                  {"weight", SampleReturns::PointAndWeight},
                                  {"index", SampleReturns::Index},
                                  {"index_and_u", SampleReturns::IndexAndRemappedU}},
                                 "returns");
}

std::vector<Parameter> parameters(const py::dict& params) {
    std::vector<Parameter> out;
    for (const auto& [key, value] : params) out.push_back({py::str(key), value.cast<double>()});
    return out;
}

/// A view's coordinate: None (x[0]), an index, "phi" (the azimuth, NaN at a pole) or a callable of the point.
std::function<double(const WarpOutput&)> view_coordinate(const py::object& c) {
    if (c.is_none()) return {};
    if (py::isinstance<py::int_>(c)) {
        const int k = c.cast<int>();
        if (k < 0 || k > 2) throw py::value_error(fmt::format("View coordinate {} is not 0, 1 or 2", k));
        return [k](const WarpOutput& w) { return static_cast<double>(w[static_cast<std::size_t>(k)]); };
    }
    if (py::isinstance<py::str>(c)) {
        if (c.cast<std::string>() != "phi") throw py::value_error("View coordinate: give 0, 1, 2, 'phi' or a callable");
        return [](const WarpOutput& w) { return w[0] == 0 && w[1] == 0 ? std::nan("") : exact_phi(w[0], w[1]); };
    }
    const PyRef fn(c);
    return [fn](const WarpOutput& w) {
        const CallGil gil;
        const py::object r = call(fn, "view coordinate", points_array(std::span(&w, 1), 3)[py::int_(0)]);
        return r.cast<double>();
    };
}

std::function<double(double)> view_pdf(const py::object& p) {
    if (p.is_none()) return {};
    const PyRef fn(p);
    return [fn](double x) {
        const CallGil gil;
        return call(fn, "view pdf", x).cast<double>();
    };
}

std::shared_ptr<CaseSpec> make_warp(const std::string& family, const py::object& sample, const py::object& pdf,
                                    const py::object& invert, const py::object& eval, const chi2::Domain& domain,
                                    const py::dict& params, const std::string& description, const std::string& input,
                                    const std::string& returns, std::size_t categories,
                                    const std::vector<MonotoneMarginal>& views, double roundtrip_tolerance,
                                    double support_measure, const std::string& inversion) {
    WarpCaseInfo info;
    info.family = family;
    info.params = parameters(params);
    info.description = description;
    info.domain = domain;
    info.views = views;
    info.categories = categories;
    info.support_measure = support_measure;
    if (roundtrip_tolerance > 0) info.roundtrip_tolerance = roundtrip_tolerance;
    info.inversion = choice<Inversion>(
        inversion, {{"measure", Inversion::Measure}, {"claimed", Inversion::Claimed}, {"not_inversion", Inversion::NotInversion}},
        "inversion");
    WarpSignature s;
    s.input = input_kind(input);
    s.returns = sample_returns(returns);
    const bool discrete = s.returns == SampleReturns::Index || s.returns == SampleReturns::IndexAndRemappedU;
    s.output_dimension = discrete ? 0 : domain.point_dimension();
    s.has_pdf = !pdf.is_none();
    s.has_inverse = !invert.is_none();
    s.has_eval = !eval.is_none();
    if (sample.is_none()) throw py::value_error("Warp " + family + ": a warp needs a sample");
    return std::make_shared<WarpSpec>(info, s, WarpParts{PyRef(sample), PyRef(pdf), PyRef(invert), PyRef(eval)});
}

std::shared_ptr<CaseSpec> make_light(const std::string& family, const py::object& sample, const py::object& pdf,
                                     const std::vector<std::array<float, 3>>& points, const py::dict& params,
                                     const std::string& description, const chi2::Domain& domain,
                                     double support_measure, const py::object& L,
                                     const std::optional<std::array<float, 3>>& normal) {
    if (points.empty()) throw py::value_error("light " + family + ": give at least one reference point");
    WarpCaseInfo info;
    info.family = family;
    info.params = parameters(params);
    info.description = description;
    if (!L.is_none()) {
        // With its own intersection: a light case proper, on the sphere, with the light checks.
        if (pdf.is_none()) throw py::value_error("light " + family + ": a light with L needs its pdf(ref, wi)");
        if (support_measure != 0.0) throw py::value_error("light " + family + ": support_measure is for a light without L");
        return std::make_shared<LightSpec>(info, LightParts{PyRef(sample), PyRef(pdf), PyRef(L)}, points,
                                           normal.value_or(std::array<float, 3>{0.0f, 0.0f, 0.0f}));
    }
    if (normal) throw py::value_error("light " + family + ": a normal weighs L, which this light does not give");
    info.domain = domain;
    info.support_measure = support_measure;
    WarpSignature s;
    s.input = InputKind::Uniform2D;
    s.returns = SampleReturns::PointAndPdf;
    s.output_dimension = domain.point_dimension();
    s.has_pdf = !pdf.is_none();
    return std::make_shared<WarpSpec>(info, s, WarpParts{PyRef(sample), PyRef(pdf), {}, {}}, points);
}

BsdfFlags lobes_of(const std::vector<std::string>& lobes) {
    BsdfFlags f = BsdfFlags::None;
    for (const std::string& l : lobes)
        f = f | choice<BsdfFlags>(l,
                                  {{"reflection", BsdfFlags::Reflection},
                                   {"transmission", BsdfFlags::Transmission},
                                   {"continuous", BsdfFlags::Continuous},
                                   {"delta", BsdfFlags::Delta}},
                                  "lobes");
    return f;
}

std::shared_ptr<CaseSpec> make_bsdf(const std::string& family, const py::object& sample, const py::object& f,
                                    const py::object& pdf, const std::vector<double>& theta_o, const py::dict& params,
                                    const std::string& description, const std::vector<std::string>& lobes, float eta,
                                    bool reciprocal, const std::string& transport, bool phase_function,
                                    bool stochastic) {
    WarpCaseInfo info;
    info.family = family;
    info.params = parameters(params);
    info.description = description;
    BsdfClaims claims;
    claims.lobes = lobes_of(lobes);
    claims.eta = eta;
    claims.reciprocal = reciprocal;
    claims.transport = choice<Transport>(transport, {{"radiance", Transport::Radiance}, {"importance", Transport::Importance}},
                                         "transport");
    claims.phase_function = phase_function;
    claims.stochastic = stochastic;
    if (sample.is_none() || f.is_none() || pdf.is_none())
        throw py::value_error("Bsdf " + family + ": a BSDF needs sample, f and pdf");
    return std::make_shared<BsdfSpec>(info, claims, BsdfParts{PyRef(sample), PyRef(f), PyRef(pdf)}, theta_o);
}

std::shared_ptr<CaseSpec> make_mis(const std::string& family, const std::shared_ptr<CaseSpec>& bsdf,
                                   const std::vector<std::shared_ptr<CaseSpec>>& lights, const std::string& heuristic,
                                   const py::object& bsdf_mis_pdf, const std::vector<py::object>& light_mis_pdfs,
                                   const py::dict& params, const std::string& description) {
    WarpCaseInfo info;
    info.family = family;
    info.params = parameters(params);
    info.description = description;
    auto b = std::dynamic_pointer_cast<const BsdfSpec>(bsdf);
    if (!b) throw py::value_error("Mis " + family + ": bsdf must be a Bsdf of Python callables");
    std::vector<std::shared_ptr<const LightSpec>> ls;
    for (const auto& l : lights) {
        auto light = std::dynamic_pointer_cast<const LightSpec>(l);
        if (!light) throw py::value_error("Mis " + family + ": each light must be a Light of Python callables with L");
        ls.push_back(std::move(light));
    }
    std::vector<PyRef> pdfs;
    for (const py::object& f : light_mis_pdfs) pdfs.emplace_back(f);
    return std::make_shared<MisSpec>(
        info, choice<MisHeuristic>(heuristic, {{"power", MisHeuristic::Power}, {"balance", MisHeuristic::Balance}}, "heuristic"),
        std::move(b), std::move(ls), PyRef(bsdf_mis_pdf), std::move(pdfs));
}

void bind_domain(py::module_& m) {
    py::class_<chi2::Domain>(m, "Domain", "The set a warp maps onto, and the measure its pdf is a density of")
        .def_static("interval", &chi2::Domain::interval, py::arg("a"), py::arg("b"))
        .def_static("half_line", &chi2::Domain::half_line, py::arg("a"))
        .def_static("lower_half_line", &chi2::Domain::lower_half_line, py::arg("b"))
        .def_static("real_line", &chi2::Domain::real_line)
        .def_static("box", &chi2::Domain::box, py::arg("x0"), py::arg("x1"), py::arg("y0"), py::arg("y1"))
        .def_static("unit_square", &chi2::Domain::unit_square)
        .def_static("unit_disk", &chi2::Domain::unit_disk)
        .def_static("spherical_cap", &chi2::Domain::spherical_cap, py::arg("z_min"))
        .def_static("sphere", &chi2::Domain::sphere)
        .def_static("hemisphere", &chi2::Domain::hemisphere)
        .def_static("triangle", &chi2::Domain::triangle, py::arg("a"), py::arg("b"), py::arg("c"))
        .def_property_readonly("point_dimension", &chi2::Domain::point_dimension)
        .def_property_readonly("measure", &chi2::Domain::measure)
        .def("__repr__", [](const chi2::Domain& d) { return "Domain(" + d.describe() + ")"; });
}

void bind_view(py::module_& m) {
    py::class_<MonotoneMarginal>(m, "View", "A monotone 1D view of a warp (C++ MonotoneMarginal)")
        .def(py::init([](const std::string& label, double lo, double hi, int input_coordinate, bool increasing,
                         double tail_mass, double lower_tail_mass, const py::object& coordinate, const py::object& pdf) {
                 MonotoneMarginal v;
                 v.label = label;
                 v.lo = lo;
                 v.hi = hi;
                 v.input_coordinate = input_coordinate;
                 v.increasing = increasing;
                 v.tail_mass = tail_mass;
                 v.lower_tail_mass = lower_tail_mass;
                 v.coordinate = view_coordinate(coordinate);
                 v.pdf = view_pdf(pdf);
                 return v;
             }),
             py::arg("label"), py::arg("lo") = 0.0, py::arg("hi") = 1.0, py::kw_only(), py::arg("input_coordinate") = 0,
             py::arg("increasing") = true, py::arg("tail_mass") = 0.0, py::arg("lower_tail_mass") = 0.0,
             py::arg("coordinate") = py::none(), py::arg("pdf") = py::none())
        .def_readonly("label", &MonotoneMarginal::label);
}

}  // namespace

void bind_cases(py::module_& m) {
    bind_domain(m);
    bind_view(m);
    py::class_<CaseSpec, std::shared_ptr<CaseSpec>>(m, "Cases", "One case, or a case per point of a grid")
        .def_property_readonly("names", [](const CaseSpec& spec) {
            std::vector<std::string> names;
            for (const auto& c : spec.make()) names.push_back(c->name());
            return names;
        });
    m.def("warp", &make_warp, py::arg("family"), py::arg("sample"), py::kw_only(), py::arg("pdf") = py::none(),
          py::arg("invert") = py::none(), py::arg("eval") = py::none(), py::arg("domain") = chi2::Domain::unit_square(),
          py::arg("params") = py::dict(), py::arg("description") = "", py::arg("input") = "uniform2d",
          py::arg("returns") = "point", py::arg("categories") = 0, py::arg("views") = std::vector<MonotoneMarginal>{},
          py::arg("roundtrip_tolerance") = 0.0, py::arg("support_measure") = 0.0, py::arg("inversion") = "measure");
    m.def("light", &make_light, py::arg("family"), py::arg("sample"), py::kw_only(), py::arg("pdf") = py::none(),
          py::arg("points"), py::arg("params") = py::dict(), py::arg("description") = "",
          py::arg("domain") = chi2::Domain::sphere(), py::arg("support_measure") = 0.0, py::arg("L") = py::none(),
          py::arg("normal") = std::optional<std::array<float, 3>>{});
    m.def("bsdf", &make_bsdf, py::arg("family"), py::arg("sample"), py::kw_only(), py::arg("f"), py::arg("pdf"),
          py::arg("theta_o"), py::arg("params") = py::dict(), py::arg("description") = "",
          py::arg("lobes") = std::vector<std::string>{"reflection", "continuous"}, py::arg("eta") = 1.0f,
          py::arg("reciprocal") = true, py::arg("transport") = "radiance", py::arg("phase_function") = false,
          py::arg("stochastic") = false);
    m.def("mis", &make_mis, py::arg("family"), py::arg("bsdf"), py::arg("lights"), py::kw_only(),
          py::arg("heuristic") = "power", py::arg("bsdf_mis_pdf") = py::none(),
          py::arg("light_mis_pdfs") = std::vector<py::object>{}, py::arg("params") = py::dict(),
          py::arg("description") = "");
}

}  // namespace warpcheck::python
