#include "reports/svg_plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "reports/color_map.h"
#include "reports/png.h"
#include "reports/text.h"

namespace warpcheck {
namespace {

constexpr double kFontSize = 11.0;
constexpr double kCharWidth = 6.4;  // average advance of an 11 px sans-serif character
constexpr const char* kTextColor = "#2b2f36";
constexpr const char* kGridColor = "#e3e6ea";
constexpr const char* kAxisColor = "#8a9099";

// ---------------------------------------------------------------------------
// Small formatting helpers

/// A coordinate with at most one decimal and no trailing ".0": compact SVG.
std::string px(double v) {
    if (!std::isfinite(v)) v = 0.0;
    std::string s = fmt::format("{:.1f}", v);
    if (s.size() > 2 && s.compare(s.size() - 2, 2, ".0") == 0) s.resize(s.size() - 2);
    if (s == "-0") s = "0";
    return s;
}

double text_width(std::string_view text) {
    std::size_t characters = 0;
    for (char c : text) characters += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
    return static_cast<double>(characters) * kCharWidth;
}

/// `text` broken at spaces into lines no wider than `width` pixels (bold
/// labels are a little wider than kCharWidth); a longer word gets its own line.
std::vector<std::string> wrap(const std::string& text, double width) {
    std::vector<std::string> lines;
    std::string line;
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t end = text.find(' ', start);
        if (end == std::string::npos) end = text.size();
        const std::string word = text.substr(start, end - start);
        const std::string candidate = line.empty() ? word : line + " " + word;
        if (!line.empty() && text_width(candidate) * 1.08 > width) {
            lines.push_back(line);
            line = word;
        } else {
            line = candidate;
        }
        start = end + 1;
    }
    if (!line.empty()) lines.push_back(line);
    return lines;
}

constexpr double kLineHeight = 14.0;

/// An axis label of one or more lines. The x label is centred at (x, y); the
/// y label is turned a quarter left about (x, y), its further lines towards
/// the plot.
std::string axis_label(const std::vector<std::string>& lines, double x, double y, bool vertical) {
    std::string svg = vertical ? fmt::format("<text transform=\"translate({} {}) rotate(-90)\" text-anchor=\"middle\" class=\"axis-label\">", px(x), px(y))
                               : fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" class=\"axis-label\">", px(x), px(y));
    for (std::size_t i = 0; i < lines.size(); ++i)
        svg += fmt::format("<tspan x=\"{}\" dy=\"{}\">{}</tspan>", vertical ? "0" : px(x), i == 0 ? 0.0 : kLineHeight, escaped(lines[i]));
    return svg + "</text>";
}

/// A tick label: its SVG markup (possibly with a superscript) and its plain
/// length, for layout.
struct Label {
    std::string markup;
    std::string plain;
};

Label plain_label(std::string text) {
    Label l{escaped(text), text};
    return l;
}

/// "10" with a superscript exponent, e.g. 10^-3.
Label power_of_ten_label(int exponent) {
    std::string e = exponent < 0 ? fmt::format("\u2212{}", -exponent) : fmt::format("{}", exponent);
    return {fmt::format("10<tspan dy=\"-0.45em\" font-size=\"8\">{}</tspan>", e), "10" + e};
}

/// The label of a linear tick at `value` on an axis with tick spacing `step`:
/// as few digits as tell the ticks apart; scientific (m x 10^e) for very large
/// or very small magnitudes.
Label number_label(double value, double step) {
    if (std::abs(value) < step * 1e-9) return plain_label("0");
    const double magnitude = std::max(std::abs(value), step);
    const int step_exponent = static_cast<int>(std::floor(std::log10(step) + 1e-9));
    if (magnitude >= 1e5 || magnitude < 1e-3) {
        const int exponent = static_cast<int>(std::floor(std::log10(magnitude) + 1e-9));
        const int decimals = std::clamp(exponent - step_exponent, 0, 8);
        const double mantissa = value / std::pow(10.0, exponent);
        std::string m = fmt::format("{:.{}f}", mantissa, decimals);
        if (m == "1" || m == "-1") {
            Label p = power_of_ten_label(exponent);
            if (m == "-1") p.markup = "\u2212" + p.markup, p.plain = "-" + p.plain;
            return p;
        }
        if (m[0] == '-') m.replace(0, 1, "\u2212");
        Label p = power_of_ten_label(exponent);
        return {m + "\u00d7" + p.markup, m + "x" + p.plain};
    }
    const int decimals = std::clamp(-step_exponent, 0, 10);
    std::string s = fmt::format("{:.{}f}", value, decimals);
    if (s[0] == '-') s.replace(0, 1, "\u2212");
    return {s, s};
}

// ---------------------------------------------------------------------------
// Axes

struct Tick {
    double value;
    Label label;
    bool major = true;
};

struct Axis {
    double lo = 0.0, hi = 1.0;  ///< data range shown
    bool log = false;
    double from = 0.0, to = 1.0;  ///< pixel positions of lo and hi
    std::vector<Tick> ticks;

    double map(double v) const {
        const double t = log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo))
                             : (v - lo) / (hi - lo);
        return from + t * (to - from);
    }
    bool shows(double v) const { return std::isfinite(v) && (!log || v > 0.0); }
};

double nice_step(double range, int target) {
    const double raw = range / std::max(target, 1);
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    const double n = raw / magnitude;
    return (n < 1.5 ? 1.0 : n < 3.0 ? 2.0 : n < 7.0 ? 5.0 : 10.0) * magnitude;
}

/// Linear ticks within [lo, hi]; with `extend`, lo and hi first grow to the
/// enclosing ticks (so the plot ends on a labelled value).
std::vector<Tick> linear_ticks(double& lo, double& hi, int target, bool extend) {
    const double step = nice_step(hi - lo, target);
    if (extend) {
        lo = std::floor(lo / step + 1e-9) * step;
        hi = std::ceil(hi / step - 1e-9) * step;
    }
    std::vector<Tick> ticks;
    const double first = std::ceil(lo / step - 1e-9);
    for (double k = first; k * step <= hi + step * 1e-9 && ticks.size() < 50; k += 1.0) {
        const double v = k * step;
        ticks.push_back({v, number_label(v, step)});
    }
    return ticks;
}

/// Ticks at multiples of pi/2 when both ends of the range are such multiples
/// (azimuth axes of spherical domains); nothing otherwise.
std::vector<Tick> pi_ticks(double lo, double hi) {
    constexpr double half_pi = std::numbers::pi / 2.0;
    const double a = lo / half_pi, b = hi / half_pi;
    if (!(std::abs(a - std::round(a)) < 1e-6 && std::abs(b - std::round(b)) < 1e-6)) return {};
    const long first = std::lround(a), last = std::lround(b);
    if (last - first < 1) return {};
    const long stride = last - first > 8 ? 2 : 1;
    std::vector<Tick> ticks;
    for (long k = first; k <= last; k += stride) {
        std::string s;
        const long n = std::labs(k);
        if (k == 0)
            s = "0";
        else if (n % 2 == 0)
            s = (n == 2 ? std::string("\u03c0") : fmt::format("{}\u03c0", n / 2));
        else
            s = (n == 1 ? std::string("\u03c0/2") : fmt::format("{}\u03c0/2", n));
        if (k < 0) s = "\u2212" + s;
        ticks.push_back({static_cast<double>(k) * half_pi, Label{escaped(s), s}});
    }
    return ticks;
}

/// Decade ticks (and minor ticks at 2..9 for short ranges); lo and hi grow to
/// whole decades.
std::vector<Tick> log_ticks(double& lo, double& hi) {
    int first = static_cast<int>(std::floor(std::log10(lo) + 1e-9));
    int last = static_cast<int>(std::ceil(std::log10(hi) - 1e-9));
    if (last <= first) last = first + 1;
    lo = std::pow(10.0, first);
    hi = std::pow(10.0, last);
    const int decades = last - first;
    const int stride = decades > 24 ? 6 : decades > 12 ? 3 : decades > 7 ? 2 : 1;
    std::vector<Tick> ticks;
    for (int e = first; e <= last; ++e) {
        if ((e - first) % stride == 0) ticks.push_back({std::pow(10.0, e), power_of_ten_label(e)});
        if (decades <= 3 && e < last) {
            for (int m = 2; m <= 9; ++m) {
                Label label;
                if (decades == 1 && (m == 2 || m == 5)) label = number_label(m * std::pow(10.0, e), std::pow(10.0, e));
                ticks.push_back({m * std::pow(10.0, e), label, false});
            }
        }
    }
    return ticks;
}

struct Range {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -std::numeric_limits<double>::infinity();
    void add(double v) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    bool empty() const { return !(lo <= hi); }
};

/// Sets an axis up over the data range `r`.
Axis make_axis(Range r, bool log, bool extend_to_ticks, int target_ticks) {
    Axis axis;
    axis.log = log;
    if (r.empty()) r = log ? Range{1.0, 10.0} : Range{0.0, 1.0};
    if (log) {
        axis.lo = r.lo, axis.hi = r.hi;
        axis.ticks = log_ticks(axis.lo, axis.hi);
        return axis;
    }
    if (r.hi - r.lo <= std::abs(r.hi) * 1e-12) {  // one value: show it in the middle
        const double pad = r.hi == 0.0 ? 1.0 : std::abs(r.hi) * 0.5;
        r.lo -= pad, r.hi += pad;
    }
    axis.lo = r.lo, axis.hi = r.hi;
    axis.ticks = pi_ticks(axis.lo, axis.hi);
    if (axis.ticks.empty()) axis.ticks = linear_ticks(axis.lo, axis.hi, target_ticks, extend_to_ticks);
    return axis;
}

// ---------------------------------------------------------------------------
// Line, bar and point plots

struct Point {
    double x, y;
};

/// The points of a series that the axes can show, in order; a missing x is the
/// index. Points that cannot be shown become NaN (a break in a line).
std::vector<Point> points_of(const Series& s, bool log_x, bool log_y) {
    const bool indexed = s.x.empty();
    const std::size_t n = indexed ? s.y.size() : std::min(s.x.size(), s.y.size());
    std::vector<Point> points(n);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i = 0; i < n; ++i) {
        double x = indexed ? static_cast<double>(i) : s.x[i];
        double y = s.y[i];
        if (!std::isfinite(x) || (log_x && x <= 0.0)) x = nan;
        if (!std::isfinite(y) || (log_y && y <= 0.0)) y = nan;
        points[i] = {x, y};
    }
    return points;
}

bool valid(const Point& p) { return !std::isnan(p.x) && !std::isnan(p.y); }

/// Path data in whole pixels, relative after the first point of each piece
/// ("M12 40l1-2 1 0 ..."): a plot's curves are a few pixels apart at most, and
/// whole pixels halve the size of a report with hundreds of curves. Points that
/// fall on the pixel of the point before are left out.
class PathWriter {
public:
    explicit PathWriter(std::string& d) : d_(d) {}
    void move_to(double x, double y) { put(x, y, false); }
    void line_to(double x, double y) { put(x, y, pen_down_); }
    void lift() { pen_down_ = false; }

private:
    void put(double x, double y, bool relative) {
        const long ix = std::lround(std::isfinite(x) ? x : 0.0), iy = std::lround(std::isfinite(y) ? y : 0.0);
        if (relative && ix == x_ && iy == y_) return;
        if (relative) {
            if (!in_line_) d_ += 'l';
            append_signed(ix - x_, true);
            append_signed(iy - y_, false);
            in_line_ = true;
        } else {
            d_ += fmt::format("M{} {}", ix, iy);
            in_line_ = false;
        }
        x_ = ix, y_ = iy;
        pen_down_ = true;
    }
    /// A number of a relative pair: a minus sign separates it from the one
    /// before, otherwise a space does (not needed right after the command letter).
    void append_signed(long v, bool first) {
        if (v >= 0 && !(first && d_.back() == 'l')) d_ += ' ';
        d_ += std::to_string(v);
    }

    std::string& d_;
    long x_ = 0, y_ = 0;
    bool pen_down_ = false, in_line_ = false;
};

/// Appends the path of a line through `points`, broken at invalid points. A
/// series sorted in x keeps, per pixel column, its first, lowest, highest and
/// last point: the drawing is the same, the file much smaller.
void append_line_path(std::string& d, const std::vector<Point>& points, const Axis& ax, const Axis& ay) {
    PathWriter path(d);
    double column = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::pair<double, double>> bucket;  // pixel positions in the current column
    const bool decimate = points.size() > 8 && std::is_sorted(points.begin(), points.end(), [](const Point& a, const Point& b) {
                              return valid(a) && valid(b) && a.x < b.x;
                          });
    const auto flush = [&] {
        if (bucket.empty()) return;
        if (bucket.size() <= 4) {
            for (auto [x, y] : bucket) path.line_to(x, y);
        } else {
            auto [lo, hi] = std::minmax_element(bucket.begin() + 1, bucket.end() - 1,
                                                [](auto a, auto b) { return a.second < b.second; });
            path.line_to(bucket.front().first, bucket.front().second);
            if (lo > hi) std::swap(lo, hi);
            path.line_to(lo->first, lo->second), path.line_to(hi->first, hi->second);
            path.line_to(bucket.back().first, bucket.back().second);
        }
        bucket.clear();
    };
    for (const Point& p : points) {
        if (!valid(p)) {
            flush();
            path.lift();
            continue;
        }
        const double x = ax.map(p.x), y = ay.map(p.y);
        if (!decimate) {
            path.line_to(x, y);
            continue;
        }
        if (std::floor(x) != column) {
            flush();
            column = std::floor(x);
        }
        bucket.emplace_back(x, y);
    }
    flush();
}

struct LegendItem {
    std::string label;
    std::string color;
    Plot::Kind kind;
    std::string dash;
};

/// Lines after the first are dashed, each differently, so that a curve lying
/// on top of another (min = ideal = max) leaves both visible.
std::string dash_of(std::size_t series) {
    static constexpr std::array<const char*, 4> dashes{"", "7 4", "2 3", "10 3 2 3"};
    const char* d = dashes[series % dashes.size()];
    return *d ? fmt::format(" stroke-dasharray=\"{}\"", d) : std::string();
}

/// Legend entries laid out left to right in rows of at most `width`; returns
/// the height used.
double append_legend(std::string& svg, const std::vector<LegendItem>& items, double left, double top, double width) {
    double x = left, y = top;
    const double row_height = 18.0;
    for (const auto& item : items) {
        const double w = 22.0 + text_width(item.label) + 18.0;
        if (x > left && x + w > left + width) x = left, y += row_height;
        const std::string& c = item.color;
        const double cy = y + 8.0;
        if (item.kind == Plot::Kind::Bars)
            svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"14\" height=\"10\" fill=\"{}\"/>", px(x), px(cy - 5), c);
        else if (item.kind == Plot::Kind::Points)
            svg += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"3.5\" fill=\"{}\"/>", px(x + 7), px(cy), c);
        else
            svg += fmt::format("<path d=\"M{} {}h16\" stroke=\"{}\" stroke-width=\"2.5\"{}/>", px(x), px(cy), c, item.dash);
        svg += fmt::format("<text x=\"{}\" y=\"{}\" dy=\"0.35em\">{}</text>", px(x + 21), px(cy), escaped(item.label));
        x += w;
    }
    return items.empty() ? 0.0 : y - top + row_height + 4.0;
}

/// The grid lines of an x-y plot area: major ones in one path, minor ones
/// (fainter) in another; minor lines are left out on long log axes.
void append_grid(std::string& svg, const Axis& ax, const Axis& ay) {
    std::string major, minor;
    for (const Tick& t : ay.ticks) {
        if (!t.major && ay.log && ay.ticks.size() > 24) continue;
        (t.major ? major : minor) += fmt::format("M{} {}H{}", px(ax.from), px(ay.map(t.value)), px(ax.to));
    }
    for (const Tick& t : ax.ticks) {
        if (!t.major && ax.log && ax.ticks.size() > 24) continue;
        (t.major ? major : minor) += fmt::format("M{} {}V{}", px(ax.map(t.value)), px(ay.to), px(ay.from));
    }
    if (!major.empty()) svg += fmt::format("<path d=\"{}\" stroke=\"{}\"/>", major, kGridColor);
    if (!minor.empty()) svg += fmt::format("<path d=\"{}\" stroke=\"{}\" stroke-opacity=\"0.5\"/>", minor, kGridColor);
}

/// Grid, ticks, tick labels and axis labels of an x-y plot area.
void append_axes(std::string& svg, const Axis& ax, const Axis& ay, const std::vector<std::string>& x_label,
                 const std::vector<std::string>& y_label, double y_label_x) {
    const double left = ax.from, right = ax.to, bottom = ay.from, top = ay.to;
    append_grid(svg, ax, ay);
    if (!ay.log && ay.lo < 0.0 && ay.hi > 0.0)  // the zero line, where differences are read against
        svg += fmt::format("<path d=\"M{} {}H{}\" stroke=\"{}\"/>", px(left), px(ay.map(0.0)), px(right), kAxisColor);
    std::string ticks = fmt::format("M{} {}H{}V{}H{}z", px(left), px(top), px(right), px(bottom), px(left));
    std::string labels = "<g text-anchor=\"middle\">";
    for (const Tick& t : ax.ticks) {
        const double x = ax.map(t.value);
        ticks += fmt::format("M{} {}v{}", px(x), px(bottom), t.major ? 4 : 2);
        if (!t.label.markup.empty())
            labels += fmt::format("<text x=\"{}\" y=\"{}\">{}</text>", px(x), px(bottom + 16), t.label.markup);
    }
    labels += "</g><g text-anchor=\"end\">";
    for (const Tick& t : ay.ticks) {
        const double y = ay.map(t.value);
        ticks += fmt::format("M{} {}h-{}", px(left), px(y), t.major ? 4 : 2);
        if (!t.label.markup.empty())
            labels += fmt::format("<text x=\"{}\" y=\"{}\" dy=\"0.35em\">{}</text>", px(left - 7), px(y), t.label.markup);
    }
    svg += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"{}\"/>", ticks, kAxisColor) + labels + "</g>";
    if (!x_label.empty()) svg += axis_label(x_label, (left + right) / 2, bottom + 34, false);
    if (!y_label.empty()) svg += axis_label(y_label, y_label_x, (top + bottom) / 2, true);
}

double max_label_width(const std::vector<Tick>& ticks) {
    double w = 0.0;
    for (const Tick& t : ticks) w = std::max(w, text_width(t.label.plain));
    return w;
}

std::string svg_open(double width, double height, std::string_view label) {
    return fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
        "font-size=\"{2}\" fill=\"{3}\" role=\"img\" aria-label=\"{4}\">",
        px(width), px(height), px(kFontSize), kTextColor, escaped(label));
}

/// The shown points of every series and the ranges they span, the x range
/// padded so that bars and points at its ends are drawn whole.
struct XyData {
    std::vector<std::vector<Point>> series;
    Range x, y;
    /// The closest pair of x values (in decades on a log axis): the width a bar may take.
    double bar_spacing = std::numeric_limits<double>::infinity();
};

/// Bars grow from zero and are as wide as the closest pair of x values allows:
/// the y range takes in 0, the x range half a bar more at each end.
void widen_for_bars(XyData& data, bool log_x, bool log_y) {
    if (!log_y && !data.y.empty()) data.y.add(0.0);
    std::vector<double> xs;
    for (const auto& points : data.series)
        for (const Point& p : points)
            if (!std::isnan(p.x)) xs.push_back(log_x ? std::log10(p.x) : p.x);
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    double spacing = std::numeric_limits<double>::infinity();
    for (std::size_t i = 1; i < xs.size(); ++i) spacing = std::min(spacing, xs[i] - xs[i - 1]);
    if (!std::isfinite(spacing)) spacing = 1.0;
    data.bar_spacing = spacing;
    if (data.x.empty()) return;
    if (log_x)
        data.x.lo *= std::pow(10.0, -spacing / 2), data.x.hi *= std::pow(10.0, spacing / 2);
    else
        data.x.lo -= spacing / 2, data.x.hi += spacing / 2;
}

/// The axes also take in the limits and highlights the report adds, so that a
/// tolerance beyond every error still shows, and where it lies.
void widen_for_annotations(XyData& data, const Plot& plot, const SvgOptions& options) {
    const auto shows = [](double v, bool log) { return std::isfinite(v) && (!log || v > 0.0); };
    for (const LimitLine& l : options.limits) {
        if (l.vertical && shows(l.value, plot.log_x)) data.x.add(l.value);
        if (!l.vertical && shows(l.value, plot.log_y)) data.y.add(l.value);
    }
    for (const Highlight& h : options.highlights)
        if (shows(h.x, plot.log_x) && shows(h.y, plot.log_y)) data.x.add(h.x), data.y.add(h.y);
}

/// The error bars of a series that the axes can show: (x, low, high) with
/// low <= high, low raised to the axis' end where a log axis cannot show it.
std::vector<std::array<double, 3>> error_bars_of(const Series& s, bool log_x, bool log_y) {
    std::vector<std::array<double, 3>> bars;
    const std::size_t n = std::min({s.x.size(), s.y.size(), s.y_low.size(), s.y_high.size()});
    for (std::size_t i = 0; i < n; ++i) {
        const double x = s.x[i], lo = s.y_low[i], hi = s.y_high[i];
        if (!std::isfinite(x) || (log_x && x <= 0.0) || !std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi)) continue;
        if (log_y && !(hi > 0.0)) continue;
        bars.push_back({x, log_y && lo <= 0.0 ? std::numeric_limits<double>::quiet_NaN() : lo, hi});
    }
    return bars;
}

XyData xy_data(const Plot& plot, const SvgOptions& options) {
    XyData data;
    for (const Series& s : plot.series) {
        data.series.push_back(points_of(s, plot.log_x, plot.log_y));
        for (const Point& p : data.series.back()) {
            if (!std::isnan(p.x)) data.x.add(p.x);
            if (valid(p)) data.y.add(p.y);
        }
        for (const auto& [x, lo, hi] : error_bars_of(s, plot.log_x, plot.log_y)) {
            if (!std::isnan(lo)) data.y.add(lo);
            data.y.add(hi);
        }
    }
    // Annotations first: the half bar of padding then also keeps a limit past every bar inside the frame.
    if (!data.x.empty() && !data.y.empty()) widen_for_annotations(data, plot, options);
    if (plot.kind == Plot::Kind::Bars) widen_for_bars(data, plot.log_x, plot.log_y);
    if (plot.kind == Plot::Kind::Points && !data.x.empty() && !plot.log_x) {
        const double pad = (data.x.hi - data.x.lo) * 0.02;
        data.x.lo -= pad, data.x.hi += pad;
    }
    return data;
}

/// The x axis ends on ticks when that adds little (e.g. cell centres 0.0025
/// .. 0.9975 become 0 .. 1), else exactly at the data.
Axis x_axis_of(const Range& rx, bool log_x) {
    Axis ax = make_axis(rx, log_x, false, 7);
    if (!log_x && !rx.empty() && ax.ticks.size() >= 2) {
        Axis trial = make_axis(rx, false, true, 7);
        if (trial.hi - trial.lo <= (ax.hi - ax.lo) * 1.1) ax = trial;
    }
    return ax;
}

/// One entry per series when there are several, or when the one series has a label.
std::vector<LegendItem> legend_items(const Plot& plot) {
    std::vector<LegendItem> legend;
    for (std::size_t i = 0; i < plot.series.size(); ++i)
        if (!plot.series[i].label.empty() || plot.series.size() > 1)
            legend.push_back({plot.series[i].label.empty() ? fmt::format("series {}", i + 1) : plot.series[i].label,
                              series_color(i), plot.kind, plot.kind == Plot::Kind::Lines ? dash_of(i) : ""});
    return legend;
}

/// Where the plot area of an x-y plot lies, in pixels, and what surrounds it:
/// the legend on top, the y tick labels and the y label on the left.
struct XyFrame {
    std::vector<std::string> x_label, y_label;  ///< wrapped into lines
    std::string legend_svg;
    double left = 0.0, right = 0.0, top = 0.0, bottom = 0.0;
};

XyFrame xy_frame(const Plot& plot, const Axis& ay, double width, double height) {
    XyFrame frame;
    frame.x_label = wrap(plot.x_label, width - 90.0);
    frame.y_label = wrap(plot.y_label, height - 70.0);
    const double y_label_space = frame.y_label.empty() ? 0.0 : 18.0 + kLineHeight * static_cast<double>(frame.y_label.size() - 1);
    frame.left = 12.0 + y_label_space + std::max(24.0, max_label_width(ay.ticks));
    frame.right = width - 16.0;
    const double legend_height = append_legend(frame.legend_svg, legend_items(plot), frame.left, 8.0, frame.right - frame.left);
    frame.top = 10.0 + legend_height;
    frame.bottom = height - (frame.x_label.empty() ? 26.0 : 42.0 + kLineHeight * static_cast<double>(frame.x_label.size() - 1));
    return frame;
}

/// A round dot at each valid point, as one path of zero-length segments
/// (whole pixels; a dot on the pixel of another is drawn once).
std::string dot_marks(const std::vector<Point>& points, const Axis& ax, const Axis& ay) {
    std::string marks;
    std::vector<std::pair<long, long>> drawn;
    for (const Point& p : points) {
        if (!valid(p)) continue;
        const std::pair<long, long> at{std::lround(ax.map(p.x)), std::lround(ay.map(p.y))};
        if (std::find(drawn.end() - std::min<std::ptrdiff_t>(std::ssize(drawn), 8), drawn.end(), at) != drawn.end()) continue;
        drawn.push_back(at);
        marks += fmt::format("M{} {}h0", at.first, at.second);
    }
    return marks;
}

/// Series `i` as a line, dashed after the first.
void append_line_series(std::string& svg, const std::vector<Point>& points, std::size_t i, const Axis& ax, const Axis& ay) {
    const std::string color = series_color(i);
    std::string d;
    append_line_path(d, points, ax, ay);
    svg += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{}\" stroke-linejoin=\"round\"{}/>", d, color,
                       i == 0 ? 2.2 : 1.8, dash_of(i));
    if (points.size() <= 40)  // few points: mark them, a lone point would be invisible
        svg += fmt::format("<path d=\"{}\" stroke=\"{}\" stroke-width=\"5\" stroke-linecap=\"round\"/>", dot_marks(points, ax, ay),
                           color);
}

/// Series as dots, smaller and fainter when there are many.
void append_point_series(std::string& svg, const std::vector<Point>& points, const std::string& color, const Axis& ax,
                         const Axis& ay) {
    const bool many = points.size() > 2000;
    svg += fmt::format("<path d=\"{}\" stroke=\"{}\" stroke-width=\"{}\" stroke-linecap=\"round\" stroke-opacity=\"{}\"/>",
                       dot_marks(points, ax, ay), color, many ? 2.5 : 5, many ? 0.6 : 0.85);
}

/// How the bars of a plot sit: side by side in groups when each has room (5
/// px), else the first series filled and the others as step outlines over it.
struct BarLayout {
    double base = 0.0;           ///< the value bars grow from
    double pixel_spacing = 0.0;  ///< the closest pair of x values, in pixels
    std::size_t n_series = 0;
    bool grouped = false;
};

BarLayout bar_layout(const Plot& plot, const XyData& data, const Axis& ax, const Axis& ay) {
    BarLayout bars;
    bars.base = ay.log ? ay.lo : std::clamp(0.0, ay.lo, ay.hi);
    const double spacing = data.bar_spacing;
    bars.pixel_spacing = std::abs(ax.map(plot.log_x ? std::pow(10.0, spacing) * ax.lo : ax.lo + spacing) - ax.map(ax.lo));
    bars.n_series = data.series.size();
    bars.grouped = plot.kind == Plot::Kind::Bars && bars.n_series > 1 &&
                   bars.pixel_spacing * 0.8 / static_cast<double>(bars.n_series) >= 5.0;
    return bars;
}

/// Series `i` as filled bars, one path: its slot of a group, or centred on x.
void append_filled_bars(std::string& svg, const std::vector<Point>& points, std::size_t i, const BarLayout& bars,
                        const Axis& ax, const Axis& ay) {
    const double full = std::max(bars.pixel_spacing * 0.8, 1.0);
    const double w = bars.grouped ? full / static_cast<double>(bars.n_series) : full;
    const double offset = bars.grouped ? -full / 2 + w * static_cast<double>(i) : -w / 2;
    std::string d;
    for (const Point& p : points) {
        if (!valid(p)) continue;
        const double y0 = ay.map(bars.base), y1 = ay.map(p.y);
        const double height = std::max(std::abs(y1 - y0), 0.5);
        d += fmt::format("M{} {}h{}v{}h-{}z", px(ax.map(p.x) + offset), px(std::min(y0, y1)), px(w), px(height), px(w));
    }
    svg += fmt::format("<path d=\"{}\" fill=\"{}\"{}/>", d, series_color(i), bars.grouped ? "" : " fill-opacity=\"0.8\"");
}

/// A series over dense bars: a step outline, one bar wide at each point.
void append_step_outline(std::string& svg, const std::vector<Point>& points, const std::string& color, double pixel_spacing,
                         const Axis& ax, const Axis& ay) {
    std::string d;
    bool pen_down = false;
    const double half = pixel_spacing / 2;
    for (const Point& p : points) {
        if (!valid(p)) {
            pen_down = false;
            continue;
        }
        const double x = ax.map(p.x), y = ay.map(p.y);
        d += fmt::format("{}{} {}H{}", pen_down ? 'L' : 'M', px(x - half), px(y), px(x + half));
        pen_down = true;
    }
    svg += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.8\"/>", d, color);
}

/// Series `i`'s error bars: a vertical stroke from low to high with caps, in
/// the series' colour (a low a log axis cannot show runs to the axis' end, capless).
void append_error_bars(std::string& svg, const Plot& plot, std::size_t i, const Axis& ax, const Axis& ay) {
    std::string d;
    for (const auto& [x, lo, hi] : error_bars_of(plot.series[i], plot.log_x, plot.log_y)) {
        const double at = ax.map(x), top = ay.map(hi), bottom = std::isnan(lo) ? ay.from : ay.map(lo);
        d += fmt::format("M{0} {1}V{2}M{3} {2}h6", px(at), px(bottom), px(top), px(at - 3));
        if (!std::isnan(lo)) d += fmt::format("M{} {}h6", px(at - 3), px(bottom));
    }
    if (!d.empty())
        svg += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.4\"/>", d, series_color(i));
}

void append_xy_series(std::string& svg, const Plot& plot, const XyData& data, const Axis& ax, const Axis& ay) {
    const BarLayout bars = bar_layout(plot, data, ax, ay);
    for (std::size_t i = 0; i < data.series.size(); ++i) {
        const auto& points = data.series[i];
        if (plot.kind == Plot::Kind::Lines)
            append_line_series(svg, points, i, ax, ay);
        else if (plot.kind == Plot::Kind::Points)
            append_point_series(svg, points, series_color(i), ax, ay);
        else if (bars.grouped || i == 0)
            append_filled_bars(svg, points, i, bars, ax, ay);
        else
            append_step_outline(svg, points, series_color(i), bars.pixel_spacing, ax, ay);
        append_error_bars(svg, plot, i, ax, ay);
    }
}

constexpr const char* kLimitColor = "#c62828";

/// Text with a white halo, readable over curves and grid lines.
std::string halo_text(double x, double y, std::string_view anchor, const std::string& text) {
    return fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"{}\" fill=\"{}\" stroke=\"#fff\" stroke-width=\"3\" "
                       "paint-order=\"stroke\" font-weight=\"600\">{}</text>",
                       px(x), px(y), anchor, kLimitColor, escaped(text));
}

/// The limits as dashed lines across the plot area, each labelled at its end.
void append_limits(std::string& svg, const std::vector<LimitLine>& limits, const Axis& ax, const Axis& ay) {
    for (const LimitLine& l : limits) {
        const Axis& along = l.vertical ? ax : ay;
        if (!along.shows(l.value)) continue;
        const double at = along.map(l.value);
        svg += fmt::format("<path d=\"M{0} {1}{2}{3}\" stroke=\"{4}\" stroke-width=\"1.6\" stroke-dasharray=\"6 3\"/>",
                           px(l.vertical ? at : ax.from), px(l.vertical ? ay.to : at), l.vertical ? 'V' : 'H',
                           px(l.vertical ? ay.from : ax.to), kLimitColor);
        if (l.label.empty()) continue;
        if (l.vertical) {
            const bool right_half = at > (ax.from + ax.to) / 2;
            svg += halo_text(right_half ? at - 4 : at + 4, ay.to + 13, right_half ? "end" : "start", l.label);
        } else {
            svg += halo_text(ax.to - 4, at - 4, "end", l.label);
        }
    }
}

/// The highlights as rings, each labelled beside it (to the left in the right half).
void append_highlights(std::string& svg, const std::vector<Highlight>& highlights, const Axis& ax, const Axis& ay) {
    for (const Highlight& h : highlights) {
        if (!ax.shows(h.x) || !ay.shows(h.y)) continue;
        const double x = ax.map(h.x), y = ay.map(h.y);
        svg += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"6\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>", px(x),
                           px(y), kLimitColor);
        const bool right_half = x > (ax.from + ax.to) / 2;
        const double label_y = y < ay.to + 20 ? y + 18 : y - 9;
        if (!h.label.empty()) svg += halo_text(right_half ? x - 9 : x + 9, label_y, right_half ? "end" : "start", h.label);
    }
}

std::string render_xy(const Plot& plot, const SvgOptions& options) {
    const XyData data = xy_data(plot, options);
    Axis ax = x_axis_of(data.x, plot.log_x);
    Axis ay = make_axis(data.y, plot.log_y, true, 6);
    const XyFrame frame = xy_frame(plot, ay, options.width, options.height);
    ax.from = frame.left, ax.to = frame.right;
    ay.from = frame.bottom, ay.to = frame.top;

    std::string svg = svg_open(options.width, options.height, plot.title);
    svg += frame.legend_svg;
    append_axes(svg, ax, ay, frame.x_label, frame.y_label, 14.0);
    if (data.x.empty() || data.y.empty()) {
        svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"{}\">no data to plot</text>",
                           px((frame.left + frame.right) / 2), px((frame.top + frame.bottom) / 2), kAxisColor);
    } else {
        append_xy_series(svg, plot, data, ax, ay);
        append_limits(svg, options.limits, ax, ay);
        append_highlights(svg, options.highlights, ax, ay);
    }
    return svg + "</svg>";
}

// ---------------------------------------------------------------------------
// Heatmaps

bool well_formed(const Heatmap& h) {
    return h.rows > 0 && h.cols > 0 && h.values.size() == static_cast<std::size_t>(h.rows) * static_cast<std::size_t>(h.cols);
}

/// A colour scale shared by some heatmaps of a plot.
struct Scale {
    ColorMap map = ColorMap::Sequential;
    double lo = 0.0, hi = 1.0;
    std::vector<std::string> members;  ///< labels of the heatmaps that use it
    std::vector<const ScaleMark*> marks;  ///< values marked on its colour bar
    double t(double v) const { return (v - lo) / (hi - lo); }
};

ColorMap resolve(const Heatmap& h) {
    switch (h.color_scale) {
        case Heatmap::ColorScale::Sequential: return ColorMap::Sequential;
        case Heatmap::ColorScale::Diverging: return ColorMap::Diverging;
        case Heatmap::ColorScale::Auto: break;
    }
    bool negative = false, positive = false;
    for (double v : h.values) negative |= v < 0.0, positive |= v > 0.0;
    return negative && positive ? ColorMap::Diverging : ColorMap::Sequential;
}

/// Colour levels of a heatmap's image: 128 steps of its scale (a step is under
/// 1% of the range, below what the eye tells apart in a map of noise, and half
/// the palette keeps a report of a hundred heatmaps small).
constexpr int kColorLevels = 128;

/// The data URL of a heatmap's image: one pixel per cell, row 0 at the bottom,
/// cells without a value transparent (palette entry 0; the hatching behind
/// them shows).
std::string heatmap_image(const Heatmap& h, const Scale& scale) {
    std::vector<Rgba> palette(kColorLevels + 1);
    palette[0] = {0, 0, 0, 0};
    for (int i = 0; i < kColorLevels; ++i) palette[static_cast<std::size_t>(i + 1)] = color_at(scale.map, i / (kColorLevels - 1.0));
    std::vector<std::uint8_t> pixels(h.values.size());
    for (int r = 0; r < h.rows; ++r) {
        for (int c = 0; c < h.cols; ++c) {
            const double v = h.values[static_cast<std::size_t>(r) * static_cast<std::size_t>(h.cols) + static_cast<std::size_t>(c)];
            std::uint8_t index = 0;
            if (!std::isnan(v))
                index = static_cast<std::uint8_t>(1 + std::lround(std::clamp(scale.t(v), 0.0, 1.0) * (kColorLevels - 1)));
            pixels[static_cast<std::size_t>(h.rows - 1 - r) * static_cast<std::size_t>(h.cols) + static_cast<std::size_t>(c)] = index;
        }
    }
    return "data:image/png;base64," + base64(encode_palette_png(h.cols, h.rows, pixels, palette));
}

std::string join(const std::vector<std::string>& parts, std::string_view separator) {
    std::string out;
    for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? std::string(separator) : "") + parts[i];
    return out;
}

/// A horizontal colour bar with ticks, its title above; returns its height.
double append_color_bar(std::string& svg, const Scale& scale, const std::string& id, double x, double y, double width) {
    svg += fmt::format("<linearGradient id=\"{}\">", id);
    for (int i = 0; i <= 16; ++i)
        svg += fmt::format("<stop offset=\"{}\" stop-color=\"{}\"/>", px(i / 16.0 * 100.0) + "%", hex(color_at(scale.map, i / 16.0)));
    svg += "</linearGradient>";
    const std::string title = join(scale.members, ", ");
    svg += fmt::format("<text x=\"{}\" y=\"{}\" class=\"legend-title\">{}</text>", px(x), px(y + 10), escaped(title));
    const double bar_top = y + 16;
    svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"10\" fill=\"url(#{})\" stroke=\"{}\" stroke-width=\"0.5\"/>",
                       px(x), px(bar_top), px(width), id, kAxisColor);
    double lo = scale.lo, hi = scale.hi;
    const auto ticks = linear_ticks(lo, hi, 5, false);
    svg += "<g text-anchor=\"middle\">";
    for (const Tick& t : ticks) {
        const double tx = x + scale.t(t.value) * width;
        svg += fmt::format("<path d=\"M{} {}v13\" stroke=\"{}\"/><text x=\"{}\" y=\"{}\">{}</text>", px(tx), px(bar_top),
                           kAxisColor, px(tx), px(bar_top + 25), t.label.markup);
    }
    svg += "</g>";
    for (const ScaleMark* m : scale.marks) {
        const double v = std::abs(m->value);
        for (double value : scale.map == ColorMap::Diverging ? std::vector<double>{-v, v} : std::vector<double>{m->value}) {
            if (!(value >= lo && value <= hi)) continue;
            svg += fmt::format("<path d=\"M{} {}v16\" stroke=\"{}\" stroke-width=\"2\"/>", px(x + scale.t(value) * width),
                               px(bar_top - 3), kLimitColor);
        }
        if (!m->label.empty()) svg += halo_text(x, bar_top + 40, "start", m->label);
    }
    return 48.0;
}

/// The colour scales of a plot's heatmaps: one per colour map, over all
/// heatmaps that use it.
struct SharedScales {
    std::vector<Scale> scales;
    std::vector<std::size_t> scale_of;  ///< per heatmap, the index of its scale
    bool any_missing = false;           ///< some cell has no value (NaN)
};

/// Widens `scale` to the values of heatmap `h` and to its min_color_limit.
void widen_scale(Scale& scale, const Heatmap& h, bool& any_missing) {
    const double floor = std::abs(h.min_color_limit);
    if (floor > 0.0 && std::isfinite(floor)) {
        scale.hi = std::max(scale.hi, floor);
        if (scale.map == ColorMap::Diverging) scale.lo = std::min(scale.lo, -floor);
    }
    for (double v : h.values) {
        if (std::isnan(v)) {
            any_missing = true;
        } else if (std::isfinite(v)) {
            scale.lo = std::min(scale.lo, v);
            scale.hi = std::max(scale.hi, v);
        }
    }
}

/// A diverging scale is symmetric about 0; a sequential one of values >= 0
/// starts at 0, so that counts and densities that are flat look flat.
void settle_scale(Scale& s) {
    if (!(s.lo <= s.hi)) s.lo = 0.0, s.hi = 1.0;
    if (s.map == ColorMap::Diverging) {
        const double limit = std::max(std::abs(s.lo), std::abs(s.hi));
        s.lo = -(limit > 0 ? limit : 1.0), s.hi = -s.lo;
    } else {
        if (s.lo >= 0.0) s.lo = 0.0;
        if (s.hi <= s.lo) s.hi = s.lo + 1.0;
    }
}

SharedScales shared_scales(const std::vector<Heatmap>& maps, const std::vector<ScaleMark>& marks) {
    SharedScales shared;
    shared.scale_of.assign(maps.size(), 0);
    for (std::size_t i = 0; i < maps.size(); ++i) {
        if (!well_formed(maps[i])) continue;
        const ColorMap map = resolve(maps[i]);
        auto it = std::find_if(shared.scales.begin(), shared.scales.end(), [&](const Scale& s) { return s.map == map; });
        if (it == shared.scales.end()) {
            shared.scales.push_back({map, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), {}, {}});
            it = shared.scales.end() - 1;
        }
        shared.scale_of[i] = static_cast<std::size_t>(it - shared.scales.begin());
        it->members.push_back(maps[i].label.empty() ? fmt::format("map {}", i + 1) : maps[i].label);
        widen_scale(*it, maps[i], shared.any_missing);
    }
    for (const ScaleMark& m : marks) {
        if (m.heatmap >= maps.size() || !well_formed(maps[m.heatmap]) || !std::isfinite(m.value)) continue;
        Scale& scale = shared.scales[shared.scale_of[m.heatmap]];
        scale.marks.push_back(&m);
        scale.lo = std::min(scale.lo, m.value), scale.hi = std::max(scale.hi, m.value);
    }
    for (Scale& s : shared.scales) settle_scale(s);
    return shared;
}

/// The layout of heatmap panels: up to three in a row (two by two for four),
/// each with its own axes, the legends below them all.
struct PanelGrid {
    std::size_t per_row = 1;
    double panel_width = 0.0, panel_height = 0.0;  ///< the cells' area
    std::vector<std::string> x_label, y_label;     ///< wrapped into lines
    double margin_left = 0.0, margin_top = 22.0;   ///< from a grid cell's corner to its panel
    double cell_width = 0.0, cell_height = 0.0;    ///< a panel with its margins
    double legend_top = 0.0, width = 0.0, height = 0.0;

    double panel_x(std::size_t i) const { return static_cast<double>(i % per_row) * cell_width + margin_left; }
    double panel_y(std::size_t i) const { return static_cast<double>(i / per_row) * cell_height + margin_top; }
};

PanelGrid panel_grid(const Plot& plot) {
    PanelGrid g;
    const std::size_t n = std::max<std::size_t>(plot.heatmaps.size(), 1);
    g.per_row = n == 4 ? 2 : std::min<std::size_t>(n, 3);
    g.panel_width = g.per_row == 1 ? 440.0 : g.per_row == 2 ? 380.0 : 300.0;
    double aspect = 0.0;  // width / height of the widest grid of cells
    for (const Heatmap& h : plot.heatmaps)
        if (well_formed(h)) aspect = std::max(aspect, static_cast<double>(h.cols) / h.rows);
    aspect = std::clamp(aspect == 0.0 ? 1.0 : aspect, 0.75, 3.0);
    g.panel_height = std::min(g.panel_width / aspect, 320.0);
    g.x_label = wrap(plot.x_label, g.panel_width);
    g.y_label = wrap(plot.y_label, g.panel_height);
    const double extra_lines_x = g.x_label.empty() ? 0.0 : kLineHeight * static_cast<double>(g.x_label.size() - 1);
    const double extra_lines_y = g.y_label.empty() ? 0.0 : kLineHeight * static_cast<double>(g.y_label.size() - 1);
    g.margin_left = (g.y_label.empty() ? 16.0 : 34.0 + extra_lines_y) + 34.0;
    const double margin_bottom = g.x_label.empty() ? 28.0 : 44.0 + extra_lines_x, gap = 18.0;
    g.cell_width = g.margin_left + g.panel_width + gap;
    g.cell_height = g.margin_top + g.panel_height + margin_bottom;
    const std::size_t panel_rows = (n + g.per_row - 1) / g.per_row;
    g.legend_top = static_cast<double>(panel_rows) * g.cell_height + 6.0;
    g.width = static_cast<double>(g.per_row) * g.cell_width + 4.0;
    const double legend_height = 56.0;
    g.height = g.legend_top + legend_height;
    return g;
}

/// The hatching shown behind cells without a value, as a pattern with id `id`.
std::string hatch_pattern(const std::string& id) {
    return fmt::format(
        "<defs><pattern id=\"{}\" width=\"6\" height=\"6\" patternUnits=\"userSpaceOnUse\" patternTransform=\"rotate(45)\">"
        "<rect width=\"6\" height=\"6\" fill=\"#eceef1\"/><path d=\"M0 0V6\" stroke=\"#a7adb5\" stroke-width=\"2\"/></pattern></defs>",
        id);
}

/// A panel's title over the hatching that shows through cells without a value.
std::string panel_background(const Heatmap& h, double x0, double y0, const PanelGrid& g, const std::string& hatch) {
    return fmt::format("<text x=\"{}\" y=\"{}\" class=\"panel-title\">{}</text>", px(x0), px(y0 - 8), escaped(h.label)) +
           fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"url(#{})\"/>", px(x0), px(y0),
                       px(g.panel_width), px(g.panel_height), hatch);
}

/// What a panel shows when the heatmap's size and values disagree.
std::string malformed_note(const Heatmap& h, double x0, double y0, const PanelGrid& g) {
    return fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">malformed heatmap: {} x {} cells, {} values</text>",
                       px(x0 + g.panel_width / 2), px(y0 + g.panel_height / 2), h.rows, h.cols, h.values.size());
}

/// A panel's frame, ticks and axis labels, without the grid, which would hide cells.
void append_panel_axes(std::string& svg, const Heatmap& h, const PanelGrid& g, double x0, double y0) {
    Axis ax = make_axis(Range{h.x_min, h.x_max}, false, false, 5);
    Axis ay = make_axis(Range{h.y_min, h.y_max}, false, false, 4);
    ax.from = x0, ax.to = x0 + g.panel_width;
    ay.from = y0 + g.panel_height, ay.to = y0;
    svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"{}\"/>", px(x0), px(y0),
                       px(g.panel_width), px(g.panel_height), kAxisColor);
    svg += "<g text-anchor=\"middle\">";
    for (const Tick& t : ax.ticks)
        svg += fmt::format("<path d=\"M{0} {1}v4\" stroke=\"{2}\"/><text x=\"{0}\" y=\"{3}\">{4}</text>", px(ax.map(t.value)),
                           px(ay.from), kAxisColor, px(ay.from + 16), t.label.markup);
    svg += "</g><g text-anchor=\"end\">";
    for (const Tick& t : ay.ticks)
        svg += fmt::format("<path d=\"M{0} {1}h-4\" stroke=\"{2}\"/><text x=\"{3}\" y=\"{1}\" dy=\"0.35em\">{4}</text>", px(x0),
                           px(ay.map(t.value)), kAxisColor, px(x0 - 7), t.label.markup);
    svg += "</g>";
    if (!g.x_label.empty()) svg += axis_label(g.x_label, x0 + g.panel_width / 2, ay.from + 34, false);
    if (!g.y_label.empty()) svg += axis_label(g.y_label, x0 - g.margin_left + 14, y0 + g.panel_height / 2, true);
}

/// The cells of a well-formed heatmap as one image, with the panel's axes.
void append_cells(std::string& svg, const Heatmap& h, const Scale& scale, double x0, double y0, const PanelGrid& g) {
    svg += fmt::format(
        "<image x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" preserveAspectRatio=\"none\" class=\"cells\" href=\"{}\"/>", px(x0),
        px(y0), px(g.panel_width), px(g.panel_height), heatmap_image(h, scale));
    append_panel_axes(svg, h, g, x0, y0);
}

/// Below the panels: one colour bar per scale, then the swatch for cells without a value.
void append_heatmap_legends(std::string& svg, const SharedScales& shared, const PanelGrid& g, const std::string& id_prefix,
                            const std::string& hatch) {
    double x = g.margin_left;
    for (std::size_t s = 0; s < shared.scales.size(); ++s) {
        append_color_bar(svg, shared.scales[s], fmt::format("{}-scale{}", id_prefix, s), x, g.legend_top, 220.0);
        x += 220.0 + 48.0;
    }
    if (shared.any_missing) {
        svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"16\" height=\"10\" fill=\"url(#{})\" stroke=\"{}\" stroke-width=\"0.5\"/>",
                           px(x), px(g.legend_top + 16), hatch, kAxisColor);
        svg += fmt::format("<text x=\"{}\" y=\"{}\" dy=\"0.35em\">no value (e.g. pooled)</text>", px(x + 22), px(g.legend_top + 21));
    }
}

/// Rings the highlighted cells of well-formed heatmaps, labelled beside the ring.
void append_cell_highlights(std::string& svg, const Plot& plot, const SvgOptions& options, const PanelGrid& g) {
    for (const CellHighlight& c : options.cells) {
        if (c.heatmap >= plot.heatmaps.size() || !well_formed(plot.heatmaps[c.heatmap])) continue;
        const Heatmap& h = plot.heatmaps[c.heatmap];
        if (c.row < 0 || c.row >= h.rows || c.col < 0 || c.col >= h.cols) continue;
        const double cell_w = g.panel_width / h.cols, cell_h = g.panel_height / h.rows;
        const double x = g.panel_x(c.heatmap) + (c.col + 0.5) * cell_w;
        const double y = g.panel_y(c.heatmap) + (h.rows - c.row - 0.5) * cell_h;
        const double r = std::max({6.0, cell_w * 0.75, cell_h * 0.75});
        svg += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"none\" stroke=\"#111\" stroke-width=\"2\"/>"
                           "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"none\" stroke=\"#fff\" stroke-width=\"1\"/>",
                           px(x), px(y), px(r), px(x), px(y), px(r + 1.5));
        if (c.label.empty()) continue;
        const bool right_half = x > g.panel_x(c.heatmap) + g.panel_width / 2;
        const bool top_half = y < g.panel_y(c.heatmap) + g.panel_height / 2;
        svg += halo_text(right_half ? x - r - 3 : x + r + 3, top_half ? y + r + 12 : y - r - 4, right_half ? "end" : "start",
                         c.label);
    }
}

std::string render_heatmaps(const Plot& plot, const SvgOptions& options) {
    const auto& maps = plot.heatmaps;
    const SharedScales shared = shared_scales(maps, options.scale_marks);
    PanelGrid grid = panel_grid(plot);
    if (!options.scale_marks.empty()) grid.height += 14.0;  // the marks' labels below the colour bars
    const std::string hatch = options.id_prefix + "-nan";
    std::string svg = svg_open(grid.width, grid.height, plot.title);
    svg += hatch_pattern(hatch);
    for (std::size_t i = 0; i < maps.size(); ++i) {
        const double x0 = grid.panel_x(i), y0 = grid.panel_y(i);
        svg += panel_background(maps[i], x0, y0, grid, hatch);
        if (well_formed(maps[i]))
            append_cells(svg, maps[i], shared.scales[shared.scale_of[i]], x0, y0, grid);
        else
            svg += malformed_note(maps[i], x0, y0, grid);
    }
    append_cell_highlights(svg, plot, options, grid);
    append_heatmap_legends(svg, shared, grid, options.id_prefix, hatch);
    if (maps.empty())
        svg += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"{}\">no heatmaps</text>", px(grid.margin_left), px(grid.margin_top + 20),
                           kAxisColor);
    return svg + "</svg>";
}

}  // namespace

std::string render_svg(const Plot& plot, const SvgOptions& options) {
    SvgOptions marked = options;  // the plot's own marks first, then the caller's
    marked.limits.insert(marked.limits.begin(), plot.limits.begin(), plot.limits.end());
    marked.highlights.insert(marked.highlights.begin(), plot.highlights.begin(), plot.highlights.end());
    marked.cells.insert(marked.cells.begin(), plot.cells.begin(), plot.cells.end());
    marked.scale_marks.insert(marked.scale_marks.begin(), plot.scale_marks.begin(), plot.scale_marks.end());
    if (plot.kind == Plot::Kind::Heatmaps) return render_heatmaps(plot, marked);
    return render_xy(plot, marked);
}

}  // namespace warpcheck
