// How checks walk their inputs: a chunk of edge inputs, then random inputs in
// chunks of fixed size, each chunk from its own stream. Results come back in
// chunk order, so whatever the thread count the merged figures are identical.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "validate/checks/check.h"

namespace warpcheck {

inline constexpr std::size_t kInputChunkSize = std::size_t{1} << 16;

/// Pilot samples (which place a check's cells or strips) come from the
/// streams of chunks past any a check draws (2^40 chunks): independent of the
/// samples it tests.
inline constexpr uint64_t kPilotChunkBase = uint64_t{1} << 40;

/// `count` inputs of `kind` from the pilot streams, chunk c of kInputChunkSize
/// from ctx.chunk_rng(kPilotChunkBase + c), in order.
std::vector<WarpInput> pilot_inputs(const CheckContext& ctx, InputKind kind, std::size_t count);

/// The edge values of one uniform coordinate: 0, every power of two 2^-k down to
/// the smallest denormal with its float neighbours, and the largest float below 1.
std::vector<float> edge_values();

/// The inputs at the edges of the input space: the edge values in 1D; in 2D
/// all pairs of {0, 2^-24, 0.5, 1 - 2^-24} and each edge value in one
/// coordinate with one of those in the other; in 3D likewise (the corners, and
/// each edge value with a pair of corners in the other two). For raw bits: 0, 1, the middle,
/// and the two largest values.
std::vector<WarpInput> edge_inputs(InputKind kind);

/// Calls f(chunk_index, inputs) for every chunk and returns the results in chunk
/// order. Chunk 0 holds the edge inputs (empty if !with_edges); chunks 1.. hold
/// `samples` random inputs, chunk c drawn from ctx.chunk_rng(c).
template <typename Result, typename F>
std::vector<Result> map_input_chunks(const CheckContext& ctx, InputKind kind, uint64_t samples, bool with_edges,
                                     F&& f) {
    const std::size_t random_chunks = static_cast<std::size_t>((samples + kInputChunkSize - 1) / kInputChunkSize);
    std::vector<Result> results(random_chunks + 1);
    ctx.parallel_for(random_chunks + 1, [&](std::size_t chunk) {
        ctx.throw_if_cancelled();
        std::vector<WarpInput> inputs;
        if (chunk == 0) {
            if (with_edges) inputs = edge_inputs(kind);
        } else {
            const uint64_t first = (chunk - 1) * kInputChunkSize;
            inputs.resize(static_cast<std::size_t>(std::min<uint64_t>(kInputChunkSize, samples - first)));
            Pcg32 rng = ctx.chunk_rng(chunk);
            draw_inputs(rng, kind, inputs);
        }
        results[chunk] = f(chunk, std::span<const WarpInput>(inputs));
    });
    return results;
}

}  // namespace warpcheck
