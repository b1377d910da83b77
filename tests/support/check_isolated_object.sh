#!/usr/bin/env bash
# The AVX-512 and AVX2 objects (validate/lanes/lane_sampling_avx512.cpp, built for
# x86-64-v4, and lane_sampling_avx2.cpp, built for x86-64-v3) must define
# nothing but their own group functions: an inline function or template one of
# them emitted as a weak symbol could be the copy the linker keeps for every
# caller, and would then run AVX-512 or AVX2 code on processors without it.
# Usage: check_isolated_object.sh "<object files, ;-separated>"
set -euo pipefail
IFS=';' read -r -a objects <<< "$1"
for suffix in avx512 avx2; do
    object=""
    for o in "${objects[@]}"; do [[ "$o" == *lane_sampling_${suffix}.cpp.o ]] && object="$o"; done
    [[ -n "$object" ]] || { echo "no lane_sampling_${suffix}.cpp.o among the objects"; exit 1; }
    # Global or weak definitions (local ones, lower case but 'w'/'v'/'u', cannot be chosen for other callers).
    # One weak object is expected and harmless: DW.ref.__gxx_personality_v0, a
    # pointer to the C++ personality routine that every object with unwind tables
    # carries, the same in all of them, and not code (an instrumented build emits
    # it here: AddressSanitizer's stack frames need unwind cleanups).
    symbols=$(nm --defined-only -C "$object" | awk '$2 ~ /^[A-Zwvu]$/ && $3 != "DW.ref.__gxx_personality_v0" {print}')
    stray=$(grep -v "T warpcheck::lane_kernels::[a-z_0-9]*_${suffix}(void const\*, warpcheck::LaneGroup const&)\$" <<< "$symbols" || true)
    count=$(grep -c 'T warpcheck::lane_kernels::' <<< "$symbols" || true)
    if [[ -n "$stray" ]]; then
        echo "lane_sampling_${suffix}.cpp.o defines symbols other callers could bind to:"
        echo "$stray"
        exit 1
    fi
    if [[ "$count" -lt 1 ]]; then
        echo "lane_sampling_${suffix}.cpp.o defines no group function"
        exit 1
    fi
    echo "lane_sampling_${suffix}.cpp.o: $count group functions, nothing else shared"
done
