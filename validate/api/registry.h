// The registry: which warp cases exist and which checks run on them.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "validate/api/case_family.h"
#include "validate/api/warp_case.h"

namespace warpcheck {

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
