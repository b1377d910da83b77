"""A warp written with NumPy, validated by warpcheck, with its wrong twin.

Cosine-weighted directions on the hemisphere by Malley's method: a uniform point
of the disk by the polar map, lifted to the hemisphere. Every function takes
and returns a whole batch: u is float32 of shape (n, 2), a direction array is
(n, 3). Run it as a script to see the table, or through pytest
(tests/python/test_warps.py runs these).
"""

import numpy as np

import warpcheck as wc


def sample(u):
    r = np.sqrt(u[:, 0])
    phi = 2 * np.pi * u[:, 1]
    z = np.sqrt(np.maximum(0.0, 1.0 - u[:, 0]))
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1).astype(np.float32)


def pdf(w):
    return np.where(w[:, 2] >= 0, w[:, 2] / np.pi, 0.0)


def invert(w):
    r2 = np.minimum(w[:, 0].astype(np.float64) ** 2 + w[:, 1].astype(np.float64) ** 2, 1.0)
    phi = np.arctan2(w[:, 1], w[:, 0]) % (2 * np.pi)
    u = np.stack([r2, phi / (2 * np.pi)], axis=1).astype(np.float32)
    return np.minimum(u, np.float32(1 - 2**-24))  # an inverse returns a valid input, below 1


def half_pdf(w):
    """The wrong twin's bug: a density that integrates to 1/2."""
    return pdf(w) / 2


def cases():
    """The correct warp and its wrong twin."""
    views = [wc.View("cos theta", 0.0, 1.0, coordinate=2, increasing=False, pdf=lambda z: 2 * z)]
    correct = wc.Warp("numpy_cosine_hemisphere", sample, pdf=pdf, invert=invert, domain=wc.Domain.hemisphere(),
                      description="cosine-weighted hemisphere in NumPy (polar map lifted)", views=views)
    wrong = wc.Warp("numpy_cosine_hemisphere_half_pdf", sample, pdf=half_pdf, invert=invert,
                    domain=wc.Domain.hemisphere(), description="the same with half its density")
    return correct, wrong


def test_cosine_hemisphere_passes():
    correct, _ = cases()
    wc.assert_passes(correct, samples=100_000)


def test_half_pdf_fails_chi2():
    _, wrong = cases()
    wc.assert_fails(wrong, "chi2", samples=100_000)


if __name__ == "__main__":
    correct, wrong = cases()
    print(wc.run([correct, wrong], samples=100_000).table())
