"""The functions of the warpcheck package (see __init__.py and validate/python/README.md)."""

import os
import re
import shlex
import sys

import numpy as np

from . import _warpcheck as _core


# ---------------------------------------------------------------------------
# Cases


def Warp(family, sample, *, pdf=None, invert=None, eval=None, domain=None, params=None, description="",
         input="uniform2d", returns="point", categories=0, views=(), roundtrip_tolerance=0.0, support_measure=0.0,
         inversion="measure"):
    """A warp of Python callables on batches, as C++'s make_warp_case describes one.

    sample(u) -> x: u is float32, (n,) for input="uniform1d", (n, 2) for "uniform2d", or raw
    bits uint32/uint64 (n,) for "bits32"/"bits64"; x is (n,) on a line, (n, 2) in the plane,
    (n, 3) on the sphere (float64 is rounded to float32, as a warp returns floats). With
    returns="pdf" or "weight", sample returns (x, value); with returns="index", category
    indices (n,) and `categories` is their number (a discrete choice takes no domain). pdf(x) -> (n,), invert(x) -> u and
    eval(x) -> (n,) as they exist: a part that is missing makes the checks that need it n/a.
    params: a dict of the parameter values, in the order of the name
    family[name=value,...]. Refused with ValueError where the declaration contradicts itself.
    """
    return _core.warp(family, sample, pdf=pdf, invert=invert, eval=eval,
                      domain=domain if domain is not None else _core.Domain.unit_square(), params=dict(params or {}),
                      description=description, input=input, returns=returns, categories=categories,
                      views=list(views), roundtrip_tolerance=roundtrip_tolerance, support_measure=support_measure,
                      inversion=inversion)


def Light(family, sample, *, pdf=None, points, params=None, description="", domain=None, support_measure=0.0,
          L=None, normal=None):
    """A light sampler at each of `points` (reference points, (x, y, z)): one case per point,
    named family[...,px=..,py=..,pz=..].

    Without L: sample(ref, u) -> (wi, pdf), checked as a warp on the sphere that returns its
    pdf: ref float32 (3,), u float32 (n, 2), wi (n, 3) unit directions, pdf (n,) per solid
    angle; pdf(ref, wi) -> (n,).

    With L(ref, wi) -> (n,), the light's own intersection (the radiance arriving along wi, 0
    on a miss): a light case as C++'s make_light_case makes, which the light checks take
    (light_radiance, light_support, light_irradiance). Then sample(ref, u) returns
    (wi, pdf, L[, distance]) or a dict of those keys, pdf is required, and `normal`
    (x, y, z) is the reference surface's unit normal (None: a point in a medium).
    """
    return _core.light(family, sample, pdf=pdf, points=[tuple(map(float, p)) for p in points],
                       params=dict(params or {}), description=description,
                       domain=domain if domain is not None else _core.Domain.sphere(),
                       support_measure=support_measure, L=L,
                       normal=None if normal is None else tuple(map(float, normal)))


def Bsdf(family, sample, *, f, pdf, theta_o, params=None, description="", lobes=("reflection", "continuous"),
         eta=1.0, reciprocal=True, transport="radiance", phase_function=False, stochastic=False):
    """A BSDF (or phase function) of Python callables at each outgoing direction theta_o
    (degrees, in the plane phi = 0): one case per direction, named family[...,theta_o=T].

    sample(wo, uc, u) -> (wi, f, pdf[, flags[, eta]]) or a dict of those keys (a phase
    function: sample(wo, u)): wo float32 (3,), uc (n,), u (n, 2); flags as pbrt's
    (1 reflection, 2 transmission, 4 continuous, 8 delta), by default continuous and the side wi is on.
    f(wo, wi) -> (n,) and pdf(wo, wi) -> (n,) with wo and wi (n, 3); f is also called with
    its arguments swapped (the reciprocity check).
    stochastic=True declares a layered BSDF as renderers ship it: f an unbiased estimate, the
    sample's f |cos| / pdf an unbiased estimate of its weight with a pdf only proportional, pdf()
    kept for MIS. The pointwise checks are then n/a and bsdf_expectation tests it in
    expectation, reciprocity included (BsdfClaims::stochastic).
    """
    return _core.bsdf(family, sample, f=f, pdf=pdf, theta_o=[float(t) for t in theta_o], params=dict(params or {}),
                      description=description, lobes=list(lobes), eta=eta, reciprocal=reciprocal,
                      transport=transport, phase_function=phase_function, stochastic=stochastic)


def Mis(family, bsdf, lights, *, heuristic="power", bsdf_mis_pdf=None, light_mis_pdfs=(), params=None,
        description=""):
    """The strategies a renderer's direct lighting combines by multiple importance sampling: a
    Bsdf (strategy 0) and one or more Lights with L (strategies 1..), as C++'s make_mis_case
    combines them. One MIS case per pair of the BSDF's theta_o and the lights' k-th reference
    point (every light gives the same number; the lights are seen with the BSDF's normal
    (0, 0, 1), or none for a phase function), named family[...,theta_o=T,px=..,py=..,pz=..].
    The MIS checks (mis_weights, mis_estimator) and chi2 of the one-sample mixture take it.

    heuristic: "power" (exponent 2) or "balance". bsdf_mis_pdf(wo, wi) -> (n,), wo and wi
    (n, 3), and light_mis_pdfs[k](ref, wi) -> (n,), ref (3,), are the pdfs your MIS code
    evaluates at the other strategies' samples where they are not the cases' own pdf (None or
    missing: the case's pdf); each is called once per batch of directions.
    """
    lights = list(lights) if isinstance(lights, (list, tuple)) else [lights]
    return _core.mis(family, bsdf, lights, heuristic=heuristic, bsdf_mis_pdf=bsdf_mis_pdf,
                     light_mis_pdfs=list(light_mis_pdfs), params=dict(params or {}), description=description)


def builtin_case(name):
    """One of warpcheck's built-in warp cases by its full name, e.g. "cosine_hemisphere",
    with its C++ functions: a reference for samples from elsewhere, or a case to run."""
    return _core.builtin_case(name)


# ---------------------------------------------------------------------------
# Settings, the rerun line and the evidence


def _env(name):
    value = os.environ.get(name, "")
    return value if value != "" else None


def _count(text, name):
    m = re.fullmatch(r"\s*([0-9][0-9_']*(?:\.[0-9]+)?(?:[eE][+-]?[0-9]+)?)\s*([kMGT]?)\s*", text)
    if not m:
        raise ValueError(f"{name}={text!r} is not a count (e.g. 1e6, 10M, 1_000_000)")
    value = float(m.group(1).replace("_", "").replace("'", "")) * {"": 1, "k": 1e3, "M": 1e6, "G": 1e9, "T": 1e12}[m.group(2)]
    if value != int(value):
        raise ValueError(f"{name}={text!r} is not a whole number")
    return int(value)


def _settings(seed, samples, alpha, threads, strict, exhaustive, time_budget):
    s = _core.Settings()
    env_seed, env_samples, env_alpha = _env("WARPCHECK_SEED"), _env("WARPCHECK_SAMPLES"), _env("WARPCHECK_ALPHA")
    s.seed = _count(env_seed, "WARPCHECK_SEED") if env_seed else int(seed)
    s.samples = _count(env_samples, "WARPCHECK_SAMPLES") if env_samples else _count(str(samples), "samples")
    s.alpha = float(env_alpha) if env_alpha else float(alpha)
    s.threads = int(threads)
    s.strict = bool(strict)
    s.exhaustive = bool(exhaustive)
    s.time_budget = float(time_budget or 0.0)
    return s


def _selection(filter, checks):
    env_filter, env_check = _env("WARPCHECK_FILTER"), _env("WARPCHECK_CHECK")
    filters = [env_filter] if env_filter else ([filter] if isinstance(filter, str) else list(filter or []))
    check_list = [env_check] if env_check else ([checks] if isinstance(checks, str) else list(checks or []))
    return filters, check_list


def _program():
    """The command that runs this again: the pytest test, or the script as it was started."""
    test = os.environ.get("PYTEST_CURRENT_TEST")
    if test:
        node = test.rsplit(" ", 1)[0]
        return f"{shlex.quote(sys.executable)} -m pytest {shlex.quote(node)}"
    argv = [a for a in sys.argv if a] or ["python"]
    return " ".join([shlex.quote(sys.executable)] + [shlex.quote(a) for a in argv])


def _set_rerun_lines(result, program):
    for row in result.rows:
        row.rerun_command = (f"WARPCHECK_FILTER={shlex.quote(row.case)} WARPCHECK_CHECK={row.check} "
                             f"WARPCHECK_SEED={result.seed} WARPCHECK_SAMPLES={result.samples} {program}")
    return result


def _evidence_path(stem):
    folder = os.environ.get("WARPCHECK_EVIDENCE_DIR") or os.path.join(os.getcwd(), "warpcheck-evidence")
    os.makedirs(folder, exist_ok=True)
    test = os.environ.get("PYTEST_CURRENT_TEST")
    name = test.rsplit(" ", 1)[0] if test else stem
    name = re.sub(r"[^A-Za-z0-9_.=-]+", "_", name).strip("_")[:150] or "run"
    return os.path.join(folder, name + ".html")


def _as_list(cases):
    return list(cases) if isinstance(cases, (list, tuple)) else [cases]


# ---------------------------------------------------------------------------
# Runs


def run(cases, *, filter=None, checks=None, seed=1, samples=1_000_000, alpha=0.01, threads=0, strict=False,
        exhaustive=False, time_budget=None):
    """Runs every check that applies on the cases (a case or a list) and returns the Run.

    filter: case name patterns as validate --filter takes them (substring, or glob with * and ?);
    checks: check names (check_names() lists them); the rest as validate's options.
    """
    filters, check_list = _selection(filter, checks)
    program = _program()
    result = _core.run(_as_list(cases), filters, check_list,
                       _settings(seed, samples, alpha, threads, strict, exhaustive, time_budget), program)
    return _set_rerun_lines(result, program)


class WarpcheckFailure(AssertionError):
    """A run with rows that did not pass: the message holds them, their rerun lines and
    the path of the HTML report; .run is the Run."""

    def __init__(self, message, result, report):
        super().__init__(message)
        self.run = result
        self.report = report


def _write_evidence(result, stem):
    path = _evidence_path(stem)
    result.write_html(path)
    result.write_json(path[:-5] + ".json")
    return path


def assert_passes(cases, **settings):
    """Runs the cases (as run() does) and raises WarpcheckFailure, an AssertionError, unless
    every row that applies passed: its message is each failing row with its rerun line and
    the path of the HTML report written for it. Returns the Run."""
    result = run(cases, **settings)
    if result.passed:
        return result
    report = _write_evidence(result, "assert_passes")
    raise WarpcheckFailure(f"warpcheck: not every check passed\n{result.table(failures_only=True)}"
                           f"evidence: {report}", result, report)


def assert_fails(cases, check, **settings):
    """Runs the cases and raises WarpcheckFailure unless the check `check` FAILs on every one
    of them (a wrong twin's bug): an ERROR, a pass or a failure of only some rows is not it."""
    result = run(cases, **settings)
    rows = [r for r in result.rows if r.check == check]
    if rows and all(r.verdict == "fail" for r in rows):
        return result
    report = _write_evidence(result, "assert_fails")
    shown = "\n".join(f"  {r.verdict:<14} {r.check:<12} {r.case}  {r.summary}" for r in rows) or "  (no such row)"
    raise WarpcheckFailure(f"warpcheck: expected check {check} to fail on every case, got:\n{shown}\n"
                           f"evidence: {report}", result, report)


# ---------------------------------------------------------------------------
# Samples from elsewhere


def record_inputs(case, *, checks=None, seed=1, samples=1_000_000, alpha=0.01, threads=0, strict=False):
    """Runs the case's checks and records every input they ask of sample.

    Returns (run, inputs, outputs, values): the Run, the distinct inputs sorted (float32 (n, d)
    or raw bits (n,)), the case's own outputs for them, and what sample returned with each
    (its pdf or weight) or None. Another implementation warps `inputs`; replay() judges its outputs.
    """
    _, check_list = _selection(None, checks)
    program = _program()
    result, inputs, outputs, values = _core.record_inputs(
        case, check_list, _settings(seed, samples, alpha, threads, strict, False, None), program)
    return _set_rerun_lines(result, program), inputs, outputs, values


def replay(case, inputs, outputs, *, values=None, checks=None, seed=1, samples=1_000_000, alpha=0.01, threads=0,
           strict=False):
    """Runs the case's checks with sample answered from `outputs`, row for row the outputs of
    `inputs` (as record_inputs gave them, under the same seed, samples and checks): the same
    outputs give the same figures as the case itself. The replayed case has no inverse."""
    _, check_list = _selection(None, checks)
    program = _program()
    result = _core.replay(case, np.asarray(inputs), np.asarray(outputs), values if values is None else np.asarray(values),
                          check_list, _settings(seed, samples, alpha, threads, strict, False, None), program)
    return _set_rerun_lines(result, program)


def judge_samples(case, samples, *, alpha=0.01, strict=False):
    """Judges independent samples (n rows of points, drawn elsewhere) against the case's pdf and
    domain: samples_consistency and samples_chi2. Returns the Run."""
    x = np.asarray(samples)
    return _core.judge_samples(case, x, _settings(1, max(len(x), 1000), alpha, 0, strict, False, None), _program())


def compare_same_inputs(a, b, *, max_ulps=0, floor=0.0, inputs=None, case=None, labels=("a", "b")):
    """Compares two implementations' outputs for the same inputs, row for row: the ulps
    between them (histogram, worst inputs), failing where any exceeds max_ulps or is NaN.
    floor > 0 counts values smaller than it in ulps of it (1 for directions)."""
    return _core.compare_same_inputs(np.asarray(a), np.asarray(b), int(max_ulps), float(floor),
                                     None if inputs is None else np.asarray(inputs), case, labels[0], labels[1],
                                     _program())


def two_sample(a, b, *, case=None, domain=None, alpha=0.01, labels=("a", "b")):
    """Tests whether two sets of independent samples come from one distribution: chi-square
    homogeneity on adaptive cells and Anderson-Darling on each coordinate of the domain (the
    case's, or `domain`, or by the number of columns), with its stated power."""
    n = max(len(a), len(b), 1000)
    return _core.two_sample(np.asarray(a), np.asarray(b), case, domain, labels[0], labels[1],
                            _settings(1, n, alpha, 0, False, False, None), _program())


def load_samples(path, layout=None):
    """A .npy file as an array, or raw little-endian float32 with layout (columns, "interleaved"
    or "planar"), as validate reads them."""
    if path.endswith(".npy"):
        return np.load(path)
    if layout is None:
        raise ValueError(f"{path} is not a .npy file: give its layout, e.g. (3, 'planar')")
    columns, order = layout
    data = np.fromfile(path, dtype="<f4")
    if data.size % columns:
        raise ValueError(f"{path} holds {data.size} floats, not a whole number of samples of {columns}")
    return data.reshape(columns, -1).T.copy() if order == "planar" else data.reshape(-1, columns)


def save_samples(path, array):
    """Writes an array as .npy (what validate --judge-samples, --replay and --compare read)."""
    np.save(path, np.ascontiguousarray(array))
