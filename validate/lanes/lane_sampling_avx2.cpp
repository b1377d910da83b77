// The AVX2 build of the lockstep loops (validate/lanes/lane_kernels.h): this whole
// file is compiled for x86-64-v3 with -fno-math-errno and -mno-fma
// (validate/CMakeLists.txt; no contraction either way, -ffp-contract=off), and
// only called where avx2_available() says the processor has it and has no
// AVX-512 (which the x86-64-v4 file serves).
#include "validate/lanes/lane_kernels.h"

// Lane vectors pass only between always_inline functions (sampling/lanes.h);
// GCC notes at the end of the file the 64-byte ones that AVX2 holds in two registers.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace warpcheck::lane_kernels {

#define WARPCHECK_DEFINE_GROUP_FN(name, Kernel) \
    void name##_avx2(const void* kernel, const LaneGroup& g) { \
        run_group(*static_cast<const lanes::Kernel*>(kernel), g); \
    }
WARPCHECK_LANE_FORMS(WARPCHECK_DEFINE_GROUP_FN)
#undef WARPCHECK_DEFINE_GROUP_FN

void planar_avx2(const void* warp, const LaneGroup& g) { run_planar_group(warp, g); }

}  // namespace warpcheck::lane_kernels
