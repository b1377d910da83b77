"""The NumPy path against C++'s scalar path, for one simple warp at 10^6 samples
(issue 39 asks for within 2x). A measured figure printed, not a timed test:

    PYTHONPATH=build/test/validate/python /usr/bin/python3 tests/benchmarks/bench_python_path.py

The warp is the polar map to the unit disk, the built-in uniform_disk_polar
(sampling/disk.h) against the same map in NumPy. Two figures, best of 5:
  - sampling: 10^6 inputs through WarpCase::sample in the checks' chunks of
    65,536 (the C++ loop with sample inlined, against one Python call per
    chunk: array in, NumPy's loops, array out, checked and rounded to float);
  - a whole chi2 check of 10^6 samples, one thread (sampling, binning and the
    integration of the pdf over the cells, where the pdf is Python's too).
"""

import sys
import time

import numpy as np

import warpcheck as wc
from warpcheck import _warpcheck as core


def sample(u):
    r = np.sqrt(u[:, 0])
    phi = np.float32(2 * np.pi) * u[:, 1]
    return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=1)


def pdf(x):
    return np.where(x[:, 0].astype(np.float64) ** 2 + x[:, 1].astype(np.float64) ** 2 <= 1, 1 / np.pi, 0.0)


def best(f, repeats=5):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return min(times)


def main():
    n = 1_000_000
    builtin = wc.builtin_case("uniform_disk_polar")
    numpy_twin = wc.Warp("numpy_disk_polar", sample, pdf=pdf, domain=wc.Domain.unit_disk())
    cpp = best(lambda: core.sample_seconds(builtin, n))
    py = best(lambda: core.sample_seconds(numpy_twin, n))
    print(f"sampling 10^6 inputs:   C++ {cpp * 1e3:7.1f} ms   NumPy {py * 1e3:7.1f} ms   ratio {py / cpp:5.2f}x")

    def chi2_seconds(case):
        return wc.run(case, checks=["chi2"], samples=n, threads=1).rows[0].seconds

    cpp_check = best(lambda: chi2_seconds(builtin), 3)
    py_check = best(lambda: chi2_seconds(numpy_twin), 3)
    print(f"chi2 check, 10^6:       C++ {cpp_check * 1e3:7.1f} ms   NumPy {py_check * 1e3:7.1f} ms   "
          f"ratio {py_check / cpp_check:5.2f}x")
    # The check's integration of the pdf over its cells makes ~11,000 pdf calls of
    # 2 to 225 points, whatever the sample count: a fixed cost of the Python path
    # (~17 us a call, most of it NumPy's per-call overhead), which 10^7 samples dilute.
    cpp_big = best(lambda: wc.run(builtin, checks=["chi2"], samples=10 * n, threads=1).rows[0].seconds, 1)
    py_big = best(lambda: wc.run(numpy_twin, checks=["chi2"], samples=10 * n, threads=1).rows[0].seconds, 1)
    print(f"chi2 check, 10^7:       C++ {cpp_big * 1e3:7.1f} ms   NumPy {py_big * 1e3:7.1f} ms   "
          f"ratio {py_big / cpp_big:5.2f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
