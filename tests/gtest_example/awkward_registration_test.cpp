// The GoogleTest suite of awkward_registration.cpp's warps.
#include <validate/api/external.h>
#include <validate/gtest/warpcheck_gtest.h>

WARPCHECK_TEST_SUITE(Awkward, warpcheck_register);
