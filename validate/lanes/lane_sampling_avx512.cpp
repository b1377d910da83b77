// The AVX-512 build of the lockstep loops (validate/lanes/lane_kernels.h): this whole
// file is compiled for x86-64-v4 with -fno-math-errno (validate/CMakeLists.txt),
// and only called where avx512_available() says the processor has it.
#include "validate/lanes/lane_kernels.h"

namespace warpcheck::lane_kernels {

#define WARPCHECK_DEFINE_GROUP_FN(name, Kernel) \
    void name##_avx512(const void* kernel, const LaneGroup& g) { \
        run_group(*static_cast<const lanes::Kernel*>(kernel), g); \
    }
WARPCHECK_LANE_FORMS(WARPCHECK_DEFINE_GROUP_FN)
#undef WARPCHECK_DEFINE_GROUP_FN

void planar_avx512(const void* warp, const LaneGroup& g) { run_planar_group(warp, g); }

}  // namespace warpcheck::lane_kernels
