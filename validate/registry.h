// The registry: which warp cases exist and which checks run on them.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "validate/check.h"
#include "validate/warp_case.h"

namespace warpcheck {

class Registry {
public:
    /// Adds a case; a second case with the same name is an error (names are how
    /// streams are seeded and how --filter finds a case).
    void add_case(std::unique_ptr<WarpCase> warp);
    void add_check(std::unique_ptr<Check> check);

    const std::vector<std::unique_ptr<WarpCase>>& cases() const { return cases_; }
    const std::vector<std::unique_ptr<Check>>& checks() const { return checks_; }
    const WarpCase* find_case(std::string_view name) const;
    const Check* find_check(std::string_view name) const;

    /// Marks a registered case as a demonstration of a known flaw (e.g. a float
    /// sampler that returns 1.0): it is expected to fail, so it runs only with
    /// --include-flawed or when selected by its full name.
    void mark_known_flaw(const std::string& case_name, std::string flaw);
    /// The flaw of a case, or an empty string.
    std::string known_flaw(const WarpCase& warp) const;

private:
    std::vector<std::pair<std::string, std::string>> flaws_;
    std::vector<std::unique_ptr<WarpCase>> cases_;
    std::vector<std::unique_ptr<Check>> checks_;
};

/// Whether `name` matches `pattern`: a glob with * and ? when the pattern has
/// either, otherwise a substring match. "cone" matches every uniform_cone case;
/// "uniform_cone[cos_theta_max=0.3]" matches exactly that one.
bool name_matches(std::string_view name, std::string_view pattern);

// The warps and checks that ship with warpcheck, one function per family.
void register_builtin_cases(Registry& registry);
void register_builtin_checks(Registry& registry);

void register_geometric_cases(Registry& registry);
void register_interval_cases(Registry& registry);
/// Renderer idioms that fail by the rules (u * 2^-32 reaching 1.0, lerps that
/// reach b or step down). Not built in: every default check of every built-in
/// case passes. Tests, and anyone who wants the evidence, add them.
/// Idioms that fail by the rules (u * 2^-32 reaching 1.0, lerps reaching b),
/// registered and marked as known flaws.
void register_flawed_interval_cases(Registry& registry);
void register_linear_cases(Registry& registry);
void register_exponential_cases(Registry& registry);
void register_trowbridge_reitz_cases(Registry& registry);
void register_piecewise_constant_cases(Registry& registry);

}  // namespace warpcheck
