// The include path of warpcheck 0.1, kept for one release: this header is now
// <validate/api/external.h> (validate/api/CHANGELOG.md). Installed as
// <validate/external.h>; it goes in 0.3. The message is a #pragma message for GCC
// (a note, shown from an installed -isystem header too, and never an error
// under -Werror) and a #warning for Clang (the one diagnostic Clang shows
// from a system header).
#pragma once
#if defined(__clang__)
#warning "<validate/external.h> is deprecated: include <validate/api/external.h> instead (warpcheck's headers moved to validate/api/; see validate/api/CHANGELOG.md)"
#else
#pragma message("<validate/external.h> is deprecated: include <validate/api/external.h> instead (warpcheck's headers moved to validate/api/; see validate/api/CHANGELOG.md)")
#endif
#include "validate/api/external.h"
