// Bookkeeping that every check's compute part shares: the K worst items seen,
// the first example of each kind of violation, and merging per-chunk partial
// results in chunk order. Each keeper orders by (key, input index), a total
// order, so the merged result is the same whichever thread ran which chunk.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace warpcheck {

/// The K items with the largest key, worst first. A NaN key ranks above every
/// number (a NaN error is the worst kind); equal keys keep the earlier input
/// index, so the list does not depend on the order in which chunks are merged.
template <typename T>
class WorstK {
public:
    struct Entry {
        double key = 0.0;
        uint64_t index = 0;  ///< position of the input in the check's input order
        T item;
    };

    explicit WorstK(std::size_t k = 10) : k_(k) {}

    /// Whether an item with this key would enter the list (a cheap test before
    /// building the item).
    bool wants(double key) const { return entries_.size() < k_ || before(rank(key), 0, entries_.back()); }

    void offer(double key, uint64_t index, T item) {
        const double r = rank(key);
        if (entries_.size() == k_ && !before(r, index, entries_.back())) return;
        Entry e{key, index, std::move(item)};
        auto at = std::upper_bound(entries_.begin(), entries_.end(), e,
                                   [](const Entry& a, const Entry& b) { return before(rank(a.key), a.index, b); });
        entries_.insert(at, std::move(e));
        if (entries_.size() > k_) entries_.pop_back();
    }

    void merge(const WorstK& other) {
        for (const Entry& e : other.entries_) offer(e.key, e.index, e.item);
    }

    const std::vector<Entry>& entries() const { return entries_; }
    bool empty() const { return entries_.empty(); }
    const Entry& front() const { return entries_.front(); }

private:
    static double rank(double key) { return std::isnan(key) ? std::numeric_limits<double>::infinity() : key; }
    static bool before(double rank_a, uint64_t index_a, const Entry& b) {
        const double rank_b = rank(b.key);
        return rank_a != rank_b ? rank_a > rank_b : index_a < b.index;
    }

    std::size_t k_;
    std::vector<Entry> entries_;
};

/// How often one kind of violation happened, with its first example in input
/// order.
template <typename T>
struct Tally {
    uint64_t count = 0;
    uint64_t first_index = 0;
    std::optional<T> first;

    void add(uint64_t index, const T& example) {
        if (count++ == 0 || index < first_index) {
            first_index = index;
            first = example;
        }
    }
    void merge(const Tally& other) {
        if (other.count == 0) return;
        if (count == 0 || other.first_index < first_index) {
            first_index = other.first_index;
            first = other.first;
        }
        count += other.count;
    }
};

/// Merges the partial results of chunks in chunk order: `Part` has a member
/// `void merge(const Part&)`.
template <typename Part>
Part merge_in_order(const std::vector<Part>& parts) {
    Part total{};
    for (const Part& p : parts) total.merge(p);
    return total;
}

/// Larger of two errors where NaN wins, so a NaN error is never hidden behind a
/// finite maximum.
inline double max_nan_wins(double a, double b) { return (std::isnan(a) || a >= b) ? a : b; }

/// "a; b; c": the reasons of one verdict, in the order the rule states them.
inline std::string join_reasons(const std::vector<std::string>& reasons) {
    std::string out;
    for (const auto& r : reasons) {
        if (r.empty()) continue;
        if (!out.empty()) out += "; ";
        out += r;
    }
    return out;
}

}  // namespace warpcheck
