// Reading what people type: counts written as 1e6, 10M or 1_000_000, limits
// stated in words, and "did you mean" for a misspelt option, case or check.
// Used by the validate command line and by the WARPCHECK_* variables of the
// GoogleTest adapter, so that both read and refuse a value the same way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace warpcheck {

struct RunOptions;

/// The limits of the run settings, for the command line and the WARPCHECK_*
/// variables alike.
inline constexpr uint64_t kMinSamples = 1000, kMaxSamples = 10'000'000'000;
inline constexpr double kMinAlpha = 1e-12, kMaxAlpha = 0.5;
inline constexpr double kMinBudget = 0.1, kMaxBudget = 86400.0;     ///< --time-budget, seconds
inline constexpr uint64_t kMaxMemoryMib = uint64_t{1} << 30;        ///< --memory-limit, MiB

/// A whole number as people type it: digits with '_' or '\'' between them
/// (1_000_000), a decimal or an exponent whose value is whole (1e6, 2.5e6),
/// and an SI suffix k, M, G or T (10M, 1.5k). Empty `problem` on success.
struct ParsedCount {
    uint64_t value = 0;
    std::string problem;  ///< e.g. "'1.5' is not a whole number"
};
ParsedCount parse_count(std::string_view text);

/// `text` read as a count in [min, max], with the problem stated for a person
/// ("100 is out of range: from 1,000 to 10,000,000,000").
ParsedCount parse_count_in(std::string_view text, uint64_t min, uint64_t max);

/// A finite real number in [min, max] (decimal or scientific notation, no
/// suffix). Empty `problem` on success.
struct ParsedReal {
    double value = 0.0;
    std::string problem;
};
ParsedReal parse_real_in(std::string_view text, double min, double max);

/// A count for people: digits grouped in threes by commas, "10,000,000,000".
std::string format_count(uint64_t value);

/// A limit for people: the shortest decimal that reads back as `value`
/// ("1e-12", "0.5", "86400"), never "0.500000".
std::string format_limit(double value);

/// Edit distance (optimal string alignment: insertions, deletions,
/// substitutions and transpositions of neighbours each cost 1).
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The smallest edit distance between `pattern` and any substring of `text`:
/// how far a --filter pattern, which matches substrings, is from matching.
std::size_t substring_edit_distance(std::string_view pattern, std::string_view text);

/// The candidates closest to `typed` (at most `limit`, all at the smallest
/// distance found, those nearest as whole names first), or none when even the
/// closest is more than a third of `typed` away (at least 1 edit is always
/// allowed). With `substring`, a candidate's distance is
/// substring_edit_distance (patterns that match parts).
std::vector<std::string> closest_names(std::string_view typed, const std::vector<std::string>& candidates,
                                       bool substring = false, std::size_t limit = 3);

/// " (did you mean 'a'?)", " (did you mean 'a', 'b' or 'c'?)", or "" for none.
std::string did_you_mean(const std::vector<std::string>& suggestions);

/// Applies WARPCHECK_SEED, WARPCHECK_SAMPLES, WARPCHECK_ALPHA and
/// WARPCHECK_TIME_BUDGET, each where it is set and not empty, to `run`, read
/// as the options --seed, --samples, --alpha and --time-budget read them; and
/// WARPCHECK_MEMORY_LIMIT (--memory-limit, MiB) to `memory_limit_mib`, where
/// given. Returns the problem with the first invalid one, e.g.
/// "WARPCHECK_SAMPLES='lots' is not a count (...)", or "" when all are valid.
std::string apply_environment_settings(RunOptions& run, std::optional<uint64_t>* memory_limit_mib = nullptr);

}  // namespace warpcheck
