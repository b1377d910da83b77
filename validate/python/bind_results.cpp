// The result model in Python: a Run (RunResult) and its rows (CheckResult),
// with the same table, JSON, JUnit XML and HTML as validate writes.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <sstream>
#include <string>

#include "reports/outputs.h"
#include "reports/render.h"
#include "reports/result.h"
#include "reports/terminal_table.h"

namespace warpcheck::python {

namespace py = pybind11;

namespace {

std::string verdict_name(Verdict v) { return std::string(EnumNames<Verdict>::names[static_cast<std::size_t>(v)]); }

std::string table_of(const RunResult& run, std::size_t width, bool failures_only) {
    std::ostringstream out;
    TableStyle style;
    style.width = width;
    style.failures_only = failures_only;
    style.families = false;
    print_table(run, out, style);
    return out.str();
}

void bind_row(py::module_& m) {
    py::class_<CheckResult>(m, "Row", "One (case, check) row of a run")
        .def_readonly("case", &CheckResult::case_name)
        .def_readonly("check", &CheckResult::check_name)
        .def_property_readonly("verdict", [](const CheckResult& r) { return verdict_name(r.verdict); },
                               "'pass', 'fail', 'error' or 'not_applicable'")
        .def_property_readonly("passed", [](const CheckResult& r) { return r.verdict == Verdict::Pass; })
        .def_readonly("summary", &CheckResult::summary)
        .def_readonly("message", &CheckResult::message)
        .def_readonly("p_value", &CheckResult::p_value)
        .def_readonly("level", &CheckResult::level)
        .def_readonly("samples", &CheckResult::samples)
        .def_readonly("seconds", &CheckResult::seconds)
        .def_readwrite("rerun_command", &CheckResult::rerun_command)
        .def_property_readonly("figures",
                               [](const CheckResult& r) {
                                   py::dict d;
                                   for (const Figure& f : r.figures) d[py::str(f.name)] = f.value;
                                   return d;
                               })
        .def("__repr__", [](const CheckResult& r) {
            return "<Row " + verdict_name(r.verdict) + " " + r.check_name + " " + r.case_name + ": " + r.summary + ">";
        });
}

}  // namespace

void bind_results(py::module_& m) {
    bind_row(m);
    py::class_<RunResult>(m, "Run", "The results of a run: its rows and its settings")
        .def_property_readonly("rows",
                               [](py::object self) {
                                   auto& run = self.cast<RunResult&>();
                                   py::list rows;
                                   for (CheckResult& r : run.results)
                                       rows.append(py::cast(&r, py::return_value_policy::reference_internal, self));
                                   return rows;
                               })
        .def_property_readonly("passed", &RunResult::all_passed,
                               "Whether every row that applies passed (n/a rows neither pass nor fail)")
        .def_property_readonly("seed", [](const RunResult& r) { return r.info.seed; })
        .def_property_readonly("samples", [](const RunResult& r) { return r.info.samples; })
        .def_property_readonly("per_test_alpha", [](const RunResult& r) { return r.info.per_test_alpha; })
        .def_property_readonly("command_line", [](const RunResult& r) { return r.info.command_line; })
        .def("table", &table_of, py::arg("width") = 0, py::arg("failures_only") = false,
             "The table validate prints, with the failures and their rerun commands")
        .def("json", &render_json)
        .def("html", &render_html)
        .def("junit", &render_junit)
        .def("write_json", &write_json_report, py::arg("path"))
        .def("write_html", &write_html_report, py::arg("path"))
        .def("write_junit", &write_junit_report, py::arg("path"));
}

}  // namespace warpcheck::python
