// Registering warps from a C++17 translation unit. warpcheck's own headers are
// C++20; a renderer that compiles as C++17 includes only this header (which
// is C++17 and includes nothing else of warpcheck) in its own files, links
// warpcheck::main as usual (the program's main() and the checks are compiled as
// C++20), and defines warpcheck_register with the functions below:
//
//     #include <validate/api/register17.h>
//     void warpcheck_register(warpcheck::Registry& registry) {
//         warpcheck::cxx17::add_case(registry, info, sample, pdf, invert);
//     }
//
// The warp is given as callables over plain arrays; the same checks, options
// and reports apply as to a case made with make_warp_case. In CMake, link the
// C++17 files' target to warpcheck::register17 (include path only) and the
// program to warpcheck::main.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace warpcheck {
class Registry;  // defined in validate/api/registry.h (C++20); only referred to here
}  // namespace warpcheck

/// Defined by the program that links warpcheck::main (as in validate/api/external.h).
void warpcheck_register(warpcheck::Registry& registry);

namespace warpcheck::cxx17 {

/// What a warp consumes: uniform floats in [0,1) (one or two), or raw bits.
enum class Input { Uniform1D, Uniform2D, Bits32, Bits64 };

/// One input: u[0..1] for uniform inputs, `bits` for raw bits.
struct WarpInput {
    std::array<float, 2> u{};
    std::uint64_t bits = 0;
};

/// One output point: x; (x, y); or a direction (x, y, z). Unused coordinates are 0.
using Point = std::array<float, 3>;

/// The domain and the measure the pdf is a density of.
struct Domain {
    enum class Kind {
        Interval,       ///< [a, b], length
        HalfLine,       ///< [a, inf), length
        LowerHalfLine,  ///< (-inf, b], length
        RealLine,       ///< (-inf, inf), length
        Box,            ///< [a, b] x [c, d], area
        UnitDisk,       ///< area
        SphericalCap,   ///< directions with z >= c (sphere: c = -1, hemisphere: 0), solid angle
    };
    Kind kind = Kind::Interval;
    double a = 0.0, b = 1.0, c = 0.0, d = 1.0;

    static Domain interval(double lo, double hi) { return {Kind::Interval, lo, hi, 0.0, 0.0}; }
    static Domain half_line(double lo) { return {Kind::HalfLine, lo, 0.0, 0.0, 0.0}; }
    static Domain lower_half_line(double hi) { return {Kind::LowerHalfLine, 0.0, hi, 0.0, 0.0}; }
    static Domain real_line() { return {Kind::RealLine, 0.0, 0.0, 0.0, 0.0}; }
    static Domain box(double x0, double x1, double y0, double y1) { return {Kind::Box, x0, x1, y0, y1}; }
    static Domain unit_square() { return box(0.0, 1.0, 0.0, 1.0); }
    static Domain unit_disk() { return {Kind::UnitDisk, 0.0, 0.0, 0.0, 0.0}; }
    static Domain spherical_cap(double z_min) { return {Kind::SphericalCap, 0.0, 0.0, z_min, 0.0}; }
    static Domain sphere() { return spherical_cap(-1.0); }
    static Domain hemisphere() { return spherical_cap(0.0); }
};

/// A monotone 1D view of the warp for the tabulated check (validate/api/warp_case.h,
/// MonotoneMarginal, says what each field means).
struct View {
    int input_coordinate = 0;
    bool increasing = true;
    double lo = 0.0, hi = 1.0;
    double tail_mass = 0.0;        ///< probability above hi
    double lower_tail_mass = 0.0;  ///< probability below lo
    std::string label;
    std::function<double(const Point&)> coordinate;  ///< empty: x
    std::function<double(double)> pdf;               ///< empty: the warp's pdf (1D warps)
};

/// Whether sample is the inversion method (WarpCaseInfo::inversion says what each means).
enum class Inversion { Measure, Claimed, NotInversion };

/// The case's name, description, input, domain and views (WarpCaseInfo).
struct CaseInfo {
    std::string family;
    std::vector<std::pair<std::string, double>> params;
    std::string description;
    Input input = Input::Uniform2D;
    Domain domain = Domain::unit_square();
    double roundtrip_tolerance = 1.0 / 65536.0;
    std::vector<View> views;
    Inversion inversion = Inversion::Measure;
};

using SampleFn = std::function<Point(const WarpInput&)>;
using PdfFn = std::function<double(const Point&)>;
/// Empty: the warp has no inverse, and its round-trip checks are not applicable.
using InvertFn = std::function<WarpInput(const Point&)>;

/// Adds a case to the registry, validated as Registry::add_case validates
/// (an inconsistent declaration throws std::invalid_argument naming the case).
void add_case(Registry& registry, const CaseInfo& info, SampleFn sample, PdfFn pdf, InvertFn invert = {});

/// A BSDF's or phase function's sample as a renderer returns it (pbrt-v4's
/// BSDFSample): the direction wi, f(wo, wi) (for a delta lobe the value whose
/// f |cos theta_i| / pdf is the weight), the pdf (for a delta lobe the
/// probability of choosing it; 0: no sample), its lobe, and for transmission
/// eta(wi's side) / eta(wo's side). Directions in the shading frame, z the normal.
struct BsdfSample {
    Point wi{};
    float f = 0.0f;
    float pdf = 0.0f;
    bool transmission = false;  ///< wi on the other side of the surface
    bool delta = false;         ///< a delta lobe (mirror, smooth refraction)
    float eta = 1.0f;
};

/// A BSDF case: its name, the outgoing direction wo it is checked at, and what
/// it claims (BsdfClaims in validate/bsdf/bsdf_case.h says what each means).
struct BsdfInfo {
    std::string family;
    std::vector<std::pair<std::string, double>> params;
    std::string description;
    Point wo{0.0f, 0.0f, 1.0f};  ///< unit length, off the horizon
    bool reflection = true, transmission = false;  ///< the sides it samples
    bool continuous = true, delta = false;         ///< lobes with a density, delta lobes
    bool reciprocal = true;      ///< f(wo, wi) = f(wi, wo) (the eta^2 rule across an interface)
    bool importance = false;     ///< transmitted f without the 1 / eta^2 of radiance
    float eta = 1.0f;            ///< index below the surface over above
    bool phase_function = false; ///< wi on the whole sphere, weight p / pdf (no cosine)
};

/// sample(wo, uc, u): uc chooses the lobe, u = (u1, u2) the direction.
using BsdfSampleFn = std::function<BsdfSample(const Point& wo, float uc, const std::array<float, 2>& u)>;
/// f(wo, wi) or pdf(wo, wi).
using BsdfEvalFn = std::function<double(const Point& wo, const Point& wi)>;

/// Adds a BSDF case that the BSDF checks take (bsdf_chi2, bsdf_weight,
/// bsdf_delta, bsdf_albedo, bsdf_reciprocity); validated as make_bsdf_case
/// validates (a bad wo or no lobes throws std::invalid_argument naming it).
void add_bsdf(Registry& registry, const BsdfInfo& info, BsdfSampleFn sample, BsdfEvalFn f, BsdfEvalFn pdf);

/// The outgoing direction at theta degrees from the normal and azimuth phi degrees.
Point bsdf_direction(double theta_degrees, double phi_degrees = 0.0);

/// Registry::mark_known_flaw for one check of a case ("" for the whole case).
void mark_known_flaw(Registry& registry, const std::string& case_name, const std::string& check_name,
                     const std::string& flaw);

}  // namespace warpcheck::cxx17
