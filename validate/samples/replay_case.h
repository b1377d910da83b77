// Record and replay: a warp's outputs computed elsewhere (another build, a GPU
// kernel, another language), for exactly the inputs warpcheck's checks draw, fed
// back to the same checks. Same inputs and same outputs give the same figures,
// bit for bit, as the warp run in-process; a device whose outputs differ is
// judged by the same rules.
//
//   1. RecordingCase runs the checks on the warp itself and records every input
//      they ask of sample (validate --record-inputs FILE);
//   2. the other program reads those inputs and writes its outputs, row for row;
//   3. ReplayCase answers sample from that table (validate --replay INPUTS OUTPUTS),
//      with the reference case's description, pdf and eval.
//
// The replayed case has no inverse (the other program's inverse is not in the
// table), so the round trips are n/a; every check whose inputs do not depend on
// the warp's answers runs as it did. An input the table does not hold makes
// the check an ERROR row that says so.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "validate/api/warp_case.h"

namespace warpcheck {

/// The warp case `inner` with every input of sample recorded (thread-safe).
/// The same name, description, parts and answers; the lane form left out, so
/// that every sample goes through sample().
class RecordingCase final : public WarpCase {
public:
    explicit RecordingCase(const WarpCase& inner);

    /// The distinct inputs asked so far, sorted by their bits (a fixed order,
    /// whichever thread asked first).
    std::vector<WarpInput> recorded_inputs() const;

    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override;
    void sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                           std::span<double> value) const override;
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override { inner_.pdf(x, out); }
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override { inner_.invert(x, out); }
    void eval(std::span<const WarpOutput> x, std::span<double> out) const override { inner_.eval(x, out); }

private:
    void record(std::span<const WarpInput> in) const;

    const WarpCase& inner_;
    mutable std::mutex mutex_;
    mutable std::vector<WarpInput> inputs_;
};

/// A recorded table: inputs, the outputs another program computed for them
/// (row for row), and the values sample returned with them where it returns one.
struct RecordedSamples {
    std::vector<WarpInput> inputs;
    std::vector<WarpOutput> outputs;
    std::optional<std::vector<double>> values;
};

/// The reference case with sample answered from a recorded table.
class ReplayCase final : public WarpCase {
public:
    /// Throws std::invalid_argument when the table's rows disagree in number
    /// or one input is recorded twice with different outputs.
    ReplayCase(const WarpCase& reference, RecordedSamples table);

    std::size_t recorded() const { return keys_.size(); }

    void sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const override;
    void sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                           std::span<double> value) const override;
    void pdf(std::span<const WarpOutput> x, std::span<double> out) const override { reference_.pdf(x, out); }
    void invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const override;
    void eval(std::span<const WarpOutput> x, std::span<double> out) const override { reference_.eval(x, out); }

    /// An input as a sortable key: its coordinates' bits and its raw bits.
    struct Key {
        uint32_t u0 = 0, u1 = 0, u2 = 0;
        uint64_t bits = 0;
        auto operator<=>(const Key&) const = default;
    };
    static Key key_of(const WarpInput& in);

private:
    std::size_t row_of(const WarpInput& in) const;

    const WarpCase& reference_;
    std::vector<std::pair<Key, std::size_t>> keys_;  ///< sorted: each distinct input and its row
    RecordedSamples table_;
};

}  // namespace warpcheck
