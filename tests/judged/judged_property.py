#!/usr/bin/env python3
"""Holds every row of a validate --json file to the judgement its check wrote:
a pass has no judged line beyond its limit, a failure at least one (the rule
that failed it), and a row that passed or failed has its lines. Errors and n/a
rows judged nothing. Usage: judged_property.py RESULTS.json; exits 1 on a row
that disagrees, printing it."""
import json
import sys


def disagreements(run):
    out = []
    for r in run["results"]:
        if r["verdict"] not in ("pass", "fail"):
            if r["judged"]:
                out.append((r, "an error or n/a row with judged lines"))
            continue
        beyond = [j for j in r["judged"] if j["state"] == "beyond"]
        if not r["judged"]:
            out.append((r, "no judged lines"))
        elif r["verdict"] == "pass" and beyond:
            out.append((r, "passed with lines beyond their limits: %s" % beyond))
        elif r["verdict"] == "fail" and not beyond:
            out.append((r, "failed with no line beyond its limit: %s" % r["message"][:300]))
    return out


def main(path):
    with open(path, encoding="utf-8") as f:
        run = json.load(f)
    bad = disagreements(run)
    for r, why in bad:
        print("%s %s (%s): %s" % (r["check"], r["case"], r["verdict"], why))
    judged = sum(1 for r in run["results"] if r["verdict"] in ("pass", "fail"))
    print("judged_property: %d rows judged, %d disagree with their lines" % (judged, len(bad)))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
