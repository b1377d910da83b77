#include "reports/family_plots.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace warpcheck {
namespace {

/// One curve being gathered: its points as (x, row order, value).
struct Curve {
    std::string label;
    std::vector<std::pair<std::pair<double, std::size_t>, FamilyValue>> points;
};

Series series_of(Curve& c) {
    std::stable_sort(c.points.begin(), c.points.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    Series s{c.label, {}, {}};
    const bool intervals =
        std::any_of(c.points.begin(), c.points.end(), [](const auto& p) { return p.second.low <= p.second.high; });
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const auto& [at, v] : c.points) {
        s.x.push_back(at.first);
        s.y.push_back(v.y);
        if (!intervals) continue;
        const bool has = v.low <= v.high;
        s.y_low.push_back(has ? v.low : nan);
        s.y_high.push_back(has ? v.high : nan);
    }
    return s;
}

}  // namespace

std::vector<FamilyPlot> family_plots(const std::vector<CheckResult>& rows) {
    std::vector<FamilyPlot> plots;
    std::vector<std::vector<Curve>> curves;
    std::map<std::pair<std::string, std::string>, std::size_t> plot_of;
    std::size_t order = 0;
    for (const CheckResult& r : rows)
        for (const FamilyPoint& p : r.family_points) {
            const auto [it, added] = plot_of.try_emplace({p.family, p.title}, plots.size());
            if (added) {
                Plot plot{Plot::Kind::Lines, p.title, p.x_label, p.y_label, false, p.log_y, {}, {}};
                plots.push_back({p.family, std::move(plot), {}});
                curves.emplace_back();
            }
            std::vector<Figure>& limits = plots[it->second].limits;
            for (const Figure& l : p.limits)
                if (std::none_of(limits.begin(), limits.end(),
                                 [&](const Figure& k) { return k.name == l.name && k.value == l.value; }))
                    limits.push_back(l);
            std::vector<Curve>& mine = curves[it->second];
            for (const FamilyValue& v : p.values) {
                const std::string label = p.group.empty() ? v.label : v.label + ", " + p.group;
                auto c = std::find_if(mine.begin(), mine.end(), [&](const Curve& k) { return k.label == label; });
                if (c == mine.end()) c = mine.insert(mine.end(), Curve{label, {}});
                c->points.push_back({{p.x, order}, v});
            }
            ++order;
        }
    for (std::size_t i = 0; i < plots.size(); ++i)
        for (Curve& c : curves[i]) plots[i].plot.series.push_back(series_of(c));
    return plots;
}

}  // namespace warpcheck
