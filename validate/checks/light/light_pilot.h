// A pilot of a light: its samples from the pilot streams (input_chunks.h:
// independent of the samples a check tests), which place light_support's cap
// and light_irradiance's cells and scale.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "validate/api/light_case.h"
#include "validate/checks/shared/input_chunks.h"

namespace warpcheck::light {

/// The samples of `count` pilot inputs, declined and non-finite ones left out.
inline std::vector<LightRecord> light_pilot(const LightCase& light, const CheckContext& ctx, std::size_t count) {
    const std::vector<WarpInput> in = pilot_inputs(ctx, InputKind::Uniform2D, count);
    std::vector<LightRecord> records(in.size());
    light.sample_light(in, records);
    std::erase_if(records, [](const LightRecord& r) {
        return !r.sampled() || !std::isfinite(r.wi[0] + r.wi[1] + r.wi[2]);
    });
    return records;
}

}  // namespace warpcheck::light
