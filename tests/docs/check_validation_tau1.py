#!/usr/bin/python3
"""The tau = 1 µm row of docs/validation.md's `--filter-sigma auto` table, checked against the
run of the block above it (which writes tau1.out.json, dk1/naive1/f1.npy and their --json).

    check_validation_tau1.py DOC.md

Run in the block's folder by run_doc_blocks.py (`<!-- doc-test: check: ... -->`). Each number of
the row must equal the run's value rounded to the digits the page prints; H at 1 µm is the
Hellinger distance of the 1 µm filtered table to D_K (mb.hellinger_distance).
"""
import json
import re
import sys

import microbrdf as mb
from quoted_numbers import Tally


def main():
    doc = open(sys.argv[1], encoding="utf-8").read()
    rows = [l for l in doc.split("\n") if l.startswith("| 1 µm |")]
    tally = Tally()
    if len(rows) != 1:
        tally.problem(f"the tau = 1 µm row: found {len(rows)} times")
        return tally.finish(sys.argv[1])
    cells = [c.strip() for c in rows[0].strip("|").split("|")]
    auto = json.load(open("tau1.out.json"))["filter_sigma_auto"]
    slopes = [json.load(open(f))["slope_rms_x"] for f in ("naive1.out.json", "dk1.out.json",
                                                           "f1.out.json")]
    for name, printed, value in zip(("naive", "D_K", "filtered at 1 um"), cells[1].split("/"),
                                    slopes):
        tally.number(f"rms slope x, {name}", printed.strip(), value)
    chosen = re.match(r"(\d+) nm", cells[2])
    tally.number("chosen sigma (nm)", chosen.group(1) if chosen else "nan", auto["sigma_m"] * 1e9)
    if "smallest swept" in cells[2] and not auto["sweep"]["at_lower_end"]:
        tally.problem("the page says the smallest swept sigma; the run's minimum is not there")
    largest = max(auto["curve"], key=lambda p: p["sigma_m"])
    h_1um = mb.hellinger_distance(mb.read_ndf("f1.npy"), mb.read_ndf("dk1.npy"))
    for what, printed, value in (("H at the chosen sigma", cells[3], auto["hellinger"]),
                                 ("H of the naive NDF", cells[4],
                                  auto["distances"]["naive_kirchhoff"]),
                                 ("H at 1 um", cells[5], h_1um),
                                 ("H at the largest sigma", cells[6], largest["hellinger"]),
                                 ("D_K raw integral", cells[7],
                                  auto["sweep"]["kirchhoff_raw_integral"])):
        tally.number(what, printed, value)
    return tally.finish(f"{sys.argv[1]}, tau = 1 µm row")


if __name__ == "__main__":
    sys.exit(main())
