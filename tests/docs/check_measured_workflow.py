#!/usr/bin/python3
"""The numbers docs/measured.md quotes from `examples/measured/workflow.sh`, checked against a run.

    check_measured_workflow.py --source REPO --build BUILD [--out DIR]

Runs the workflow (about a minute on two cores) into a temporary folder (or reads DIR when it
already holds compare/*/compare.json), then compares every number of the page's comparison
table, and the count of measured nodes in the text, with what the run wrote in
compare/{kirchhoff,filtered}/compare.json. A number printed with d decimals must equal the run's
value rounded to d decimals: a changed number in the page, or a change in the code that moves a
result, fails the test.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

from quoted_numbers import Tally

# Table row label in docs/measured.md -> the compare.json of that prediction.
ROWS = {"Kirchhoff D_K, 550 nm": "kirchhoff", "filtered NDF, σ = 1 µm": "filtered"}


def quoted(cell):
    """The numbers of a table cell, as printed."""
    return re.findall(r"\d+\.\d+", cell)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", required=True)
    ap.add_argument("--build", required=True)
    ap.add_argument("--out", help="a workflow output folder to check instead of running it")
    a = ap.parse_args()
    source, build = os.path.abspath(a.source), os.path.abspath(a.build)
    out = a.out
    if not out:
        out = os.path.join(tempfile.mkdtemp(prefix="measured-workflow-"), "run")
        env = dict(os.environ, PYTHONPATH=os.path.join(build, "python"))
        subprocess.run(["bash", os.path.join(source, "examples/measured/workflow.sh"),
                        os.path.join(build, "bin/microbrdf"), out], check=True, env=env,
                       stdout=subprocess.DEVNULL)
    doc = open(os.path.join(source, "docs/measured.md"), encoding="utf-8").read()
    tally = Tally()
    for label, name in ROWS.items():
        run = json.load(open(os.path.join(out, "compare", name, "compare.json")))
        pred, meas = run["predicted_fit"]["params"], run["measured_fit"]["params"]
        values = [run["relative_l2"], run["hellinger"], pred["alpha_x"], pred["alpha_y"],
                  meas["alpha_x"], meas["alpha_y"], run["alpha_x_ratio"], run["alpha_y_ratio"]]
        rows = [l for l in doc.split("\n") if l.startswith("| " + label)]
        if len(rows) != 1:
            tally.problem(f"table row '{label}': found {len(rows)} times")
            continue
        printed = [n for cell in rows[0].split("|")[2:] for n in quoted(cell)]
        if len(printed) != len(values):
            tally.problem(f"row '{label}': {len(printed)} numbers, expected {len(values)}")
            continue
        for p, v in zip(printed, values):
            tally.number(f"row '{label}'", p, v)
    nodes = re.search(r"([\d ]+) of the disk nodes hold data", doc)
    if nodes:
        tally.number("measured nodes", nodes.group(1).replace(" ", ""), run["nodes"])
    else:
        tally.problem("the count of measured nodes is not in the page")
    return tally.finish(f"docs/measured.md against {out}")


if __name__ == "__main__":
    sys.exit(main())
