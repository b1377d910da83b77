// The Python module _warpcheck (the package warpcheck wraps it: validate/python/warpcheck/):
// cases of Python callables, the same checks through the same runner, the
// same results and reports, and samples from elsewhere as NumPy arrays.
// validate/python/README.md is its guide.
//
// Runs are in-process, never in worker processes: the runner's isolation forks,
// and a fork of a process that runs Python (whose other threads, NumPy's BLAS
// pools among them, do not survive it) is not safe. A Python exception is an
// ERROR row; a crash inside an extension the callable uses takes the
// interpreter down, as it would without warpcheck.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <sstream>
#include <thread>

#include <fmt/format.h>

#include "reports/outputs.h"
#include "reports/render.h"
#include "reports/terminal_table.h"
#include "validate/cli/cli_input.h"
#include "validate/python/python_cases.h"
#include "validate/run/run_digest.h"
#include "validate/run/runner.h"
#include "validate/samples/replay_run.h"
#include "validate/samples/sample_arrays.h"
#include "validate/samples/sample_set.h"
#include "validate/samples/two_sample_comparison.h"
#include "validate/samples/ulp_comparison.h"
#include "warpcheck/version.h"

namespace warpcheck::python {
namespace {

/// The settings of a run, as Python gives them (the package fills in the
/// WARPCHECK_* variables and the defaults).
struct Settings {
    uint64_t seed = 1;
    uint64_t samples = 1'000'000;
    unsigned threads = 0;
    double alpha = 0.01;
    bool strict = false;
    bool exhaustive = false;
    double time_budget = 0.0;  ///< 0: the default

    RunOptions options() const {
        const ParsedCount count = parse_count_in(std::to_string(samples), kMinSamples, kMaxSamples);
        if (!count.problem.empty()) throw py::value_error("samples: " + count.problem);
        if (!(alpha >= kMinAlpha && alpha <= kMaxAlpha))
            throw py::value_error(fmt::format("alpha: {} is out of range: from {} to {}", alpha, format_limit(kMinAlpha),
                                              format_limit(kMaxAlpha)));
        if (threads > 1024) throw py::value_error(fmt::format("threads: {} is out of range: from 0 to 1024", threads));
        RunOptions o;
        o.seed = seed;
        o.samples = samples;
        o.threads = threads;
        o.alpha = alpha;
        o.strict = strict;
        o.exhaustive = exhaustive;
        o.program = "python";
        if (time_budget > 0.0) o.check_time_budget = time_budget, o.time_budget_set = true;
        return o;
    }
};

/// The registry of the built-in warps, made once.
const Registry& builtin_registry() {
    static const Registry registry = [] {
        Registry r;
        register_builtin_cases(r);
        register_builtin_checks(r);
        register_flawed_interval_cases(r);
        return r;
    }();
    return registry;
}

std::vector<std::string> check_names() {
    std::vector<std::string> names;
    for (const auto& c : builtin_registry().checks()) names.push_back(c->name());
    return names;
}

/// A registry of the specs' cases and the built-in checks.
std::unique_ptr<Registry> registry_of(const std::vector<std::shared_ptr<CaseSpec>>& specs) {
    auto registry = std::make_unique<Registry>();
    register_builtin_checks(*registry);
    for (const auto& spec : specs) {
        if (!spec) throw py::value_error("cases: None is not a case");
        for (auto& c : spec->make()) registry->add_case(std::move(c));
    }
    return registry;
}

/// Raises KeyboardInterrupt if one reached a callable during the run.
void raise_if_interrupted() {
    if (!interrupted()) return;
    reset_interrupted();
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
}

/// Runs jobs with the GIL released: the check threads take it for each call.
template <typename F>
auto without_gil(F&& f) {
    reset_interrupted();
    decltype(f()) result;
    {
        const py::gil_scoped_release release;
        result = f();
    }
    raise_if_interrupted();
    return result;
}

std::vector<Job> jobs_of(const Registry& registry, const std::vector<std::string>& filters,
                         const std::vector<std::string>& checks, const RunOptions& options) {
    for (const std::string& name : checks)
        if (!registry.find_check(name)) {
            std::string list;
            for (const std::string& n : check_names()) list += " " + n;
            throw py::value_error(fmt::format("unknown check '{}'{}; the checks are:{}", name,
                                              did_you_mean(closest_names(name, check_names())), list));
        }
    for (const std::string& pattern : filters) {
        bool any = false;
        for (const auto& c : registry.cases()) any = any || name_matches(c->name(), pattern);
        if (!any) throw py::value_error(fmt::format("no case matches the filter '{}'", pattern));
    }
    return select_jobs(registry, filters, checks, options);
}

RunResult finish(RunResult run, const std::string& command) {
    run.info.command_line = command;
    run.info.tool_version = WARPCHECK_VERSION;
    std::vector<JobName> names;
    for (const CheckResult& r : run.results) names.push_back({r.case_name, r.check_name});
    seal_run(run, names);
    return run;
}

RunResult run_cases(const std::vector<std::shared_ptr<CaseSpec>>& specs, const std::vector<std::string>& filters,
                    const std::vector<std::string>& checks, const Settings& settings, const std::string& command) {
    const RunOptions options = settings.options();
    const std::unique_ptr<Registry> registry = registry_of(specs);
    const std::vector<Job> jobs = jobs_of(*registry, filters, checks, options);
    RunResult run = without_gil([&] { return run_jobs(jobs, options, {}, Isolation{}); });
    return finish(std::move(run), command);
}

/// The one case a spec makes (the sample-from-elsewhere functions take one).
const WarpCase& single_case(const Registry& registry, const char* function) {
    if (registry.cases().size() != 1)
        throw py::value_error(fmt::format("{} takes one case; this one makes {} (one per grid point): pass one of them",
                                          function, registry.cases().size()));
    if (as_bsdf(*registry.cases().front()))
        throw py::value_error(fmt::format("{} takes a warp or a light, not a BSDF", function));
    return *registry.cases().front();
}

py::tuple record_inputs(const std::shared_ptr<CaseSpec>& spec, const std::vector<std::string>& checks,
                        const Settings& settings, const std::string& command) {
    const RunOptions options = settings.options();
    const std::unique_ptr<Registry> registry = registry_of({spec});
    const WarpCase& warp = single_case(*registry, "record_inputs");
    const std::vector<Job> jobs = jobs_of(*registry, {}, checks, options);
    Recording rec = without_gil([&] { return record_run(warp, jobs, options); });
    NumericArray outputs = array_of(rec.samples.outputs, std::max(1, warp.signature().output_dimension));
    py::object values = py::none();
    if (rec.samples.values) {
        py::array_t<double> v(static_cast<py::ssize_t>(rec.samples.values->size()));
        std::copy(rec.samples.values->begin(), rec.samples.values->end(), v.mutable_data());
        values = std::move(v);
    }
    return py::make_tuple(finish(std::move(rec.run), command), to_numpy(array_of(rec.samples.inputs, warp.input_kind())),
                          to_numpy(outputs), values);
}

RunResult replay(const std::shared_ptr<CaseSpec>& spec, const py::handle& inputs, const py::handle& outputs,
                 const py::handle& values, const std::vector<std::string>& checks, const Settings& settings,
                 const std::string& command) {
    const RunOptions options = settings.options();
    const std::unique_ptr<Registry> registry = registry_of({spec});
    const WarpCase& warp = single_case(*registry, "replay");
    RecordedSamples table;
    table.inputs = inputs_of(numeric_array(inputs, "inputs"), warp.input_kind(), "inputs");
    table.outputs = outputs_of(numeric_array(outputs, "outputs"), std::max(1, warp.signature().output_dimension), "outputs");
    if (!values.is_none()) {
        const NumericArray v = numeric_array(values, "values");
        if (!v.is_real() || v.cols != 1) throw py::value_error("values: give one value per output, shape (n,)");
        table.values = v.reals;
    }
    if (table.inputs.size() != table.outputs.size())
        throw py::value_error(fmt::format("{} inputs but {} outputs: one output per input, row for row",
                                          table.inputs.size(), table.outputs.size()));
    const std::vector<Job> jobs = jobs_of(*registry, {}, checks, options);
    RunResult run = without_gil([&] { return replay_run(warp, std::move(table), jobs, options); });
    return finish(std::move(run), command);
}

RunResult judge_samples(const std::shared_ptr<CaseSpec>& spec, const py::handle& samples, const Settings& settings,
                        const std::string& command) {
    const RunOptions options = settings.options();
    const std::unique_ptr<Registry> registry = registry_of({spec});
    const WarpCase& warp = single_case(*registry, "judge_samples");
    const std::vector<WarpOutput> x =
        outputs_of(numeric_array(samples, "samples"), std::max(1, warp.signature().output_dimension), "samples");
    std::vector<CheckResult> rows = without_gil([&] { return judge_sample_set(warp, x, options); });
    return run_of_rows(std::move(rows), options, command);
}

/// The outputs of two arrays of one dimension: the case's, or the arrays' columns.
int dimension_of(const NumericArray& a, const WarpCase* warp) {
    return warp ? std::max(1, warp->signature().output_dimension) : static_cast<int>(a.cols);
}

RunResult compare(const py::handle& a, const py::handle& b, uint64_t max_ulps, float floor, const py::handle& inputs,
                  const std::shared_ptr<CaseSpec>& spec, const std::string& label_a, const std::string& label_b,
                  const std::string& command) {
    const std::unique_ptr<Registry> registry = spec ? registry_of({spec}) : nullptr;
    const WarpCase* warp = registry ? &single_case(*registry, "compare_same_inputs") : nullptr;
    const NumericArray na = numeric_array(a, label_a), nb = numeric_array(b, label_b);
    UlpComparison how;
    how.max_ulps = max_ulps;
    if (!(floor >= 0.0f)) throw py::value_error("floor: give 0 (the float grid) or a positive scale");
    how.floor = floor;
    how.dimension = dimension_of(na, warp);
    how.label_a = label_a;
    how.label_b = label_b;
    std::vector<WarpInput> in;
    if (!inputs.is_none()) {
        const NumericArray u = numeric_array(inputs, "inputs");
        how.input_kind = warp ? warp->input_kind()
                         : u.type == ElementType::UInt32 ? InputKind::Bits32
                         : u.type == ElementType::UInt64 ? InputKind::Bits64
                         : u.cols == 2                   ? InputKind::Uniform2D
                         : u.cols == 3                   ? InputKind::Uniform3D
                                                         : InputKind::Uniform1D;
        in = inputs_of(u, how.input_kind, "inputs");
        how.inputs = in;
    }
    const auto xa = outputs_of(na, how.dimension, label_a), xb = outputs_of(nb, how.dimension, label_b);
    CheckResult r = compare_same_inputs(xa, xb, how);
    r.case_name = warp ? warp->name() : label_a + " vs " + label_b;
    RunOptions options;
    return run_of_rows({std::move(r)}, options, command);
}

RunResult two_sample(const py::handle& a, const py::handle& b, const std::shared_ptr<CaseSpec>& spec,
                     const std::optional<chi2::Domain>& domain, const std::string& label_a, const std::string& label_b,
                     const Settings& settings, const std::string& command) {
    const RunOptions options = settings.options();
    const std::unique_ptr<Registry> registry = spec ? registry_of({spec}) : nullptr;
    const WarpCase* warp = registry ? &single_case(*registry, "two_sample") : nullptr;
    const NumericArray na = numeric_array(a, label_a), nb = numeric_array(b, label_b);
    TwoSampleComparison how;
    how.domain = warp ? std::optional(warp->domain()) : domain;
    how.dimension = dimension_of(na, warp);
    how.label_a = label_a;
    how.label_b = label_b;
    const auto xa = outputs_of(na, how.dimension, label_a), xb = outputs_of(nb, how.dimension, label_b);
    CheckResult r = without_gil([&] { return compare_independent(xa, xb, how, options); });
    r.case_name = warp ? warp->name() : label_a + " vs " + label_b;
    return run_of_rows({std::move(r)}, options, command);
}

/// Seconds to warp n inputs of the case's kind in batches of `batch`, through
/// WarpCase::sample as the checks call it (inputs drawn before the clock starts).
double sample_seconds(const std::shared_ptr<CaseSpec>& spec, std::size_t n, std::size_t batch) {
    const std::unique_ptr<Registry> registry = registry_of({spec});
    const WarpCase& warp = single_case(*registry, "sample_seconds");
    std::vector<WarpInput> in(n);
    Pcg32 rng(7, 1);
    draw_inputs(rng, warp.input_kind(), in);
    std::vector<WarpOutput> out(n);
    return without_gil([&] {
        const auto start = std::chrono::steady_clock::now();
        for (std::size_t first = 0; first < n; first += batch) {
            const std::size_t m = std::min(batch, n - first);
            warp.sample(std::span(in).subspan(first, m), std::span(out).subspan(first, m));
        }
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    });
}

}  // namespace

void bind_cases(py::module_& m);
void bind_results(py::module_& m);

}  // namespace warpcheck::python

PYBIND11_MODULE(_warpcheck, m) {
    namespace py = pybind11;
    using namespace warpcheck::python;
    py::module_::import("numpy");  // the array API, loaded before any check thread needs it
    m.doc() = "warpcheck's C++ core; use the package warpcheck (validate/python/README.md)";
    m.attr("__version__") = WARPCHECK_VERSION;
    py::class_<Settings>(m, "Settings")
        .def(py::init<>())
        .def_readwrite("seed", &Settings::seed)
        .def_readwrite("samples", &Settings::samples)
        .def_readwrite("threads", &Settings::threads)
        .def_readwrite("alpha", &Settings::alpha)
        .def_readwrite("strict", &Settings::strict)
        .def_readwrite("exhaustive", &Settings::exhaustive)
        .def_readwrite("time_budget", &Settings::time_budget);
    bind_cases(m);
    bind_results(m);
    m.def("check_names", &check_names, "The names of the checks, in the order they run");
    m.def("builtin_case_names", [] {
        std::vector<std::string> names;
        for (const auto& c : builtin_registry().cases())
            if (!warpcheck::as_bsdf(*c)) names.push_back(c->name());
        return names;
    });
    m.def("builtin_case", [](const std::string& name) {
        const warpcheck::WarpCase* c = builtin_registry().find_case(name);
        if (!c || warpcheck::as_bsdf(*c)) throw py::value_error("no built-in warp case is named '" + name + "'");
        return std::shared_ptr<CaseSpec>(std::make_shared<RegisteredSpec>(*c));
    });
    m.def("run", &run_cases, py::arg("cases"), py::arg("filters"), py::arg("checks"), py::arg("settings"),
          py::arg("command"));
    m.def("record_inputs", &record_inputs, py::arg("case"), py::arg("checks"), py::arg("settings"), py::arg("command"));
    m.def("replay", &replay, py::arg("case"), py::arg("inputs"), py::arg("outputs"), py::arg("values"),
          py::arg("checks"), py::arg("settings"), py::arg("command"));
    m.def("judge_samples", &judge_samples, py::arg("case"), py::arg("samples"), py::arg("settings"), py::arg("command"));
    m.def("compare_same_inputs", &compare, py::arg("a"), py::arg("b"), py::arg("max_ulps"), py::arg("floor"),
          py::arg("inputs"),
          py::arg("case"), py::arg("label_a"), py::arg("label_b"), py::arg("command"));
    m.def("two_sample", &two_sample, py::arg("a"), py::arg("b"), py::arg("case"), py::arg("domain"),
          py::arg("label_a"), py::arg("label_b"), py::arg("settings"), py::arg("command"));
    m.def("sample_seconds", &sample_seconds, py::arg("case"), py::arg("n"), py::arg("batch") = 65536);
}
