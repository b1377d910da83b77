#include "validate/samples/ulp_comparison.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "validate/checks/shared/evidence.h"
#include "validate/checks/shared/formatting.h"

namespace warpcheck {

uint64_t ulp_distance(float a, float b) {
    if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<uint64_t>::max();
    // Floats in order as integers: the negative ones mirrored below zero, so
    // that -0 and +0 are both 0 and neighbouring floats differ by one.
    const auto ordered = [](float x) {
        const auto bits = static_cast<int64_t>(std::bit_cast<uint32_t>(x));
        return bits & 0x80000000 ? -(bits & 0x7fffffff) : bits;
    };
    const int64_t d = ordered(a) - ordered(b);
    return static_cast<uint64_t>(d < 0 ? -d : d);
}

uint64_t ulp_distance(float a, float b, float floor) {
    if (std::isnan(a) || std::isnan(b) || !(floor > 0.0f) || !(std::max(std::abs(a), std::abs(b)) < floor))
        return ulp_distance(a, b);  // NaN gets the grid's answer: the largest
    const double spacing = static_cast<double>(std::nextafter(floor, HUGE_VALF)) - static_cast<double>(floor);
    return static_cast<uint64_t>(std::ceil(std::abs(static_cast<double>(a) - static_cast<double>(b)) / spacing));
}

namespace {

/// Histogram bins: 0, 1, 2, then (2^(k-1), 2^k] for k = 2 .. 31, and one for NaN.
constexpr std::size_t kPowerBins = 33;
std::size_t bin_of(uint64_t ulps) {
    if (ulps == std::numeric_limits<uint64_t>::max()) return kPowerBins;  // NaN
    if (ulps <= 2) return static_cast<std::size_t>(ulps);
    return std::min<std::size_t>(kPowerBins - 1, static_cast<std::size_t>(std::bit_width(ulps - 1)) + 1);
}
std::string bin_label(std::size_t bin) {
    if (bin == kPowerBins) return "NaN";
    if (bin <= 2) return std::to_string(bin);
    return fmt::format("{}-{}", (uint64_t{1} << (bin - 2)) + 1, uint64_t{1} << (bin - 1));
}

struct Distances {
    std::vector<uint64_t> bins = std::vector<uint64_t>(kPowerBins + 1, 0);
    uint64_t worst = 0, over = 0, nan = 0, identical = 0;
    double sum = 0.0, max_abs = 0.0;
    WorstK<std::size_t> worst_rows{10};
};

Distances tally(std::span<const WarpOutput> a, std::span<const WarpOutput> b, const UlpComparison& how) {
    Distances t;
    for (std::size_t i = 0; i < a.size(); ++i) {
        uint64_t d = 0;
        for (int c = 0; c < how.dimension; ++c) {
            const auto k = static_cast<std::size_t>(c);
            d = std::max(d, ulp_distance(a[i][k], b[i][k], how.floor));
            t.max_abs = std::max(t.max_abs, std::abs(static_cast<double>(a[i][k]) - static_cast<double>(b[i][k])));
        }
        const bool is_nan = d == std::numeric_limits<uint64_t>::max();
        ++t.bins[bin_of(d)];
        t.nan += is_nan;
        t.identical += d == 0;
        // Written so that NaN (the largest distance) is over any tolerance.
        t.over += !(d <= how.max_ulps);
        if (!is_nan) t.worst = std::max(t.worst, d), t.sum += static_cast<double>(d);
        const double key = is_nan ? std::nan("") : static_cast<double>(d);
        if (d > 0 && t.worst_rows.wants(key)) t.worst_rows.offer(key, i, i);
    }
    return t;
}

Table worst_table(const Distances& t, std::span<const WarpOutput> a, std::span<const WarpOutput> b,
                  const UlpComparison& how) {
    Table table{"Inputs where the two differ most", {"row"}, {}};
    if (!how.inputs.empty()) table.columns.push_back("input");
    for (const std::string& c : {how.label_a, how.label_b, std::string("ulps")}) table.columns.push_back(c);
    for (const auto& e : t.worst_rows.entries()) {
        const std::size_t i = e.item;
        std::vector<std::string> row{std::to_string(i)};
        if (!how.inputs.empty()) row.push_back(format_input(how.inputs[i], how.input_kind));
        row.push_back(format_output(a[i], how.dimension));
        row.push_back(format_output(b[i], how.dimension));
        row.push_back(std::isnan(e.key) ? "NaN" : fmt::format("{}", static_cast<uint64_t>(e.key)));
        table.rows.push_back(std::move(row));
    }
    return table;
}

}  // namespace

CheckResult compare_same_inputs(std::span<const WarpOutput> a, std::span<const WarpOutput> b, const UlpComparison& how) {
    if (a.size() != b.size())
        throw std::invalid_argument(fmt::format("ulps: {} has {} samples and {} has {}: the same inputs give as many",
                                                how.label_a, a.size(), how.label_b, b.size()));
    if (!how.inputs.empty() && how.inputs.size() != a.size())
        throw std::invalid_argument(fmt::format("ulps: {} inputs for {} samples", how.inputs.size(), a.size()));
    const Distances t = tally(a, b, how);
    CheckResult r;
    r.check_name = "ulps";
    r.samples = a.size();
    const double n = static_cast<double>(a.size());
    const double numeric = n - static_cast<double>(t.nan);
    r.figures = {{"max_ulps", static_cast<double>(t.worst)},
                 {"ulps_tolerance", static_cast<double>(how.max_ulps)},
                 {"ulp_floor", static_cast<double>(how.floor)},
                 {"mean_ulps", numeric > 0 ? t.sum / numeric : 0.0},
                 {"identical_fraction", n > 0 ? static_cast<double>(t.identical) / n : 0.0},
                 {"over_tolerance", static_cast<double>(t.over)},
                 {"nan", static_cast<double>(t.nan)},
                 {"max_abs_difference", t.max_abs},
                 {"samples", n}};
    Plot histogram;
    histogram.kind = Plot::Kind::Bars;
    histogram.title = fmt::format("ulps between {} and {}, per output (largest over coordinates)", how.label_a, how.label_b);
    histogram.x_label = "bin: 0, 1, 2 ulps, then bin k holds (2^(k-2), 2^(k-1)] ulps; NaN last";
    histogram.y_label = "outputs";
    histogram.log_y = true;
    Series bars{"outputs", {}, {}};
    Table counts{"Distance histogram", {"ulps", "outputs"}, {}};
    for (std::size_t bin = 0; bin < t.bins.size(); ++bin) {
        if (t.bins[bin] == 0) continue;
        bars.x.push_back(static_cast<double>(bin));
        bars.y.push_back(static_cast<double>(t.bins[bin]));
        counts.rows.push_back({bin_label(bin), std::to_string(t.bins[bin])});
    }
    histogram.series.push_back(std::move(bars));
    r.plots.push_back(std::move(histogram));
    r.tables.push_back(std::move(counts));
    r.tables.push_back(worst_table(t, a, b, how));
    r.summary = fmt::format("max {} ulps, {:.4g}% identical, {} over {} ulps", t.worst, 100.0 * (n > 0 ? t.identical / n : 0),
                            t.over, how.max_ulps);
    if (t.nan > 0) r.summary += fmt::format(", {} NaN", t.nan);
    if (how.floor > 0.0f) r.summary += fmt::format(" (below {:g}: ulps of {:g})", how.floor, how.floor);
    r.verdict = t.over == 0 && a.size() > 0 ? Verdict::Pass : Verdict::Fail;
    if (a.empty()) r.message = "no samples to compare";
    else if (t.over > 0)
        r.message = fmt::format("{} of {} outputs differ by more than {} ulps{}", t.over, a.size(), how.max_ulps,
                                t.nan ? fmt::format(" ({} with a NaN, which never agrees)", t.nan) : "");
    return r;
}

}  // namespace warpcheck
