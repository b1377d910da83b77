#include "validate/python/python_calls.h"

#include <atomic>
#include <cstring>

#include <fmt/format.h>

namespace warpcheck::python {

namespace {
std::atomic<bool> g_interrupted{false};
}  // namespace

bool interrupted() { return g_interrupted.load(); }
void reset_interrupted() { g_interrupted = false; }
void note_interrupt() { g_interrupted = true; }

namespace {

/// A thread's Python state, kept from its first call until the thread ends,
/// for a thread that had none (not Python's own threads).
struct KeptThreadState {
    bool kept = false;
    KeptThreadState() {
        if (PyGILState_GetThisThreadState() != nullptr) return;
        py::gil_scoped_acquire gil;
        gil.inc_ref();  // one more holder than this scope: the state outlives it
        kept = true;
    }
    ~KeptThreadState() {
        if (!kept || !Py_IsInitialized() || _Py_IsFinalizing()) return;
        py::gil_scoped_acquire gil;
        gil.dec_ref();  // the holder the constructor added: the state goes with this scope
    }
    KeptThreadState(const KeptThreadState&) = delete;
    KeptThreadState& operator=(const KeptThreadState&) = delete;
};

}  // namespace

void CallGil::keep_thread_state() { thread_local const KeptThreadState state; }

PyRef::PyRef(py::object object) {
    if (!object.is_none()) holder_ = std::make_shared<Holder>(std::move(object));
}

PyRef::Holder::~Holder() {
    // The last C++ copy may go on a check's thread: the reference is dropped
    // with the GIL held, as Python requires.
    const CallGil gil;
    object = py::object();
}

py::array inputs_array(std::span<const WarpInput> in, InputKind kind) {
    const auto n = static_cast<py::ssize_t>(in.size());
    if (kind == InputKind::Bits32) {
        py::array_t<uint32_t> a(n);
        auto* p = a.mutable_data();
        for (std::size_t i = 0; i < in.size(); ++i) p[i] = static_cast<uint32_t>(in[i].bits);
        return a;
    }
    if (kind == InputKind::Bits64) {
        py::array_t<uint64_t> a(n);
        auto* p = a.mutable_data();
        for (std::size_t i = 0; i < in.size(); ++i) p[i] = in[i].bits;
        return a;
    }
    const int dims = input_dimension(kind);
    py::array_t<float> a = dims == 1 ? py::array_t<float>(n) : py::array_t<float>({n, static_cast<py::ssize_t>(dims)});
    float* p = a.mutable_data();
    for (std::size_t i = 0; i < in.size(); ++i)
        for (int c = 0; c < dims; ++c) p[i * static_cast<std::size_t>(dims) + static_cast<std::size_t>(c)] = in[i].u[static_cast<std::size_t>(c)];
    return a;
}

py::array points_array(std::span<const WarpOutput> x, int dimension) {
    const auto n = static_cast<py::ssize_t>(x.size());
    py::array_t<float> a =
        dimension == 1 ? py::array_t<float>(n) : py::array_t<float>({n, static_cast<py::ssize_t>(dimension)});
    float* p = a.mutable_data();
    const auto d = static_cast<std::size_t>(dimension);
    for (std::size_t i = 0; i < x.size(); ++i)
        for (std::size_t c = 0; c < d; ++c) p[i * d + c] = x[i][c];
    return a;
}

namespace {

std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s += fmt::format("{}{}", k ? ", " : "", a.shape(k));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

/// The array of a returned value, its shape checked.
py::array checked_array(py::handle result, std::size_t n, std::size_t cols, const std::string& what, bool integer) {
    py::array a;
    try {
        a = py::array::ensure(result);
    } catch (py::error_already_set&) {
    }
    if (!a) throw PythonCallError(fmt::format("{} returned a {}, not an array", what, py::str(result.get_type()).cast<std::string>()));
    const char kind = a.dtype().kind();
    const bool kind_ok = integer ? (kind == 'i' || kind == 'u') : kind == 'f';
    const bool shape_ok = (a.ndim() == 2 && static_cast<std::size_t>(a.shape(0)) == n &&
                           static_cast<std::size_t>(a.shape(1)) == cols) ||
                          (a.ndim() == 1 && cols == 1 && static_cast<std::size_t>(a.shape(0)) == n);
    if (!kind_ok || !shape_ok)
        throw PythonCallError(fmt::format("{} returned a {} array of shape {}; expected {} values of shape {}", what,
                                          a.dtype().attr("name").cast<std::string>(), shape_text(a),
                                          integer ? "integer" : "floating-point",
                                          cols == 1 ? fmt::format("({},)", n) : fmt::format("({}, {})", n, cols)));
    return a;
}

}  // namespace

std::vector<double> read_array(py::handle result, std::size_t n, std::size_t cols, const std::string& what,
                               bool integer) {
    const py::array a = checked_array(result, n, cols, what, integer);
    const auto values = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!values) throw py::error_already_set();
    return std::vector<double>(values.data(), values.data() + n * cols);
}

std::vector<uint64_t> read_bits(py::handle result, std::size_t n, const std::string& what) {
    const py::array a = checked_array(result, n, 1, what, true);
    const auto values = py::array_t<uint64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    if (!values) throw py::error_already_set();
    return std::vector<uint64_t>(values.data(), values.data() + n);
}

NumericArray numeric_array(py::handle object, const std::string& what) {
    const py::array a = py::array::ensure(object);
    if (!a) throw py::value_error(what + " is not an array");
    NumericArray out;
    const py::dtype t = a.dtype();
    if (t.is(py::dtype::of<float>())) out.type = ElementType::Float32;
    else if (t.is(py::dtype::of<double>())) out.type = ElementType::Float64;
    else if (t.is(py::dtype::of<uint32_t>())) out.type = ElementType::UInt32;
    else if (t.is(py::dtype::of<uint64_t>())) out.type = ElementType::UInt64;
    else if (t.kind() == 'f' || t.kind() == 'i' || t.kind() == 'u')
        throw py::value_error(fmt::format("{} is a {} array: give float32 or float64 samples (float32 inputs; uint32 "
                                          "or uint64 raw bits)",
                                          what, t.attr("name").cast<std::string>()));
    else throw py::value_error(fmt::format("{} is a {} array, not numbers", what, t.attr("name").cast<std::string>()));
    if (a.ndim() < 1 || a.ndim() > 2)
        throw py::value_error(fmt::format("{} has {} dimensions: give one row per sample, shape (n,) or (n, d)", what,
                                          a.ndim()));
    out.rows = static_cast<std::size_t>(a.shape(0));
    out.cols = a.ndim() == 2 ? static_cast<std::size_t>(a.shape(1)) : 1;
    out.one_dimensional = a.ndim() == 1;
    if (out.is_real()) {
        const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
        out.reals.assign(v.data(), v.data() + out.rows * out.cols);
    } else {
        const auto v = py::array_t<uint64_t, py::array::c_style | py::array::forcecast>::ensure(a);
        out.integers.assign(v.data(), v.data() + out.rows * out.cols);
    }
    return out;
}

py::array to_numpy(const NumericArray& a) {
    std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(a.rows)};
    if (!a.one_dimensional) shape.push_back(static_cast<py::ssize_t>(a.cols));
    const auto fill = [&](auto array, auto convert) {
        auto* p = array.mutable_data();
        for (std::size_t i = 0; i < a.rows * a.cols; ++i) p[i] = convert(i);
        return py::array(std::move(array));
    };
    switch (a.type) {
        case ElementType::Float32:
            return fill(py::array_t<float>(shape), [&](std::size_t i) { return static_cast<float>(a.reals[i]); });
        case ElementType::Float64: return fill(py::array_t<double>(shape), [&](std::size_t i) { return a.reals[i]; });
        case ElementType::UInt32:
            return fill(py::array_t<uint32_t>(shape), [&](std::size_t i) { return static_cast<uint32_t>(a.integers[i]); });
        case ElementType::UInt64: return fill(py::array_t<uint64_t>(shape), [&](std::size_t i) { return a.integers[i]; });
    }
    return py::array();
}

}  // namespace warpcheck::python
