"""A warp computed in another array framework (PyTorch, JAX, Dr.Jit, CuPy), validated
through NumPy.

warpcheck hands the warp NumPy arrays and wants NumPy arrays back; a warp written
for a framework converts at the two ends: NumPy to the framework's tensor on the
way in (no copy on the CPU: torch.from_numpy, jnp.asarray, drjit's Array2f(u)),
and back with .numpy() or DLPack on the way out. A GPU tensor is copied to the
host (.cpu()) before the conversion. Samples a framework produced on its own
(a render's path vertices, a GPU kernel's buffer) are judged the same way:
to_numpy(tensor), then warpcheck.judge_samples or two_sample.

With PyTorch installed, the warp below runs in PyTorch; without it, in NumPy
through the same conversions (DLPack), so the example runs anywhere.
"""

import numpy as np

import warpcheck as wc

try:  # the framework, where it is installed
    import torch as framework

    def to_framework(a):
        return framework.from_numpy(np.ascontiguousarray(a))
except ImportError:  # NumPy stands in for it, through the same DLPack exchange
    framework = np

    def to_framework(a):
        return np.from_dlpack(np.ascontiguousarray(a))


def to_numpy(t):
    """A framework's tensor as a NumPy array: PyTorch (detached, on the host), then any
    DLPack producer (JAX, CuPy, Dr.Jit), then the array protocol."""
    if hasattr(t, "detach"):
        return t.detach().cpu().numpy()
    if hasattr(t, "__dlpack__"):
        return np.from_dlpack(t)
    return np.asarray(t)


def concentric_disk(u):
    """Shirley and Chiu's concentric map, in the framework's operations."""
    t = to_framework(u)
    a, b = 2 * t[:, 0] - 1, 2 * t[:, 1] - 1
    wedge = framework.abs(a) > framework.abs(b)
    r = framework.where(wedge, a, b)
    # Both ratios are guarded where the wedge does not use them (0/0 at the centre).
    ba = b / framework.where(a == 0, 1, a)
    ab = a / framework.where(b == 0, 1, b)
    phi = framework.where(wedge, (np.pi / 4) * ba, np.pi / 2 - (np.pi / 4) * ab)
    return to_numpy(framework.stack([r * framework.cos(phi), r * framework.sin(phi)], 1))


def disk_pdf(x):
    return np.where(x[:, 0].astype(np.float64) ** 2 + x[:, 1].astype(np.float64) ** 2 <= 1, 1 / np.pi, 0.0)


def case():
    return wc.Warp("framework_concentric_disk", concentric_disk, pdf=disk_pdf, domain=wc.Domain.unit_disk(),
                   description=f"concentric disk computed in {framework.__name__}")


def test_framework_warp_passes():
    wc.assert_passes(case(), samples=100_000)


def test_framework_samples_judged_as_arrays():
    """Samples the framework drew with its own random numbers: judged against the pdf."""
    rng = np.random.default_rng(5)
    samples = concentric_disk(rng.random((200_000, 2), dtype=np.float32))
    assert wc.judge_samples(case(), samples).passed


if __name__ == "__main__":
    print(wc.run(case(), samples=100_000).table())
