#!/usr/bin/python3
"""The table of docs/sun2002.md section 4.3 checked against the run of the block above it.

    check_sun2002_table.py DOC.md SIM.json

SIM.json is what `microbrdf sun simulate-ftp ... --json` printed. Each row of the table (s,
crossings, the four largest signed differences with their angles, the best k tau values) must
equal the run's value rounded to the digits the page prints, and the quoted bound on the
standard errors must hold. Run by run_doc_blocks.py (`<!-- doc-test: check: ... -->`).
"""
import json
import re
import sys

from quoted_numbers import Tally

# Table columns after s and crossings -> the run's record of that difference.
DIFFS = ["leaving_minus_sun", "any_minus_sun", "leaving_minus_smith_g1",
         "leaving_minus_smith_mean_plane"]


def main():
    doc = open(sys.argv[1], encoding="utf-8").read().replace("−", "-")
    run = {r["s"]: r for r in json.load(open(sys.argv[2]))["results"]}
    section = doc[doc.index("### 4.3 Results"):]
    lines = section.split("\n")
    head = next(i for i, l in enumerate(lines) if l.startswith("| s | crossings"))
    rows = []
    for l in lines[head + 2:]:  # after the header and its |---| line, up to the table's end
        if not l.startswith("|"):
            break
        rows.append(l)
    tally = Tally()
    check = tally.number
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        s = float(cells[0])
        if s not in run:
            tally.problem(f"s = {cells[0]}: not in the run")
            continue
        r = run[s]
        check(f"s = {cells[0]} crossings", cells[1].replace(" ", ""), r["crossings"])
        for cell, key in zip(cells[2:6], DIFFS):
            m = re.match(r"([-+]?\d\.\d+) at (\d+)°", cell)
            if not m:
                tally.problem(f"s = {cells[0]} {key}: cannot read {cell!r}")
                continue
            check(f"s = {cells[0]} {key}", m.group(1), r[key]["signed"])
            check(f"s = {cells[0]} {key} angle", m.group(2), r[key]["at_theta_deg"])
        leaving, any_ = cells[6].split("/")
        check(f"s = {cells[0]} best k tau (leaving)", leaving.strip(), r["best_k_tau_leaving"])
        check(f"s = {cells[0]} best k tau (any)", any_.strip(), r["best_k_tau_any"])
    if len(rows) != len(run):
        tally.problem(f"{len(rows)} table rows for {len(run)} values of s in the run")
    bound = re.search(r"Standard errors of the simulated points ≤ (\d\.\d+)", doc)
    worst = max(r["max_standard_error_leaving"] for r in run.values())
    tally.checked += 1
    if not bound or round(worst, len(bound.group(1)) - 2) > float(bound.group(1)):
        tally.problem(f"standard errors: the page says ≤ {bound.group(1) if bound else '?'}, "
                      f"the run's largest is {worst:.4g}")
    return tally.finish(f"{sys.argv[1]}, section 4.3")


if __name__ == "__main__":
    sys.exit(main())
