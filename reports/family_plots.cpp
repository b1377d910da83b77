#include "reports/family_plots.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <string_view>
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

/// The quantity a limit named "<quantity> bound" bounds ("energy"), or empty.
std::string bounded_quantity(const std::string& limit) {
    constexpr std::string_view suffix = " bound";
    if (limit.size() <= suffix.size() || !std::string_view(limit).ends_with(suffix)) return {};
    return limit.substr(0, limit.size() - suffix.size());
}

/// The series of a plot indexed by every start of their labels that ends
/// before a space ("energy" and "energy albedo," for "energy albedo, alpha=0.3"):
/// each quantity a bound names is then looked up, not searched for.
std::map<std::string, std::vector<std::size_t>> label_starts(const std::vector<Series>& series) {
    std::map<std::string, std::vector<std::size_t>> starts;
    for (std::size_t k = 0; k < series.size(); ++k)
        for (std::size_t at = series[k].label.find(' '); at != std::string::npos; at = series[k].label.find(' ', at + 1))
            starts[series[k].label.substr(0, at)].push_back(k);
    return starts;
}

/// Where a plot's limit "<quantity> bound" bounds only some of its curves
/// (those labelled "<quantity> ..."), those curves and the bound move to a
/// plot of their own, titled by the quantity: a BSDF's energy albedo under its
/// bound 1, apart from the radiance albedo, which may exceed 1 across an
/// interface and is not judged against it.
void separate_bounded_curves(std::vector<FamilyPlot>& plots) {
    for (std::size_t i = 0; i < plots.size(); ++i) {
        std::vector<std::string> quantities;  // each once, in the order of the limits
        for (const Figure& l : plots[i].limits)
            if (const std::string q = bounded_quantity(l.name);
                !q.empty() && std::find(quantities.begin(), quantities.end(), q) == quantities.end())
                quantities.push_back(q);
        for (const std::string& quantity : quantities) {
            std::vector<Series>& series = plots[i].plot.series;
            const auto starts = label_starts(series);
            const auto bounded = starts.find(quantity);
            if (bounded == starts.end() || bounded->second.size() == series.size()) continue;
            std::vector<Series> all = std::move(series);
            series.clear();
            FamilyPlot apart{plots[i].family, plots[i].plot, {}};
            const std::string& label = all[bounded->second.front()].label;
            const std::size_t against = plots[i].plot.title.find(" against ");
            apart.plot.title = label.substr(0, label.find(", ")) +
                               (against == std::string::npos ? "" : plots[i].plot.title.substr(against));
            apart.plot.y_label = quantity + " " + plots[i].plot.y_label;
            std::vector<bool> moves(all.size(), false);
            for (std::size_t k : bounded->second) moves[k] = true;
            for (std::size_t k = 0; k < all.size(); ++k) (moves[k] ? apart.plot.series : series).push_back(std::move(all[k]));
            std::vector<Figure>& limits = plots[i].limits;
            const auto of_quantity = [&](const Figure& l) { return bounded_quantity(l.name) == quantity; };
            std::copy_if(limits.begin(), limits.end(), std::back_inserter(apart.limits), of_quantity);
            limits.erase(std::remove_if(limits.begin(), limits.end(), of_quantity), limits.end());
            plots.insert(plots.begin() + static_cast<std::ptrdiff_t>(i) + 1, std::move(apart));
        }
    }
}

}  // namespace

std::vector<FamilyPlot> family_plots(const std::vector<CheckResult>& rows) {
    // Each plot's curves and limits are found through maps, not by a search
    // of those already gathered: a merge of shards whose points each name a
    // curve of their own (64,000 points took 146 s) stays n log n.
    struct Gathering {
        std::vector<Curve> curves;
        std::map<std::string, std::size_t> curve_of;
        std::set<std::pair<std::string, uint64_t>> limits;  ///< (name, value's bits): NaN has an order too
    };
    std::vector<FamilyPlot> plots;
    std::vector<Gathering> gathered;
    std::map<std::pair<std::string, std::string>, std::size_t> plot_of;
    std::size_t order = 0;
    for (const CheckResult& r : rows)
        for (const FamilyPoint& p : r.family_points) {
            const auto [it, added] = plot_of.try_emplace({p.family, p.title}, plots.size());
            if (added) {
                Plot plot{Plot::Kind::Lines, p.title, p.x_label, p.y_label, false, p.log_y, {}, {}};
                plots.push_back({p.family, std::move(plot), {}});
                gathered.emplace_back();
            }
            Gathering& g = gathered[it->second];
            for (const Figure& l : p.limits)
                if (g.limits.insert({l.name, std::bit_cast<uint64_t>(l.value == 0.0 ? 0.0 : l.value)}).second)
                    plots[it->second].limits.push_back(l);
            for (const FamilyValue& v : p.values) {
                std::string label = p.group.empty() ? v.label : v.label + ", " + p.group;
                const auto [c, new_curve] = g.curve_of.try_emplace(label, g.curves.size());
                if (new_curve) g.curves.push_back(Curve{std::move(label), {}});
                g.curves[c->second].points.push_back({{p.x, order}, v});
            }
            ++order;
        }
    for (std::size_t i = 0; i < plots.size(); ++i)
        for (Curve& c : gathered[i].curves) plots[i].plot.series.push_back(series_of(c));
    separate_bounded_curves(plots);
    return plots;
}

}  // namespace warpcheck
