#include "validate/samples/replay_case.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

#include <fmt/format.h>

namespace warpcheck {

namespace {

WarpCaseInfo without_lanes(WarpCaseInfo info) {
    info.lanes = nullptr;  // the lane form would warp inputs that sample() never sees
    return info;
}

WarpSignature replayed_signature(const WarpCase& reference, bool with_values) {
    WarpSignature s = reference.signature();
    s.has_inverse = false;  // the other program's inverse is not in the table
    if (!with_values && !reference.is_discrete()) s.returns = SampleReturns::Point;
    if (!with_values && reference.sample_returns() == SampleReturns::IndexAndRemappedU) s.returns = SampleReturns::Index;
    return s;
}

std::string describe_input(const WarpInput& in, InputKind kind) {
    if (takes_bits(kind)) return fmt::format("bits {:#x}", in.bits);
    const int dims = input_dimension(kind);
    std::string text = "u = (";
    for (int c = 0; c < dims; ++c) text += fmt::format("{}{}", c ? ", " : "", in.u[static_cast<std::size_t>(c)]);
    return text + ")";
}

}  // namespace

RecordingCase::RecordingCase(const WarpCase& inner)
    : WarpCase(without_lanes(inner.info()), inner.signature()), inner_(inner) {}

void RecordingCase::record(std::span<const WarpInput> in) const {
    const std::lock_guard lock(mutex_);
    inputs_.insert(inputs_.end(), in.begin(), in.end());
}

void RecordingCase::sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const {
    record(in);
    inner_.sample(in, out);
}

void RecordingCase::sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                                      std::span<double> value) const {
    record(in);
    inner_.sample_with_value(in, out, value);
}

std::vector<WarpInput> RecordingCase::recorded_inputs() const {
    std::vector<WarpInput> inputs;
    {
        const std::lock_guard lock(mutex_);
        inputs = inputs_;
    }
    const auto less = [](const WarpInput& a, const WarpInput& b) { return ReplayCase::key_of(a) < ReplayCase::key_of(b); };
    const auto same = [](const WarpInput& a, const WarpInput& b) { return ReplayCase::key_of(a) == ReplayCase::key_of(b); };
    std::sort(inputs.begin(), inputs.end(), less);
    inputs.erase(std::unique(inputs.begin(), inputs.end(), same), inputs.end());
    return inputs;
}

ReplayCase::Key ReplayCase::key_of(const WarpInput& in) {
    return {std::bit_cast<uint32_t>(in.u[0]), std::bit_cast<uint32_t>(in.u[1]), std::bit_cast<uint32_t>(in.u[2]),
            in.bits};
}

ReplayCase::ReplayCase(const WarpCase& reference, RecordedSamples table)
    : WarpCase(without_lanes(reference.info()), replayed_signature(reference, table.values.has_value())),
      reference_(reference),
      table_(std::move(table)) {
    if (table_.inputs.size() != table_.outputs.size() || (table_.values && table_.values->size() != table_.inputs.size()))
        throw std::invalid_argument(fmt::format("replay of {}: {} inputs but {} outputs", name(), table_.inputs.size(),
                                                table_.outputs.size()));
    keys_.reserve(table_.inputs.size());
    for (std::size_t i = 0; i < table_.inputs.size(); ++i) keys_.emplace_back(key_of(table_.inputs[i]), i);
    std::sort(keys_.begin(), keys_.end());
    // One input recorded twice must have one answer: bits compared, so NaN equals NaN.
    const auto same_row = [&](std::size_t a, std::size_t b) {
        const bool same_value = !table_.values || std::bit_cast<uint64_t>((*table_.values)[a]) ==
                                                      std::bit_cast<uint64_t>((*table_.values)[b]);
        return std::bit_cast<std::array<uint32_t, 3>>(table_.outputs[a]) ==
                   std::bit_cast<std::array<uint32_t, 3>>(table_.outputs[b]) &&
               same_value;
    };
    std::vector<std::pair<Key, std::size_t>> distinct;
    for (const auto& entry : keys_) {
        if (!distinct.empty() && distinct.back().first == entry.first) {
            if (!same_row(distinct.back().second, entry.second))
                throw std::invalid_argument(fmt::format("replay of {}: rows {} and {} have the same input ({}) but "
                                                        "different outputs",
                                                        name(), distinct.back().second, entry.second,
                                                        describe_input(table_.inputs[entry.second], input_kind())));
            continue;
        }
        distinct.push_back(entry);
    }
    keys_ = std::move(distinct);
}

std::size_t ReplayCase::row_of(const WarpInput& in) const {
    const Key key = key_of(in);
    const auto at = std::lower_bound(keys_.begin(), keys_.end(), key,
                                     [](const std::pair<Key, std::size_t>& e, const Key& k) { return e.first < k; });
    if (at == keys_.end() || at->first != key)
        throw std::runtime_error(fmt::format(
            "replay: the input {} was not recorded ({} inputs are): the recording was made for another selection of "
            "checks, --seed or --samples; record again with validate --record-inputs and the same options",
            describe_input(in, input_kind()), keys_.size()));
    return at->second;
}

void ReplayCase::sample(std::span<const WarpInput> in, std::span<WarpOutput> out) const {
    for (std::size_t k = 0; k < in.size(); ++k) out[k] = table_.outputs[row_of(in[k])];
}

void ReplayCase::sample_with_value(std::span<const WarpInput> in, std::span<WarpOutput> out,
                                   std::span<double> value) const {
    if (!table_.values) return WarpCase::sample_with_value(in, out, value);
    for (std::size_t k = 0; k < in.size(); ++k) {
        const std::size_t row = row_of(in[k]);
        out[k] = table_.outputs[row];
        value[k] = (*table_.values)[row];
    }
}

void ReplayCase::invert(std::span<const WarpOutput> x, std::span<WarpInput> out) const {
    (void)x, (void)out;
    throw std::logic_error("replay of " + name() + ": a replayed warp has no inverse");
}

}  // namespace warpcheck
