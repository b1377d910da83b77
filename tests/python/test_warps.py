"""Python warps, lights and BSDFs through warpcheck's checks: the correct ones pass, each
wrong twin fails with its row, its rerun line and the path of its evidence; bad callables
and bad declarations give clear errors, never a crash; the same seed gives the same figures."""

import os

import numpy as np
import pytest

import warpcheck as wc
import framework_arrays
import light_and_bsdf
import numpy_warp

N = 100_000  # samples per statistical check: the suite stays within seconds


def test_numpy_warp_passes_every_check_that_applies():
    correct, _ = numpy_warp.cases()
    result = wc.assert_passes(correct, samples=N)
    checks = {r.check for r in result.rows if r.verdict == "pass"}
    assert {"consistency", "roundtrip", "chi2", "tabulated", "unbinned"} <= checks


def test_wrong_twin_fails_with_its_row_rerun_line_and_evidence(evidence_dir):
    _, wrong = numpy_warp.cases()
    with pytest.raises(AssertionError) as failure:
        wc.assert_passes(wrong, samples=N)
    message = str(failure.value)
    assert "FAIL" in message and "chi2" in message and "numpy_cosine_hemisphere_half_pdf" in message
    assert "WARPCHECK_FILTER=numpy_cosine_hemisphere_half_pdf WARPCHECK_CHECK=chi2" in message
    report = message.rsplit("evidence: ", 1)[1].strip()
    assert report.startswith(str(evidence_dir)) and os.path.getsize(report) > 1000
    assert "numpy_cosine_hemisphere_half_pdf" in open(report, encoding="utf-8").read()
    assert failure.value.run.rows and not failure.value.run.passed


def test_assert_fails_names_the_check_that_catches_the_twin():
    _, wrong = numpy_warp.cases()
    wc.assert_fails(wrong, "chi2", samples=N)
    with pytest.raises(AssertionError, match="expected check roundtrip to fail"):
        wc.assert_fails(wrong, "roundtrip", samples=N)


def test_same_seed_same_figures_whatever_the_threads():
    correct, _ = numpy_warp.cases()
    one = wc.run(correct, samples=N, seed=7, threads=1, checks=["chi2", "unbinned", "consistency"])
    two = wc.run(correct, samples=N, seed=7, threads=2, checks=["chi2", "unbinned", "consistency"])
    assert [r.figures for r in one.rows] == [r.figures for r in two.rows]
    other = wc.run(correct, samples=N, seed=8, threads=2, checks=["chi2"])
    assert other.rows[0].figures["statistic"] != one.rows[1].figures["statistic"]


def test_light_passes_and_its_twin_fails_chi2():
    correct, wrong = light_and_bsdf.lights()
    result = wc.assert_passes(correct, samples=N)
    assert {r.case for r in result.rows} == set(correct.names) and len(correct.names) == 2
    assert any(r.check == "sample_pdf" and r.passed for r in result.rows)
    wc.assert_fails(wrong, "chi2", samples=N, checks=["chi2"])


def test_light_with_radiance_takes_the_light_checks_and_its_twin_fails():
    correct, wrong = light_and_bsdf.lights_with_radiance()
    result = wc.assert_passes(correct, samples=N)
    assert {"light_radiance", "light_support", "light_irradiance", "chi2"} <= {r.check for r in result.rows if r.passed}
    wc.assert_fails(wrong, "chi2", samples=N, checks=["chi2"])
    wc.assert_fails(wrong, "light_irradiance", samples=N, checks=["light_irradiance"])


def test_a_light_with_radiance_needs_its_pdf_and_a_normal_needs_radiance():
    with pytest.raises(ValueError, match="needs its pdf"):
        wc.Light("no_pdf", light_and_bsdf.light_sample, L=light_and_bsdf.light_radiance, points=[(0, 0, 0)])
    with pytest.raises(ValueError, match="a normal weighs L"):
        wc.Light("no_l", light_and_bsdf.light_sample, pdf=light_and_bsdf.light_pdf, normal=(0, 0, 1),
                 points=[(0, 0, 0)])


def test_bsdf_passes_and_its_twin_fails_the_albedo_check():
    correct, wrong = light_and_bsdf.bsdfs()
    result = wc.assert_passes(correct, samples=N)
    assert {"bsdf_chi2", "bsdf_albedo", "bsdf_reciprocity"} <= {r.check for r in result.rows if r.passed}
    with pytest.raises(AssertionError) as failure:
        wc.assert_passes(wrong, samples=N, checks=["bsdf_albedo", "bsdf_weight"])
    assert "FAIL   bsdf_albedo" in str(failure.value) and "evidence: " in str(failure.value)


def test_a_stochastic_bsdf_passes_in_expectation_and_its_one_way_twin_fails_by_reciprocity():
    correct, wrong = light_and_bsdf.stochastic_bsdfs()
    result = wc.assert_passes(correct, samples=N)
    verdicts = {r.check: r.verdict for r in result.rows}
    assert verdicts["bsdf_expectation"] == "pass"
    assert verdicts["bsdf_reciprocity"] == "not_applicable" and verdicts["bsdf_chi2"] == "not_applicable"
    failed = wc.assert_fails(wrong, "bsdf_expectation", samples=N)
    row = next(r for r in failed.rows if r.check == "bsdf_expectation")
    assert row.figures["reciprocity_largest_abs_z"] > 5


def test_mis_of_python_parts_passes_and_its_area_pdf_twin_fails_the_weights():
    correct, wrong = light_and_bsdf.mis_cases()
    assert correct.names == ["numpy_mis_lambert_sphere[theta_o=45,px=0,py=0,pz=0]"]
    calls = []

    def counted_light_pdf(ref, wi):
        calls.append(len(wi))
        return light_and_bsdf.light_pdf(ref, wi)

    bsdf, light = light_and_bsdf.mis_parts()
    counted = wc.Mis("numpy_mis_counted", bsdf, [light], light_mis_pdfs=[counted_light_pdf])
    result = wc.assert_passes([correct, counted], samples=N)
    for case in (correct.names[0], counted.names[0]):
        verdicts = {r.check: r.verdict for r in result.rows if r.case == case}
        assert verdicts["mis_weights"] == "pass" and verdicts["mis_estimator"] == "pass", verdicts
    # The MIS pdf is called on batches (one call per chunk of directions), not per direction.
    assert sum(calls) > 2 * N and len(calls) < sum(calls) / 1000 and min(calls) > 0
    failed = wc.assert_fails(wrong, "mis_weights", samples=N, checks=["mis_weights", "mis_estimator"])
    row = next(r for r in failed.rows if r.check == "mis_weights")
    assert row.figures["wrong_sums"] > N / 2
    assert any(r.check == "mis_estimator" and r.verdict == "fail" for r in failed.rows)


def test_mis_refuses_parts_that_do_not_fit():
    bsdf, light = light_and_bsdf.mis_parts()
    with pytest.raises(ValueError, match="bsdf must be a Bsdf"):
        wc.Mis("bad", light, [light])
    with pytest.raises(ValueError, match="a Light of Python callables with L"):
        wc.Mis("bad", bsdf, [light_and_bsdf.lights()[0]])
    two_points = wc.Light("two", light_and_bsdf._with_radiance(light_and_bsdf.light_sample), pdf=light_and_bsdf.light_pdf,
                          L=light_and_bsdf.light_radiance, normal=(0, 0, 1), points=light_and_bsdf.POINTS)
    with pytest.raises(ValueError, match="different numbers of reference points"):
        wc.Mis("bad", bsdf, [light, two_points])
    with pytest.raises(ValueError, match="more MIS pdfs than lights"):
        wc.Mis("bad", bsdf, [light], light_mis_pdfs=[None, None])
    no_normal = wc.Light("no_normal", light_and_bsdf._with_radiance(light_and_bsdf.light_sample),
                         pdf=light_and_bsdf.light_pdf, L=light_and_bsdf.light_radiance, points=[(0, 0, 0)])
    with pytest.raises(ValueError, match="normal"):
        wc.Mis("bad", bsdf, [no_normal])
    with pytest.raises(ValueError, match="heuristic"):
        wc.Mis("bad", bsdf, [light], heuristic="maximum")


def test_a_framework_warp_passes():
    framework_arrays.test_framework_warp_passes()


def _hemisphere(sample, **kw):
    return wc.Warp("broken", sample, pdf=numpy_warp.pdf, domain=wc.Domain.hemisphere(), **kw)


@pytest.mark.parametrize("sample, words", [
    (lambda u: (_ for _ in ()).throw(ValueError("no light here")), ["ValueError", "no light here", "broken: sample"]),
    (lambda u: u, ["shape (4096, 2)", "expected floating-point values of shape (4096, 3)"]),
    (lambda u: np.zeros((len(u), 3), dtype=np.int32), ["int32", "floating-point"]),
    (lambda u: "directions", ["broken: sample returned a str", "shape ()", "expected floating-point values"]),
])
def test_a_callable_that_throws_or_returns_the_wrong_thing_is_an_error_row(sample, words):
    result = wc.run(_hemisphere(sample), samples=N, checks=["chi2"])
    row = result.rows[0]
    assert row.verdict == "error"
    assert all(w in row.message for w in words), row.message


def test_nan_samples_fail_consistency():
    def sample(u):
        x = numpy_warp.sample(u)
        x[::1000] = np.nan
        return x
    result = wc.run(_hemisphere(sample), samples=N, checks=["consistency", "chi2"])
    assert [r.verdict for r in result.rows] == ["fail", "fail"]


def test_a_declaration_that_contradicts_itself_is_refused():
    views = [wc.View("z", 0, 1, coordinate=2), wc.View("z", 0, 1, coordinate=2)]
    with pytest.raises(ValueError, match="declared inconsistently"):
        wc.Warp("twice", numpy_warp.sample, pdf=numpy_warp.pdf, domain=wc.Domain.hemisphere(), views=views)
    with pytest.raises(ValueError, match="input"):
        wc.Warp("what", numpy_warp.sample, input="uniform5d")
    with pytest.raises(ValueError, match="unknown check 'chi3'"):
        wc.run(numpy_warp.cases()[0], checks=["chi3"], samples=N)


def test_returned_pdf_is_checked_against_the_pdf_function():
    def with_pdf(scale):
        def sample(u):
            x = numpy_warp.sample(u)
            return x, scale * numpy_warp.pdf(x)
        return wc.Warp(f"returns_pdf_{scale}", sample, pdf=numpy_warp.pdf, returns="pdf", domain=wc.Domain.hemisphere())
    assert wc.run(with_pdf(1.0), samples=N, checks=["sample_pdf"]).passed
    wc.assert_fails(with_pdf(1.01), "sample_pdf", samples=N)


def test_a_1d_warp_on_a_half_line():
    def sample(u):
        return (-np.log1p(-u.astype(np.float64)) / 2.0).astype(np.float32)
    exponential = wc.Warp("numpy_exponential", sample, pdf=lambda x: np.where(x >= 0, 2 * np.exp(-2.0 * x), 0.0),
                          input="uniform1d", domain=wc.Domain.half_line(0), params={"rate": 2},
                          views=[wc.View("x", 0, 8, tail_mass=float(np.exp(-16.0)))])
    assert exponential.names == ["numpy_exponential[rate=2]"]
    wc.assert_passes(exponential, samples=N, checks=["consistency", "chi2", "unbinned"])


def test_the_rerun_variables_select_what_they_name(monkeypatch):
    correct, wrong = numpy_warp.cases()
    monkeypatch.setenv("WARPCHECK_FILTER", "numpy_cosine_hemisphere_half_pdf")
    monkeypatch.setenv("WARPCHECK_CHECK", "chi2")
    monkeypatch.setenv("WARPCHECK_SAMPLES", "1e5")
    result = wc.run([correct, wrong])
    assert [(r.case, r.check) for r in result.rows] == [("numpy_cosine_hemisphere_half_pdf", "chi2")]
    assert result.samples == 100_000


def test_reports_are_the_same_views_as_validate_writes(tmp_path):
    result = wc.run(numpy_warp.cases()[0], samples=N, checks=["chi2"])
    assert '"check":"chi2"' in result.json().replace(" ", "")
    assert "<html" in result.html() and "<testsuite" in result.junit()
    result.write_json(str(tmp_path / "r.json"))
    assert (tmp_path / "r.json").stat().st_size > 100


def test_raw_bits_and_discrete_choices():
    # 32 random bits to a float of [0, 1): the top 24 bits, scaled.
    unit = wc.Warp("numpy_unit_float", lambda bits: (bits >> np.uint32(8)).astype(np.float32) * np.float32(2**-24),
                   pdf=lambda x: np.where((x >= 0) & (x < 1), 1.0, 0.0), input="bits32",
                   domain=wc.Domain.interval(0, 1))
    wc.assert_passes(unit, samples=N, checks=["consistency", "chi2"])
    pmf = np.array([0.1, 0.2, 0.3, 0.4])

    def choice(pmf_claimed):
        cdf = np.cumsum(pmf)
        return wc.Warp("numpy_choice" if pmf_claimed is pmf else "numpy_choice_swapped",
                       lambda u: np.minimum(np.searchsorted(cdf, u, side="right"), 3), pdf=lambda i: pmf_claimed[i],
                       input="uniform1d", returns="index", categories=4)
    wc.assert_passes(choice(pmf), samples=N, checks=["pmf", "discrete_chi2"])
    wc.assert_fails(choice(pmf[::-1].copy()), "discrete_chi2", samples=N, checks=["discrete_chi2"])
