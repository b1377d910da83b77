"""The property validate_all holds every row to (tests/judged/judged_property.py):
a row's verdict agrees with the lines its check judged. Each disagreement it
exists for is caught, and agreeing rows pass."""
import importlib.util
import pathlib

_PATH = pathlib.Path(__file__).resolve().parent.parent / "judged" / "judged_property.py"
_SPEC = importlib.util.spec_from_file_location("judged_property", _PATH)
judged_property = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(judged_property)


def row(verdict, *states):
    return {"check": "chi2", "case": "c", "verdict": verdict, "message": "why",
            "judged": [{"quantity": "q%d" % i, "value": "1", "limit": "= 0", "state": s}
                       for i, s in enumerate(states)]}


def test_rows_that_agree_with_their_lines_pass():
    run = {"results": [row("pass", "within", "reported"), row("fail", "within", "beyond"),
                       row("not_applicable"), row("error")]}
    assert judged_property.disagreements(run) == []


def test_each_disagreement_is_caught():
    for bad in (row("pass", "within", "beyond"), row("fail", "within", "reported"), row("pass"),
                row("error", "within")):
        assert len(judged_property.disagreements({"results": [bad]})) == 1, bad
