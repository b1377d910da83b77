// A stand-in for a GPU: a separate program that reads the inputs warpcheck
// recorded (a .npy file), runs its build of a warp over them, and writes its
// outputs as a .npy file for validate to judge (validate/samples/README.md has the
// recipe a CUDA kernel or a shader follows). Or it draws its own inputs with
// its own generator, as a device does for independent draws. It links nothing
// of warpcheck: the warp's header and the few lines of .npy below are all a
// device's host code needs.
//
//   device_standin BUILD INPUTS.npy OUTPUTS.npy
//   device_standin BUILD --draw N --seed S OUTPUTS.npy
//
// BUILD: normal (as warpcheck compiles the warp), fastmath (-ffast-math),
// fma (-ffast-math -mfma, where the processor has FMA; otherwise fastmath, said
// on standard error), double (the warp in double), error1pct (the normal
// build with a 1% error: u.x scaled by 0.99).
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

void warp_normal(const float* u, float* x, std::size_t n);
void warp_fastmath(const float* u, float* x, std::size_t n);
void warp_double(const float* u, float* x, std::size_t n);
#if defined(WARPCHECK_HAS_FMA_BUILD)
void warp_fma(const float* u, float* x, std::size_t n);
#endif

namespace {

/// Reads a float32 .npy file of shape (n, cols), C order, little-endian.
std::vector<float> read_npy(const std::string& path, std::size_t cols) {
    std::ifstream in(path, std::ios::binary);
    char preamble[10];
    if (!in.read(preamble, 10) || std::memcmp(preamble, "\x93NUMPY", 6) != 0 || preamble[6] != 1)
        throw std::runtime_error(path + " is not a version 1 .npy file");
    const std::size_t header_length =
        static_cast<unsigned char>(preamble[8]) | static_cast<std::size_t>(static_cast<unsigned char>(preamble[9])) << 8;
    std::string header(header_length, ' ');
    in.read(header.data(), static_cast<std::streamsize>(header_length));
    std::size_t rows = 0, columns = 0;
    const std::size_t shape = header.find("'shape': (");
    if (header.find("'<f4'") == std::string::npos || header.find("'fortran_order': False") == std::string::npos ||
        shape == std::string::npos || std::sscanf(header.c_str() + shape + 10, "%zu, %zu", &rows, &columns) != 2 ||
        columns != cols)
        throw std::runtime_error(path + ": expected float32 of shape (n, " + std::to_string(cols) + ")");
    std::vector<float> data(rows * cols);
    if (!in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(data.size() * sizeof(float))))
        throw std::runtime_error(path + " is cut short");
    return data;
}

/// Writes float32 (n, cols) as a .npy file.
void write_npy(const std::string& path, const std::vector<float>& data, std::size_t cols) {
    std::ostringstream h;
    h << "{'descr': '<f4', 'fortran_order': False, 'shape': (" << data.size() / cols << ", " << cols << "), }";
    std::string header = h.str();
    header.append(64 - (10 + header.size() + 1) % 64, ' ');  // the preamble and header fill 64-byte lines
    header.push_back('\n');
    std::ofstream out(path, std::ios::binary);
    out.write("\x93NUMPY\x01\x00", 8);
    out.put(static_cast<char>(header.size() & 0xff)).put(static_cast<char>(header.size() >> 8));
    out << header;
    out.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size() * sizeof(float)));
    if (!out) throw std::runtime_error("cannot write " + path);
}

using Kernel = void (*)(const float*, float*, std::size_t);

Kernel kernel_of(const std::string& build) {
    if (build == "normal" || build == "error1pct") return warp_normal;
    if (build == "fastmath") return warp_fastmath;
    if (build == "double") return warp_double;
    if (build == "fma") {
#if defined(WARPCHECK_HAS_FMA_BUILD)
        if (__builtin_cpu_supports("fma")) return warp_fma;
#endif
        std::cerr << "device_standin: no FMA on this processor or compiler: the fastmath build stands in\n";
        return warp_fastmath;
    }
    throw std::runtime_error("unknown build '" + build + "': normal, fastmath, fma, double or error1pct");
}

/// Inputs from the device's own generator (not warpcheck's): 24-bit floats of [0, 1).
std::vector<float> draw(std::size_t n, uint64_t seed) {
    std::mt19937_64 generator(seed);
    std::vector<float> u(2 * n);
    for (float& v : u) v = static_cast<float>(generator() >> 40) * 0x1p-24f;
    return u;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const std::vector<std::string> args(argv + 1, argv + argc);
        std::vector<float> u;
        std::string out;
        if (args.size() == 3) {
            u = read_npy(args[1], 2);
            out = args[2];
        } else if (args.size() == 6 && args[1] == "--draw" && args[3] == "--seed") {
            u = draw(std::stoull(args[2]), std::stoull(args[4]));
            out = args[5];
        } else {
            std::cerr << "usage: device_standin BUILD INPUTS.npy OUTPUTS.npy\n"
                         "       device_standin BUILD --draw N --seed S OUTPUTS.npy\n";
            return 2;
        }
        const Kernel kernel = kernel_of(args[0]);
        if (args[0] == "error1pct")
            for (std::size_t i = 0; i < u.size(); i += 2) u[i] *= 0.99f;
        std::vector<float> x(u.size() / 2 * 3);
        kernel(u.data(), x.data(), u.size() / 2);
        write_npy(out, x, 3);
    } catch (const std::exception& e) {
        std::cerr << "device_standin: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
