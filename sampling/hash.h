// Hashing of names and integers into seeds and PCG32 stream indices. A (case,
// check) stream is derived from what it is (its name and the global seed), never
// from when or where it runs, so results do not depend on threads or selection.
#pragma once

#include <cstdint>
#include <string_view>

namespace warpcheck {

/// The 64-bit finaliser of SplitMix64: a bijection with full avalanche.
constexpr uint64_t mix64(uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    x ^= x >> 31;
    return x;
}

/// FNV-1a over the bytes of `text`, then mixed: a stable hash (no dependence on
/// the standard library's std::hash, which differs between implementations).
constexpr uint64_t hash_string(std::string_view text) {
    uint64_t h = 0xcbf29ce484222325ULL;
    for (char c : text) {
        h ^= static_cast<unsigned char>(c);
        h *= 0x100000001b3ULL;
    }
    return mix64(h);
}

/// Combines a running hash with one more value; order matters.
constexpr uint64_t hash_combine(uint64_t h, uint64_t value) {
    return mix64(h ^ (mix64(value) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2)));
}

template <typename... Ts>
constexpr uint64_t hash_values(uint64_t first, Ts... rest) {
    uint64_t h = mix64(first);
    ((h = hash_combine(h, static_cast<uint64_t>(rest))), ...);
    return h;
}

/// Seed and stream index of the PCG32 stream for `name` under `global_seed`.
struct StreamId {
    uint64_t seed = 0;
    uint64_t sequence = 0;
};

constexpr StreamId stream_for(std::string_view name, uint64_t global_seed) {
    const uint64_t h = hash_combine(hash_string(name), global_seed);
    return {mix64(h ^ 0x5eedULL), h};
}

}  // namespace warpcheck
