"""Samples from elsewhere as NumPy arrays: recorded inputs replayed with the same
figures, independent draws judged against a pdf, two implementations compared in
ulps (same inputs) or by two-sample tests (independent draws), and the same
arrays judged by the validate command with the same verdicts and figures."""

import json
import os
import subprocess

import numpy as np
import pytest

import warpcheck as wc
import numpy_warp

N = 100_000


def _figures(result):
    return {(r.case, r.check): (r.verdict, r.figures) for r in result.rows}


def test_replayed_outputs_give_the_same_figures_as_the_warp_itself():
    correct, _ = numpy_warp.cases()
    checks = ["consistency", "chi2", "unbinned"]
    own, u, x, values = wc.record_inputs(correct, checks=checks, samples=N, seed=3)
    assert values is None and u.dtype == np.float32 and u.shape[1] == 2 and x.shape == (len(u), 3)
    replayed = wc.replay(correct, u, x, checks=checks, samples=N, seed=3)
    assert _figures(replayed) == _figures(own)
    # Another seed asks inputs that were not recorded: an ERROR row that says so.
    other = wc.replay(correct, u, x, checks=["chi2"], samples=N, seed=4)
    assert other.rows[0].verdict == "error" and "was not recorded" in other.rows[0].message


def test_replayed_outputs_of_a_wrong_implementation_fail():
    correct, _ = numpy_warp.cases()
    _, u, x, _ = wc.record_inputs(correct, checks=["chi2"], samples=N)
    bent = x.copy()
    bent[:, 2] = np.sqrt(np.maximum(0, 1 - 1.02 * (bent[:, 0] ** 2 + bent[:, 1] ** 2)))  # cos theta 2% off near the rim
    assert not wc.replay(correct, u, bent, checks=["chi2"], samples=N).passed


def test_independent_draws_are_judged_against_the_pdf():
    correct, _ = numpy_warp.cases()
    rng = np.random.default_rng(11)
    draws = numpy_warp.sample(rng.random((N, 2), dtype=np.float32))
    result = wc.judge_samples(correct, draws)
    assert [(r.check, r.verdict) for r in result.rows] == [("samples_consistency", "pass"), ("samples_chi2", "pass")]
    tilted = draws.copy()
    tilted[:, 2] *= np.float32(0.99)  # directions no longer of unit length: outside the hemisphere
    assert [r.verdict for r in wc.judge_samples(correct, tilted).rows] == ["fail", "fail"]


def test_same_inputs_compared_in_ulps():
    builtin = wc.builtin_case("cosine_hemisphere")
    _, u, x, _ = wc.record_inputs(builtin, checks=["chi2"], samples=N)
    same = wc.compare_same_inputs(x, x.copy(), inputs=u, case=builtin)
    assert same.passed and same.rows[0].figures["identical_fraction"] == 1.0
    nudged = x.copy()
    nudged[::100, 2] = np.nextafter(nudged[::100, 2], np.float32(2))
    one_ulp = wc.compare_same_inputs(x, nudged, inputs=u, max_ulps=0)
    assert not one_ulp.passed and one_ulp.rows[0].figures["max_ulps"] == 1
    assert wc.compare_same_inputs(x, nudged, max_ulps=1).passed
    nudged[5, 0] = np.nan
    with_nan = wc.compare_same_inputs(x, nudged, max_ulps=1000)
    assert not with_nan.passed and with_nan.rows[0].figures["nan"] == 1


def test_two_sample_passes_a_correct_pair_and_fails_a_one_percent_error():
    correct, _ = numpy_warp.cases()
    rng = np.random.default_rng(2)
    a = numpy_warp.sample(rng.random((200_000, 2), dtype=np.float32))
    b = numpy_warp.sample(rng.random((200_000, 2), dtype=np.float32))
    u = rng.random((200_000, 2), dtype=np.float32)
    u[:, 0] *= np.float32(0.99)  # one build's 1% error: the outer rim of the disk is never reached
    c = numpy_warp.sample(u)
    good = wc.two_sample(a, b, case=correct)
    assert good.passed, good.table()
    assert good.rows[0].figures["power_tilt_ad"] < 0.05
    assert not wc.two_sample(a, c, case=correct).passed
    assert not wc.two_sample(a, c, domain=wc.Domain.hemisphere()).passed


@pytest.mark.parametrize("bad, words", [
    (np.zeros((10, 3), dtype=np.int64), "int64"),
    (np.zeros((10, 3, 1), dtype=np.float32), "3 dimensions"),
    (np.zeros((10, 2), dtype=np.float32), "(n, 3)"),
])
def test_bad_arrays_are_refused_with_what_was_expected(bad, words):
    correct, _ = numpy_warp.cases()
    with pytest.raises((ValueError, RuntimeError), match=words.replace("(", r"\(").replace(")", r"\)")):
        wc.judge_samples(correct, bad)


def test_validate_judges_the_same_arrays_with_the_same_figures(tmp_path):
    validate = os.environ.get("WARPCHECK_VALIDATE")
    if not validate:
        pytest.skip("WARPCHECK_VALIDATE (the validate program) is set by ctest")
    builtin = wc.builtin_case("cosine_hemisphere")
    checks = ["consistency", "chi2"]
    own, u, x, _ = wc.record_inputs(builtin, checks=checks, samples=N, seed=5)
    wc.save_samples(str(tmp_path / "u.npy"), u)
    wc.save_samples(str(tmp_path / "x.npy"), x)
    command = [validate, "--filter", "cosine_hemisphere", "--check", "consistency", "--check", "chi2", "--seed", "5",
               "--samples", str(N), "--replay", str(tmp_path / "u.npy"), str(tmp_path / "x.npy"),
               "--json", str(tmp_path / "r.json"), "--progress", "none"]
    assert subprocess.run(command, capture_output=True).returncode == 0
    rows = json.load(open(tmp_path / "r.json"))["results"]
    from_validate = {(r["case"], r["check"]): r["figures"] for r in rows}
    for r in own.rows:
        assert from_validate[(r.case, r.check)] == {k: v for k, v in r.figures.items() if k in from_validate[(r.case, r.check)]}
