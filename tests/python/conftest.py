"""pytest set-up for warpcheck's Python module: the examples importable, and the
evidence of failures (the HTML reports the assertion helpers write) in one folder
of the build tree per run. ctest runs this suite with PYTHONPATH at the built
package (tests/CMakeLists.txt); `cmake --workflow --preset test` includes it."""

import os
import sys

import pytest

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "validate", "python", "examples")
sys.path.insert(0, os.path.abspath(EXAMPLES))


@pytest.fixture(autouse=True)
def evidence_dir(tmp_path, monkeypatch):
    """Each test's reports go to its own temporary folder; returned for the tests that look."""
    folder = tmp_path / "evidence"
    monkeypatch.setenv("WARPCHECK_EVIDENCE_DIR", str(folder))
    for name in ("WARPCHECK_SEED", "WARPCHECK_SAMPLES", "WARPCHECK_ALPHA", "WARPCHECK_FILTER", "WARPCHECK_CHECK"):
        monkeypatch.delenv(name, raising=False)
    return folder
