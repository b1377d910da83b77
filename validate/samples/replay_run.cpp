#include "validate/samples/replay_run.h"

#include "validate/run/runner.h"

namespace warpcheck {

bool returns_value(const WarpCase& warp) {
    const SampleReturns r = warp.sample_returns();
    return r == SampleReturns::PointAndPdf || r == SampleReturns::PointAndWeight ||
           r == SampleReturns::IndexAndRemappedU;
}

std::vector<Job> jobs_for(const std::vector<Job>& jobs, const WarpCase& original, const WarpCase& wrapper) {
    std::vector<Job> out;
    for (const Job& job : jobs) {
        if (job.warp != &original) continue;
        const Applicability a = job.check->applicability(wrapper);
        if (a.applies()) out.push_back({&wrapper, job.check});
        else if (!a.not_applicable_because().empty()) out.push_back({&wrapper, job.check, a.not_applicable_because()});
    }
    return out;
}

Recording record_run(const WarpCase& warp, const std::vector<Job>& jobs, const RunOptions& options,
                     const ProgressCallback& progress) {
    const RecordingCase recording(warp);
    Recording r;
    r.run = run_jobs(jobs_for(jobs, warp, recording), options, progress, Isolation{});
    r.samples.inputs = recording.recorded_inputs();
    r.samples.outputs.resize(r.samples.inputs.size());
    if (returns_value(warp)) {
        r.samples.values.emplace(r.samples.inputs.size());
        warp.sample_with_value(r.samples.inputs, r.samples.outputs, *r.samples.values);
    } else {
        warp.sample(r.samples.inputs, r.samples.outputs);
    }
    return r;
}

RunResult replay_run(const WarpCase& reference, RecordedSamples table, const std::vector<Job>& jobs,
                     const RunOptions& options, const Isolation& isolation, const ProgressCallback& progress) {
    const ReplayCase replay(reference, std::move(table));
    return run_jobs(jobs_for(jobs, reference, replay), options, progress, isolation);
}

}  // namespace warpcheck
