// Calling Python from the checks' threads: a Python callable held so that C++
// may copy it on any thread (the copy touches no Python reference count), called
// with the GIL taken, on NumPy arrays of a whole batch; what it returns checked
// for shape and element type, with a message that says what was expected; and a
// Python exception turned into a C++ one that the runner makes an ERROR row.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "validate/api/warp_case.h"
#include "validate/samples/sample_file.h"

namespace warpcheck::python {

namespace py = pybind11;

/// A Python object shared by C++ copies; released with the GIL taken.
class PyRef {
public:
    PyRef() = default;
    /// Holds `object` (None counts as not given). Call with the GIL held.
    explicit PyRef(py::object object);
    bool given() const { return holder_ != nullptr; }
    /// The object; use only with the GIL held.
    const py::object& get() const { return holder_->object; }

private:
    struct Holder {
        py::object object;
        explicit Holder(py::object o) : object(std::move(o)) {}
        ~Holder();
        Holder(const Holder&) = delete;
        Holder& operator=(const Holder&) = delete;
    };
    std::shared_ptr<Holder> holder_;
};

/// The GIL, taken for one call from any thread. pybind11's gil_scoped_acquire
/// makes a Python thread state on a thread that has none and deletes it again
/// when released, which cost ~15 us per call (a tabulated view's pdf is called
/// per value): a check's thread keeps the state it gets at its first call until
/// the thread ends.
class CallGil {
private:
    static void keep_thread_state();
    /// Constructed first: the state is kept before the GIL is taken.
    struct KeepThreadState {
        KeepThreadState() { keep_thread_state(); }
    };
    KeepThreadState keep_;
    py::gil_scoped_acquire gil_;
};

/// Thrown for a Python exception or a malformed return value inside a check:
/// the runner makes it an ERROR row with this message.
struct PythonCallError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Calls fn(args...) with the GIL held (the caller takes it); a Python
/// exception becomes a PythonCallError naming `what` ("cone[a=1]: sample"). A
/// KeyboardInterrupt is remembered (interrupted()) so that the run can raise it
/// once it is over.
template <typename... Args>
py::object call(const PyRef& fn, const std::string& what, Args&&... args);

/// Whether a KeyboardInterrupt reached a call since the last reset.
bool interrupted();
void reset_interrupted();
/// Records that one did (call does).
void note_interrupt();

/// A float32 array of the inputs: (n,) for 1D, (n, d) for d > 1; uint32 or
/// uint64 (n,) for raw bits.
py::array inputs_array(std::span<const WarpInput> in, InputKind kind);
/// A float32 array of points: (n,) for 1D, (n, d) otherwise.
py::array points_array(std::span<const WarpOutput> x, int dimension);

/// The values of a returned array-like, (n, cols) as doubles in C order,
/// checked: a NumPy array (or what numpy.asarray makes of it) of shape (n,
/// cols), or (n,) when cols is 1; floating point, or integer when `integer`
/// (indices, raw bits). `what` says what it should be, for the message.
std::vector<double> read_array(py::handle result, std::size_t n, std::size_t cols, const std::string& what,
                               bool integer = false);
/// The same for raw bits, exactly (uint64 holds what a double cannot).
std::vector<uint64_t> read_bits(py::handle result, std::size_t n, const std::string& what);

/// A NumPy array as a NumericArray (float32, float64, uint32, uint64; one or
/// two dimensions), or a ValueError saying what it is.
NumericArray numeric_array(py::handle array, const std::string& what);
/// A NumericArray as a NumPy array.
py::array to_numpy(const NumericArray& array);

// ---------------------------------------------------------------------------

template <typename... Args>
py::object call(const PyRef& fn, const std::string& what, Args&&... args) {
    try {
        py::object result = fn.get()(std::forward<Args>(args)...);
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        return result;
    } catch (py::error_already_set& e) {
        if (e.matches(PyExc_KeyboardInterrupt)) note_interrupt();
        throw PythonCallError(what + " raised " + e.what());
    }
}

}  // namespace warpcheck::python
