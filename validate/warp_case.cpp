#include "validate/warp_case.h"

#include <fmt/format.h>

namespace warpcheck {

std::string case_name(const std::string& family, const std::vector<Parameter>& params) {
    if (params.empty()) return family;
    std::string name = family + "[";
    for (std::size_t i = 0; i < params.size(); ++i) {
        if (i > 0) name += ",";
        // {} gives the shortest decimal that reads back as the same double: 0.3, 1e-06, 85.
        name += fmt::format("{}={}", params[i].name, params[i].value);
    }
    return name + "]";
}

}  // namespace warpcheck
