#include "chi2/sweep_recount.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <iterator>
#include <limits>
#include <memory>
#include <new>
#include <vector>

namespace warpcheck::chi2::sweep {
namespace {

// LSD radix sort of keys, 11 bits a pass.
void radix_sort(std::vector<uint32_t>& keys) {
    std::vector<uint32_t> tmp(keys.size());
    for (int shift = 0; shift < 32; shift += 11) {
        std::vector<std::size_t> count(2049, 0);
        for (uint32_t k : keys) ++count[((k >> shift) & 2047u) + 1];
        for (std::size_t i = 1; i < count.size(); ++i) count[i] += count[i - 1];
        for (uint32_t k : keys) tmp[count[(k >> shift) & 2047u]++] = k;
        keys.swap(tmp);
    }
}

// The window recount (see chi2/float_sweep.h): one-byte counters over the key ranges
// of a window's binades, filled by radix partitioning in rounds of
// kRoundChunks chunks. First each chunk of the round appends the counter
// indices of its outputs to blocks of the slice they fall in (the smallest
// power of two of at least 2^16 counters that makes at most 257 slices: at
// most 2 MiB, within L2, for windows of at most 64 binades), in one pass: each slice
// gathers 16 indices in a cache line of its own and writes them out whole with
// a streaming store, so the round buffer is written once, without being read
// first, and never goes through the cache. Then each slice adds the blocks of
// every chunk of the round, so the increments of a slice stay in cache, and no
// two threads touch one counter (no locks, no atomics). A counter that wraps
// past 255 records the wrap in its slice's list: a count is its counter plus
// 256 per recorded wrap, so the lists hold at most count / 256 entries.
constexpr std::size_t kRoundChunks = 16;
// Indices per block (4 KiB). A chunk of n inputs over S slices fills at most
// n / kBlockEntries + S blocks (all but each slice's last are full): 17 MiB a
// chunk for 257 slices, 272 MiB a round.
constexpr uint32_t kBlockEntries = 1024;
constexpr uint32_t kLineEntries = 16;  // indices per 64-byte line
// Keys outside the first window kept for counting by sorting: 2^14 per chunk
// of the sweep, 2^24 (64 MiB) over 2^32 inputs, shared by all chunks (a
// sampler that is monotone but for local swaps puts all of its first chunks'
// outputs outside the window, and a budget per chunk sent it through a second
// pass of f). More than the budget makes the recount count the remaining
// binades in further windows instead; either way the counts are exact.
constexpr std::size_t kStraysPerChunk = std::size_t{1} << 14;

// The strays' shared budget: keys kept so far by all chunks, and whether they
// overran it (then nobody keeps more: the further windows will count them).
// Whether it overruns depends only on the total number of strays, not on the
// order the chunks ran in. Memory: the budget plus one block per thread.
struct StrayBudget {
    uint64_t limit = 0;
    std::atomic<uint64_t> kept{0};
    std::atomic<bool> overrun{false};

    // Takes n more keys; false once the budget is overrun.
    bool take(uint64_t n) {
        if (overrun.load(std::memory_order_relaxed)) return false;
        if (kept.fetch_add(n, std::memory_order_relaxed) + n <= limit) return true;
        overrun.store(true, std::memory_order_relaxed);
        return false;
    }
};

// What the first window pass notes of each chunk, for the steps down and the
// reach (the first pass of the sweep stops once it knows f is not monotone):
// the steps down within the chunk, its first and last key, and the smallest
// and largest key.
struct ChunkTrace {
    uint64_t steps_down = 0;
    uint32_t first = 0, last = 0, lo = ~0u, hi = 0;

    void add(const uint32_t* k, std::size_t n, bool chunk_start) {
        if (n == 0) return;
        if (chunk_start) first = last = k[0];
        uint64_t down = k[0] < last;
        uint32_t low = lo, high = hi;
        for (std::size_t i = 1; i < n; ++i) down += k[i] < k[i - 1];
        for (std::size_t i = 0; i < n; ++i) {
            low = std::min(low, k[i]);
            high = std::max(high, k[i]);
        }
        steps_down += down;
        lo = low;
        hi = high;
        last = k[n - 1];
    }
};

// The steps down over all inputs from the chunks' traces (in chunk order).
uint64_t steps_down_of(const std::vector<ChunkTrace>& traces) {
    uint64_t down = 0;
    for (std::size_t c = 0; c < traces.size(); ++c)
        down += traces[c].steps_down + (c > 0 && traces[c].first < traces[c - 1].last);
    return down;
}

struct Window {
    // Keys [lo, lo + size) are counted at counters [base, base + size).
    struct Range {
        uint32_t lo = 0, size = 0, base = 0;
    };
    std::vector<Range> ranges;
    std::vector<uint8_t> counts;
    int slice_shift = 16;
    std::size_t slices = 1;
    std::vector<std::vector<uint32_t>> wraps;  // per slice

    // The key ranges of these binades (in increasing order), adjacent ones joined.
    explicit Window(const std::vector<int>& groups) {
        uint32_t base = 0;
        for (const int g : groups) {
            const auto lo = static_cast<uint32_t>(group_key_lo(g));
            const auto size = static_cast<uint32_t>(group_key_hi(g) - group_key_lo(g));
            if (!ranges.empty() && ranges.back().lo + ranges.back().size == lo) ranges.back().size += size;
            else ranges.push_back({lo, size, base});
            base += size;
        }
        counts.assign(base, 0);
        while ((uint64_t{base} >> slice_shift) > 256) ++slice_shift;
        slices = (uint64_t{base} + (uint64_t{1} << slice_shift) - 1) >> slice_shift;
        wraps.resize(slices);
    }
};

// 4 KiB-aligned storage (blocks and cache lines start at their own alignment).
struct AlignedFree {
    void operator()(uint32_t* p) const { std::free(p); }
};
using AlignedIndices = std::unique_ptr<uint32_t[], AlignedFree>;
AlignedIndices aligned_indices(std::size_t n) {
    const std::size_t bytes = (n * sizeof(uint32_t) + 4095) / 4096 * 4096;
    auto* p = static_cast<uint32_t*>(std::aligned_alloc(4096, std::max<std::size_t>(bytes, 4096)));
    if (p == nullptr) throw std::bad_alloc();
    return AlignedIndices(p);
}

// Writes one full line of 16 indices (64-byte aligned at both ends): a
// streaming store where there is one, so the line is not read first.
inline void write_line(uint32_t* to, const uint32_t* from) {
#if defined(__x86_64__)
    auto* dst = reinterpret_cast<__m128i*>(to);
    const auto* src = reinterpret_cast<const __m128i*>(from);
    _mm_stream_si128(dst, _mm_load_si128(src));
    _mm_stream_si128(dst + 1, _mm_load_si128(src + 1));
    _mm_stream_si128(dst + 2, _mm_load_si128(src + 2));
    _mm_stream_si128(dst + 3, _mm_load_si128(src + 3));
#else
    std::memcpy(to, from, kLineEntries * sizeof(uint32_t));
#endif
}

// One chunk's part of a round: its blocks, which slice each holds and how
// full it is, and after partitioning, its blocks grouped by slice.
struct ChunkBlocks {
    uint32_t* entries = nullptr;          // capacity blocks of kBlockEntries
    std::vector<uint32_t> slice_of, fill;  // per block
    std::vector<uint32_t> by_slice, slice_start;  // blocks of slice s: by_slice[slice_start[s] .. slice_start[s + 1])
    uint32_t used = 0;

    // Groups the blocks by slice (in block order within a slice).
    void group(std::size_t slices) {
        slice_start.assign(slices + 1, 0);
        for (uint32_t b = 0; b < used; ++b) ++slice_start[slice_of[b] + 1];
        for (std::size_t s = 1; s <= slices; ++s) slice_start[s] += slice_start[s - 1];
        by_slice.resize(used);
        std::vector<uint32_t> at(slice_start.begin(), slice_start.end() - 1);
        for (uint32_t b = 0; b < used; ++b) by_slice[at[slice_of[b]]++] = b;
    }
};

// Appends counter indices to a chunk's blocks, by slice, through a line per
// slice (see above).
class SlicePartitioner {
public:
    SlicePartitioner(const Window& w, ChunkBlocks& out) : shift_(w.slice_shift), slices_(w.slices), out_(out) {
        thread_local AlignedIndices lines;
        thread_local std::size_t line_slices = 0;
        if (line_slices < slices_) {
            lines = aligned_indices(slices_ * kLineEntries);
            line_slices = slices_;
        }
        lines_ = lines.get();
        thread_local std::vector<uint32_t> in_line, block, in_block;
        in_line.assign(slices_, 0);
        block.assign(slices_, kNoBlock);
        in_block.assign(slices_, 0);
        in_line_ = in_line.data();
        block_ = block.data();
        in_block_ = in_block.data();
        out_.used = 0;
    }

    void add(uint32_t at) {
        const uint32_t s = at >> shift_;
        uint32_t* const line = lines_ + s * kLineEntries;
        const uint32_t n = in_line_[s];
        line[n] = at;
        if (n + 1 < kLineEntries) {
            in_line_[s] = n + 1;
            return;
        }
        in_line_[s] = 0;
        write_line(room(s, kLineEntries), line);
    }

    // Writes out the lines' remainders; the blocks are complete afterwards.
    void finish() {
        for (uint32_t s = 0; s < slices_; ++s) {
            const uint32_t n = in_line_[s];
            if (n > 0) std::copy_n(lines_ + s * kLineEntries, n, room(s, n));
        }
#if defined(__x86_64__)
        _mm_sfence();  // streaming stores are weakly ordered: complete them before the chunk is done
#endif
        out_.group(slices_);
    }

private:
    static constexpr uint32_t kNoBlock = std::numeric_limits<uint32_t>::max();

    // Where slice s's next n indices go (n <= kLineEntries; full lines keep
    // their alignment, since only the last write of a slice is partial).
    uint32_t* room(uint32_t s, uint32_t n) {
        uint32_t b = block_[s];
        if (b == kNoBlock || in_block_[s] == kBlockEntries) {
            b = out_.used++;
            block_[s] = b;
            in_block_[s] = 0;
            out_.slice_of[b] = s;
        }
        uint32_t* const to = out_.entries + std::size_t{b} * kBlockEntries + in_block_[s];
        in_block_[s] += n;
        out_.fill[b] = in_block_[s];
        return to;
    }

    const int shift_;
    const uint32_t slices_;
    ChunkBlocks& out_;
    uint32_t* lines_ = nullptr;
    uint32_t *in_line_ = nullptr, *block_ = nullptr, *in_block_ = nullptr;
};

// One chunk of a round: the counter indices of its outputs that fall in the
// window, into its blocks by slice; with `strays`, keeps the other outputs
// there while the shared budget lasts (once it is overrun, drops them); with
// `trace`, notes the chunk's steps down and reach.
void partition_chunk(const FloatBlockFn& f, uint64_t first, uint64_t n, const Window& w, ChunkBlocks& blocks,
                     std::vector<uint32_t>* strays, StrayBudget& budget, ChunkTrace* trace) {
    // Scratch reused by the thread across chunks (no page faults per chunk).
    thread_local std::vector<float> values;
    thread_local std::vector<uint32_t> keys;
    values.resize(kBlockSize);
    keys.resize(kBlockSize);
    const Window::Range* const ranges = w.ranges.data();
    const std::size_t range_count = w.ranges.size();
    const Window::Range first_range = w.ranges.front();
    SlicePartitioner parts(w, blocks);
    for (uint64_t done = 0; done < n; done += kBlockSize) {
        const auto len = static_cast<std::size_t>(std::min<uint64_t>(kBlockSize, n - done));
        f(first + done, len, values.data());
        const uint32_t* const k = keys.data();
        to_keys(values.data(), len, keys.data());
        if (trace != nullptr) trace->add(k, len, done == 0);
        const std::size_t strays_before = strays != nullptr ? strays->size() : 0;
        for (std::size_t i = 0; i < len; ++i) {
            const uint32_t key = k[i];
            uint32_t at = key - first_range.lo;
            if (at < first_range.size) {
                parts.add(at + first_range.base);
                continue;
            }
            std::size_t r = 1;
            while (r < range_count && key - ranges[r].lo >= ranges[r].size) ++r;
            if (r < range_count) {
                parts.add(ranges[r].base + (key - ranges[r].lo));
            } else if (strays != nullptr) {
                strays->push_back(key);
            }
        }
        if (strays != nullptr && !budget.take(strays->size() - strays_before)) {
            std::vector<uint32_t>().swap(*strays);
            strays = nullptr;
        }
    }
    parts.finish();
}

// Counts every chunk's outputs in the window, round by round (see above).
void count_in_window(const FloatBlockFn& f, uint64_t count, const ParallelFor& parallel_for, Window& w,
                     std::vector<std::vector<uint32_t>>* strays, StrayBudget& budget,
                     std::vector<ChunkTrace>* traces) {
    const auto chunks = static_cast<std::size_t>(chunk_count(count));
    const std::size_t round = std::min(kRoundChunks, chunks);
    const std::size_t capacity = kChunkSize / kBlockEntries + w.slices;  // blocks a chunk may fill
    const AlignedIndices entries = aligned_indices(round * capacity * kBlockEntries);
    std::vector<ChunkBlocks> blocks(round);
    for (std::size_t k = 0; k < round; ++k) {
        blocks[k].entries = entries.get() + k * capacity * kBlockEntries;
        blocks[k].slice_of.resize(capacity);
        blocks[k].fill.resize(capacity);
    }
    for (std::size_t from = 0; from < chunks; from += round) {
        const std::size_t here = std::min(round, chunks - from);
        parallel_for(here, [&](std::size_t k) {
            const std::size_t c = from + k;
            const uint64_t first = c * kChunkSize;
            partition_chunk(f, first, std::min(kChunkSize, count - first), w, blocks[k],
                            strays != nullptr ? &(*strays)[c] : nullptr, budget,
                            traces != nullptr ? &(*traces)[c] : nullptr);
        });
        parallel_for(w.slices, [&](std::size_t s) {
            uint8_t* const counts = w.counts.data();
            std::vector<uint32_t>& wraps = w.wraps[s];
            for (std::size_t k = 0; k < here; ++k) {
                const ChunkBlocks& cb = blocks[k];
                for (uint32_t j = cb.slice_start[s]; j < cb.slice_start[s + 1]; ++j) {
                    const uint32_t b = cb.by_slice[j];
                    const uint32_t* const part = cb.entries + std::size_t{b} * kBlockEntries;
                    for (uint32_t i = 0; i < cb.fill[b]; ++i)
                        if (++counts[part[i]] == 0) wraps.push_back(part[i]);
                }
            }
        });
    }
}

// Adds counters [from, from + n) of a window range (all in binade g) to out,
// key by key in increasing order: inside [a,b) and past the binade's first
// float, straight into the binade's counts (ties go to the smaller key, as in
// GroupCounts::merge); any other key through RunCounter::add.
void add_counts(const Window& w, const Window::Range& r, uint32_t from, uint32_t n, int g,
                const std::vector<uint32_t>& wraps, RunCounter& out) {
    const SweepFrame& frame = *out.frame;
    const uint64_t fast_lo = std::max<uint64_t>(group_key_lo(g) + 1, frame.key_a);
    const uint64_t fast_hi = std::min<uint64_t>(group_key_hi(g), frame.key_b);
    const uint64_t ceiling = frame.ideal_ceiling[static_cast<std::size_t>(g)];
    const uint32_t flip = g >= 256 ? 0u : 1u;  // a negative key is ~bits
    GroupCounts c;
    uint64_t* const mins[2] = {&c.min_even, &c.min_odd};
    uint64_t* const maxs[2] = {&c.max_even, &c.max_odd};
    auto next_wrap = std::lower_bound(wraps.begin(), wraps.end(), r.base + from);
    for (uint32_t i = from; i < from + n; ++i) {
        const uint32_t at = r.base + i;
        uint64_t m = w.counts[at];
        for (; next_wrap != wraps.end() && *next_wrap == at; ++next_wrap) m += 256;
        if (m == 0) continue;
        const uint32_t key = r.lo + i;
        if (key < fast_lo || key >= fast_hi) {
            out.add(key, m);
            continue;
        }
        if (c.distinct == 0) c.lo_key = key;
        c.hi_key = key;
        ++c.distinct;
        c.inputs += m;
        const uint32_t odd = (key ^ flip) & 1u;
        if (m < *mins[odd]) {
            *mins[odd] = m;
            c.min_key[odd] = key;
        }
        if (m > *maxs[odd]) {
            *maxs[odd] = m;
            c.max_key[odd] = key;
        }
        if (m >= ceiling) {
            ++c.n_ge;
            c.s_ge += m;
        } else {
            ++c.n_lt;
            c.s_lt += m;
        }
    }
    out.group_inputs_all[static_cast<std::size_t>(g)] += c.inputs;
    out.groups[static_cast<std::size_t>(g)].merge(c);
}

// Adds the window's counts to total: pieces of 2^20 counters within a binade
// in parallel, merged in key order.
void add_window_counts(Window& w, const ParallelFor& parallel_for, RunCounter& total) {
    std::vector<uint32_t> wraps;
    for (auto& list : w.wraps) {
        wraps.insert(wraps.end(), list.begin(), list.end());
        std::vector<uint32_t>().swap(list);
    }
    std::sort(wraps.begin(), wraps.end());
    struct Piece {
        const Window::Range* range;
        uint32_t from, n;
        int group;
    };
    std::vector<Piece> pieces;
    constexpr uint32_t kPiece = uint32_t{1} << 20;
    for (const Window::Range& r : w.ranges) {
        for (uint32_t i = 0; i < r.size;) {
            const int g = group_of(r.lo + i);
            const auto group_end = static_cast<uint32_t>(group_key_hi(g) - r.lo);
            const uint32_t n = std::min({kPiece, r.size - i, group_end - i});
            pieces.push_back({&r, i, n, g});
            i += n;
        }
    }
    std::vector<std::unique_ptr<RunCounter>> parts(pieces.size());
    parallel_for(pieces.size(), [&](std::size_t p) {
        parts[p] = std::make_unique<RunCounter>(*total.frame);
        add_counts(w, *pieces[p].range, pieces[p].from, pieces[p].n, pieces[p].group, wraps, *parts[p]);
    });
    for (auto& part : parts) total.merge(*part);
}

}  // namespace

// Exact recount of a non-monotone f with at most SweepLimits::sort_limit inputs: sort all outputs.
RecountTrace recount_sorted(const FloatBlockFn& f, uint64_t count, const ParallelFor& parallel_for, RunCounter& total) {
    const auto chunks = static_cast<std::size_t>(chunk_count(count));
    std::vector<uint32_t> keys(static_cast<std::size_t>(count));
    parallel_for(chunks, [&](std::size_t c) {
        const uint64_t first = c * kChunkSize;
        const uint64_t n = std::min(kChunkSize, count - first);
        std::vector<float> values(kBlockSize);
        for (uint64_t done = 0; done < n; done += kBlockSize) {
            const auto len = static_cast<std::size_t>(std::min<uint64_t>(kBlockSize, n - done));
            f(first + done, len, values.data());
            to_keys(values.data(), len, keys.data() + first + done);
        }
    });
    RecountTrace trace{.steps_down = 0, .passes = 1};
    for (std::size_t i = 1; i < keys.size(); ++i) trace.steps_down += keys[i] < keys[i - 1];
    radix_sort(keys);
    std::size_t i = 0;
    while (i < keys.size()) {
        std::size_t j = i + 1;
        while (j < keys.size() && keys[j] == keys[i]) ++j;
        total.add(keys[i], j - i);
        i = j;
    }
    return trace;
}

// Exact recount of a non-monotone f with more inputs than the sort limit.
// `mass` ranks the binades (inputs seen there, or a sample of them); `reach`
// marks every binade an output may lie in. The first window takes the
// window_binades binades of most mass; the outputs outside it are kept and
// counted by sorting, unless there are too many: then the remaining binades
// are counted in further windows (one more run of f each).
RecountTrace recount_windows(const FloatBlockFn& f, uint64_t count, const ParallelFor& parallel_for,
                             const std::array<uint64_t, kGroups>& mass, int window_binades, RunCounter& total) {
    const auto chunks = static_cast<std::size_t>(chunk_count(count));
    std::vector<int> candidates;
    for (int g = 0; g < kGroups; ++g)
        if (mass[static_cast<std::size_t>(g)] > 0) candidates.push_back(g);
    const auto per_window = static_cast<std::size_t>(std::max(window_binades, 1));
    // The first window: most mass first, then by binade; no more binades than
    // it takes to leave a quarter of the strays' room outside (a smaller
    // window keeps its counters closer to the cores).
    std::vector<int> by_mass = candidates;
    std::stable_sort(by_mass.begin(), by_mass.end(), [&](int x, int y) {
        return mass[static_cast<std::size_t>(x)] > mass[static_cast<std::size_t>(y)];
    });
    uint64_t mass_outside = 0;
    for (const int g : by_mass) mass_outside += mass[static_cast<std::size_t>(g)];
    const uint64_t mass_total = std::max<uint64_t>(mass_outside, 1);
    std::size_t first_window = 0;
    while (first_window < std::min(per_window, by_mass.size()) &&
           static_cast<double>(mass_outside) / static_cast<double>(mass_total) * static_cast<double>(count) >
               static_cast<double>(chunks * kStraysPerChunk / 4)) {
        mass_outside -= mass[static_cast<std::size_t>(by_mass[first_window])];
        ++first_window;
    }
    by_mass.resize(std::max<std::size_t>(first_window, 1));
    std::sort(by_mass.begin(), by_mass.end());
    std::vector<std::vector<uint32_t>> strays(chunks);
    StrayBudget budget;
    budget.limit = chunks * kStraysPerChunk;
    std::vector<ChunkTrace> traces(chunks);
    {
        Window w(by_mass);
        count_in_window(f, count, parallel_for, w, &strays, budget, &traces);
        add_window_counts(w, parallel_for, total);
    }
    RecountTrace trace{.steps_down = steps_down_of(traces), .passes = 1};
    if (!budget.overrun.load()) {
        std::vector<uint32_t> keys;
        for (auto& s : strays) {
            keys.insert(keys.end(), s.begin(), s.end());
            std::vector<uint32_t>().swap(s);
        }
        std::sort(keys.begin(), keys.end());
        for (std::size_t i = 0; i < keys.size();) {
            std::size_t j = i + 1;
            while (j < keys.size() && keys[j] == keys[i]) ++j;
            total.add(keys[i], j - i);
            i = j;
        }
        return trace;
    }
    std::vector<std::vector<uint32_t>>().swap(strays);
    // Every binade between a chunk's smallest and largest output that the
    // first window did not hold (outputs may lie there: a superset).
    std::array<uint8_t, kGroups> reach{};
    for (const ChunkTrace& t : traces)
        for (int g = group_of(t.lo); g <= group_of(t.hi); ++g) reach[static_cast<std::size_t>(g)] = 1;
    for (const int g : by_mass) reach[static_cast<std::size_t>(g)] = 0;
    std::vector<int> rest;
    for (int g = 0; g < kGroups; ++g)
        if (reach[static_cast<std::size_t>(g)]) rest.push_back(g);
    for (std::size_t from = 0; from < rest.size(); from += per_window, ++trace.passes) {
        const std::vector<int> groups(rest.begin() + static_cast<std::ptrdiff_t>(from),
                                      rest.begin() + static_cast<std::ptrdiff_t>(std::min(rest.size(), from + per_window)));
        Window w(groups);
        count_in_window(f, count, parallel_for, w, nullptr, budget, nullptr);
        add_window_counts(w, parallel_for, total);
    }
    return trace;
}

}  // namespace warpcheck::chi2::sweep
