#include "validate/api/registry.h"

#include <stdexcept>


namespace warpcheck {

void Registry::add_case(std::unique_ptr<WarpCase> warp) {
    if (!warp) throw std::invalid_argument("registry: null warp case");
    if (find_case(warp->name())) throw std::invalid_argument("registry: duplicate warp case name " + warp->name());
    validate_case(*warp);
    cases_.push_back(std::move(warp));
}

void Registry::add_named_check(std::string name, std::shared_ptr<const Check> check) {
    if (!check) throw std::invalid_argument("registry: null check");
    if (find_check(name)) throw std::invalid_argument("registry: duplicate check name " + name);
    checks_.push_back(std::move(check));
    check_names_.push_back(std::move(name));
}

void Registry::add_family(CaseFamily family) {
    if (!family.make) throw std::invalid_argument("registry: family " + family.base.family + " has no maker");
    if (find_family(family.base.family))
        throw std::invalid_argument("registry: duplicate family " + family.base.family);
    for (const GridAxis& a : family.axes)
        for (const ParamRange& r : a.ranges)
            if (!r.declared() || (r.lo == r.hi && (r.lo_open || r.hi_open)))
                throw std::invalid_argument("registry: family " + family.base.family + ": a range of " + a.name +
                                            " needs finite ends with lo <= hi, and a point range closed");
    families_.push_back(std::move(family));
}

const CaseFamily* Registry::find_family(std::string_view family) const {
    for (const CaseFamily& f : families_)
        if (f.base.family == family) return &f;
    return nullptr;
}

const WarpCase* Registry::find_case(std::string_view name) const {
    for (const auto& c : cases_)
        if (c->name() == name) return c.get();
    return nullptr;
}

void Registry::mark_known_flaw(const std::string& case_name, std::string flaw) {
    if (!find_case(case_name)) throw std::invalid_argument("registry: no case " + case_name + " to mark as flawed");
    flaws_.push_back({case_name, "", std::move(flaw)});
}

void Registry::mark_known_flaw(const std::string& case_name, const std::string& check_name, std::string flaw) {
    if (!find_case(case_name)) throw std::invalid_argument("registry: no case " + case_name + " to mark as flawed");
    if (!find_check(check_name))
        throw std::invalid_argument("registry: no check " + check_name + " to mark as flawed for case " + case_name);
    flaws_.push_back({case_name, check_name, std::move(flaw)});
}

std::string Registry::known_flaw(const WarpCase& warp) const {
    for (const Flaw& f : flaws_)
        if (f.case_name == warp.name() && f.check_name.empty()) return f.text;
    return {};
}

std::string Registry::known_flaw(const WarpCase& warp, std::string_view check_name) const {
    for (const Flaw& f : flaws_)
        if (f.case_name == warp.name() && f.check_name == check_name) return f.text;
    return known_flaw(warp);
}

const Check* Registry::find_check(std::string_view name) const {
    for (std::size_t i = 0; i < checks_.size(); ++i)
        if (check_names_[i] == name) return checks_[i].get();
    return nullptr;
}

namespace {

// Classic glob matching with backtracking over the last '*'.
bool glob_match(std::string_view text, std::string_view pattern) {
    std::size_t t = 0, p = 0, star = std::string_view::npos, mark = 0;
    while (t < text.size()) {
        if (p < pattern.size() && (pattern[p] == '?' || pattern[p] == text[t])) {
            ++t;
            ++p;
        } else if (p < pattern.size() && pattern[p] == '*') {
            star = p++;
            mark = t;
        } else if (star != std::string_view::npos) {
            p = star + 1;
            t = ++mark;
        } else {
            return false;
        }
    }
    while (p < pattern.size() && pattern[p] == '*') ++p;
    return p == pattern.size();
}

}  // namespace

bool name_matches(std::string_view name, std::string_view pattern) {
    // Contained as it is written, or matched as a glob: a case whose own name
    // holds '*' or '?' is found by a part of its name too.
    if (name.find(pattern) != std::string_view::npos) return true;
    return pattern.find_first_of("*?") != std::string_view::npos && glob_match(name, pattern);
}

}  // namespace warpcheck
