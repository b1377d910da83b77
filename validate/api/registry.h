// The registry: which warp cases exist and which checks run on them.
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "validate/api/warp_case.h"

namespace warpcheck {

// A family of cases: one warp (or BSDF, or light) made at any point of its
// parameters. A grid registers the family's chosen points (case_grid.h); the
// family itself, kept by the registry, lets --fuzz make cases at the ends of
// the ranges its axes declare and anywhere between (validate/run/fuzz.h).

/// The values a parameter may take beyond its grid, as the family declares
/// them: [lo, hi], each end included unless it is open (an open end is
/// approached, never reached: roughness 0 that the constructor refuses, g = 1).
/// Unset (the default): the axis takes its grid values only.
struct ParamRange {
    double lo = std::numeric_limits<double>::quiet_NaN();
    double hi = std::numeric_limits<double>::quiet_NaN();
    bool lo_open = false;
    bool hi_open = false;
    bool declared() const { return std::isfinite(lo) && std::isfinite(hi) && lo <= hi; }
    /// Whether v lies in the range, open ends excluded (NaN is in no range).
    bool contains(double v) const {
        return declared() && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
    }
};

/// One parameter of a grid, the values it takes, in order, and (where the
/// family declares them) the ranges --fuzz draws it from: one, or several
/// where a value between them is refused by design (theta_o = 90, wo on the
/// horizon, between [0, 90) and (90, 180]).
struct GridAxis {
    std::string name;
    std::vector<double> values;
    std::vector<ParamRange> ranges{};
};

/// One point of a grid: its parameters in axis order, looked up by name.
class GridPoint {
public:
    explicit GridPoint(std::vector<Parameter> params) : params_(std::move(params)) {}
    /// The value of the named axis; an unknown name is a std::invalid_argument.
    double operator[](std::string_view name) const {
        for (const Parameter& p : params_)
            if (p.name == name) return p.value;
        throw std::invalid_argument("grid point has no parameter " + std::string(name));
    }
    const std::vector<Parameter>& params() const { return params_; }

private:
    std::vector<Parameter> params_;
};

/// Makes the case of one grid point from `info` (the base info with the
/// point's parameters appended to its params, so the name is stable) and the
/// point: make_warp_case, make_bsdf_case or any other maker of a case.
using GridCaseMaker = std::function<std::unique_ptr<WarpCase>(WarpCaseInfo info, const GridPoint& point)>;

/// A family as its grid registered it: the base description, the axes and the maker.
struct CaseFamily {
    WarpCaseInfo base;
    std::vector<GridAxis> axes;
    GridCaseMaker make;
    /// Whether any axis declares a range (only such a family has anything to fuzz).
    bool fuzzable() const {
        for (const GridAxis& a : axes)
            if (!a.ranges.empty()) return true;
        return false;
    }
};

/// A check (validate/checks/check.h, private to warpcheck): the registry holds
/// the checks that run, and names them, without a renderer seeing their interface.
class Check;

class Registry {
public:
    /// Adds a case; a second case with the same name is an error (names are how
    /// streams are seeded and how --filter finds a case), and so is a case
    /// declared inconsistently (validate_case in warp_case.h): the message names
    /// the case and every problem.
    void add_case(std::unique_ptr<WarpCase> warp);
    /// Adds a check (a class derived from Check); a second check of one name is an error.
    template <typename C>
    void add_check(std::unique_ptr<C> check) {
        if (!check) throw std::invalid_argument("registry: null check");
        std::string name = check->name();
        add_named_check(std::move(name), std::shared_ptr<const Check>(std::move(check)));
    }

    /// Keeps a family (add_case_grid does, after its cases): --fuzz makes its
    /// cases at other points of the ranges its axes declare. A second family
    /// of one name is an error.
    void add_family(CaseFamily family);
    const std::vector<CaseFamily>& families() const { return families_; }
    const CaseFamily* find_family(std::string_view family) const;

    /// Adds a check another registry holds, by its name there (a registry of
    /// cases made for one run, such as --fuzz-case's, with the checks of the
    /// one it came from); a second check of one name is an error.
    void add_named_check(std::string name, std::shared_ptr<const Check> check);

    const std::vector<std::unique_ptr<WarpCase>>& cases() const { return cases_; }
    /// Hands the registered cases over, leaving none (a family's maker that
    /// registers its point's case into a registry of its own, as the C++17
    /// grids do, takes it back out).
    std::vector<std::unique_ptr<WarpCase>> take_cases() { return std::exchange(cases_, {}); }
    const std::vector<std::shared_ptr<const Check>>& checks() const { return checks_; }
    const WarpCase* find_case(std::string_view name) const;
    const Check* find_check(std::string_view name) const;

    /// Marks a registered case as a demonstration of a known flaw (e.g. a float
    /// sampler that returns 1.0): it is expected to fail, so it runs only with
    /// --include-flawed or when selected by its full name.
    void mark_known_flaw(const std::string& case_name, std::string flaw);
    /// Marks one check of a registered case as a known flaw: only that check is
    /// expected to fail, so only it is left out (with the same exceptions); the
    /// case's other checks run as usual. The check must be registered.
    void mark_known_flaw(const std::string& case_name, const std::string& check_name, std::string flaw);
    /// The flaw of a whole case, or an empty string.
    std::string known_flaw(const WarpCase& warp) const;
    /// The flaw of one check (by its name) of a case: its own mark, else the
    /// whole case's, else empty.
    std::string known_flaw(const WarpCase& warp, std::string_view check_name) const;

private:

    struct Flaw {
        std::string case_name;
        std::string check_name;  ///< empty: the whole case
        std::string text;
    };
    std::vector<Flaw> flaws_;
    std::vector<CaseFamily> families_;
    std::vector<std::unique_ptr<WarpCase>> cases_;
    std::vector<std::shared_ptr<const Check>> checks_;
    std::vector<std::string> check_names_;  ///< checks_[i]'s name
};

/// Whether `name` matches `pattern`: a glob with * and ? when the pattern has
/// either, otherwise a substring match. "cone" matches every uniform_cone case;
/// "uniform_cone[cos_theta_max=0.3]" matches exactly that one.
bool name_matches(std::string_view name, std::string_view pattern);

// The warps and checks that ship with warpcheck.
/// Adds every built-in case: each file of validate/cases registers its family
/// with WARPCHECK_BUILTIN_CASES, and this calls them in order of their rank
/// (then of their name), so the output order does not depend on link order.
void register_builtin_cases(Registry& registry);
void register_builtin_checks(Registry& registry);

/// Idioms that fail by the rules (u * 2^-32 reaching 1.0, 23 random bits that
/// never reach 1 - 2^-24, lerps reaching b), registered and
/// marked as known flaws. Not part of register_builtin_cases, so that every
/// default check of every built-in case passes; validate adds them and runs
/// them with --include-flawed or when one is named in full.
void register_flawed_interval_cases(Registry& registry);

/// A known-bad BSDF (validate/cases/bsdf_flawed.cpp): how to make it, the
/// check meant to catch it, its bug in a few words, and the other checks its
/// bug rightly fails too (a wrong weight moves the mean weight, so the albedo
/// test fails with it); every other check that applies must pass.
struct FlawedBsdf {
    std::unique_ptr<WarpCase> (*make)();
    std::string caught_by;
    std::string flaw;
    std::vector<std::string> also_fails{};
};
/// The catalogue of known-bad BSDFs, one per bug renderers ship.
std::vector<FlawedBsdf> bsdf_flawed_catalogue();
/// Registers the catalogue, each marked as a known flaw (as
/// register_flawed_interval_cases).
void register_flawed_bsdf_cases(Registry& registry);

/// A known-bad light (validate/cases/light_flawed.cpp), described as a
/// known-bad BSDF is: how to make it, its check, its bug, what else it fails.
using FlawedLight = FlawedBsdf;
/// The catalogue of known-bad lights, one per bug class renderers have shipped.
std::vector<FlawedLight> light_flawed_catalogue();
/// The known-bad MIS cases (validate/cases/mis.cpp), the end of light_flawed_catalogue.
std::vector<FlawedLight> mis_flawed_catalogue();
/// Registers the catalogue, each marked as a known flaw.
void register_flawed_light_cases(Registry& registry);

namespace detail {
using RegisterCasesFn = void (*)(Registry&);
/// Records a family's registration function; called during static initialisation.
bool add_builtin_cases(int rank, const char* name, RegisterCasesFn fn);
}  // namespace detail

}  // namespace warpcheck

/// Registers a built-in family from its own file in validate/cases, e.g.
///   WARPCHECK_BUILTIN_CASES(30, register_linear_cases);
/// `rank` orders the families in register_builtin_cases (and so in the output):
/// the ranks 10..60 keep the historical order; a new family takes the next free one.
#define WARPCHECK_BUILTIN_CASES(rank, fn)                                        \
    [[maybe_unused]] static const bool warpcheck_builtin_cases_registered_##fn = \
        ::warpcheck::detail::add_builtin_cases(rank, #fn, fn)
