"""warpcheck from Python: validate Monte Carlo sampling routines written on NumPy arrays.

A warp, BSDF or light is described as in C++ (domain, parameters, claims,
views) with Python callables that take and return NumPy arrays of a whole
batch; the same checks run through the same runner and give the same result
model, table, JSON and HTML report. Samples computed elsewhere (another build,
a GPU, another framework) are judged from arrays. The guide is
validate/python/README.md.

    import numpy as np, warpcheck as wc

    def sample(u):                      # u: float32 (n, 2)
        r, phi = np.sqrt(u[:, 0]), 2 * np.pi * u[:, 1]
        return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=1)

    disk = wc.Warp("my_disk", sample, pdf=lambda x: np.full(len(x), 1 / np.pi),
                   domain=wc.Domain.unit_disk())
    wc.assert_passes(disk)              # in a pytest test: fails with the rows and the report's path

Runs are in this process (never forked: see the README), seeded, and the same
seed gives the same figures whatever the thread count. The variables
WARPCHECK_SEED, WARPCHECK_SAMPLES, WARPCHECK_ALPHA, WARPCHECK_FILTER and
WARPCHECK_CHECK override the arguments (they are what a failure's rerun line sets);
WARPCHECK_EVIDENCE_DIR is where the assertion helpers write their reports.
"""

from ._warpcheck import Domain, View, Run, Row, Cases, __version__  # noqa: F401
from ._warpcheck import check_names, builtin_case_names  # noqa: F401
from .api import (  # noqa: F401
    Warp,
    Light,
    Bsdf,
    Mis,
    builtin_case,
    run,
    assert_passes,
    assert_fails,
    record_inputs,
    replay,
    judge_samples,
    compare_same_inputs,
    two_sample,
    load_samples,
    save_samples,
    WarpcheckFailure,
)
