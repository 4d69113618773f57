#!/usr/bin/python3
"""The papers' figures made by scripts/make-westin-fig7.sh, make-westin-fig14.sh and
make-sun-fig9.sh: what they must show, and the numbers the pages quote from them.

    check_paper_figures.py PAGE.md fig7|fig14|fig9 WORK_DIR

Run by run_doc_blocks.py after the block that runs the script (`<!-- doc-test: check: ... -->`),
in the block's folder (figures in docs/img/, the script's files in WORK_DIR).

fig7   W92 Fig. 7: the cylinder array drawn as geometry far away and the plate with the SH BRDF
       simulated from it agree in mean luminance within 5 % at both orientations (W92's check of
       its hierarchy); the page's table is the run's far_field.json.
fig9   Sun Fig. 9: on every vase the highlight's full width at half maximum along the row equals
       the width predicted from the analytic BRDF within 5 %, the measured widths fall with s
       from s = 1 on (as the lobe's half-width does) for each metal, and the page's table is the
       run's widths.json.
fig14  W92 Fig. 14: the weave with diffuse threads (albedo 0.8) is brighter than with the dark
       nylon-thread BRDF.
Every figure is a PNG under 300 KB.
"""
import json
import os
import re
import sys

from quoted_numbers import Tally

FIGURES = {"fig7": "westin_fig7.png", "fig9": "sun_fig9.png", "fig14": "westin_fig14.png"}
MAX_BYTES = 300 * 1024


def table_rows(doc, first_cell):
    return [[c.strip() for c in line.strip().strip("|").split("|")]
            for line in doc.split("\n") if re.match(r"\|\s*" + re.escape(first_cell) + r"\s*\|", line)]


def fig7(doc, work, tally):
    data = json.load(open(os.path.join(work, "far_field.json")))["orientations"]
    for o in data:
        ratio = o["ratio_geometry_over_sh"]
        if abs(ratio - 1) > 0.05:
            tally.problem(f"axes {o['cylinder_axes']}: geometry / SH BRDF = {ratio:.4f}, not within 5 %")
        rows = table_rows(doc, o["cylinder_axes"])
        if len(rows) != 1:
            tally.problem(f"the row '{o['cylinder_axes']}': found {len(rows)} times")
            continue
        for printed, value in zip(rows[0][1:4], (o["geometry_luminance"], o["sh_brdf_luminance"], ratio)):
            tally.number(f"{o['cylinder_axes']}", printed, value)


def fig9(doc, work, tally):
    data = json.load(open(os.path.join(work, "widths.json")))
    metals = list(data["vases"][0]["measured"])
    for v in data["vases"]:
        for m, meas in v["measured"].items():
            if abs(meas["ratio"] - 1) > 0.05:
                tally.problem(f"{m}, s = {v['s']:g}: measured / predicted width {meas['ratio']:.3f}, not within 5 %")
        rows = table_rows(doc, f"s = {v['s']:g}")
        if len(rows) != 1:
            tally.problem(f"the row s = {v['s']:g}: found {len(rows)} times")
            continue
        cells = rows[0]
        tally.number(f"s = {v['s']:g}, lobe half-width", cells[1].split()[0], v["theta_half_deg"])
        px, rel = re.match(r"([\d.]+) \(([\d.]+)\)", cells[2]).groups()
        tally.number(f"s = {v['s']:g}, predicted px", px, v["predicted_fwhm_px"])
        tally.number(f"s = {v['s']:g}, predicted relative", rel, v["predicted_fwhm_px"] / v["vase_width_px"])
        for m, cell in zip(metals, cells[3:]):
            px, ratio = re.match(r"([\d.]+) \(([\d.]+)\)", cell).groups()
            tally.number(f"s = {v['s']:g}, {m} px", px, v["measured"][m]["fwhm_px"])
            tally.number(f"s = {v['s']:g}, {m} ratio", ratio, v["measured"][m]["ratio"])
    for m in metals:
        widths = [v["measured"][m]["fwhm_px"] for v in data["vases"] if v["s"] >= 1]
        if any(b >= a for a, b in zip(widths, widths[1:])):
            tally.problem(f"{m}: the widths do not fall with s from s = 1 on: {widths}")


def fig14(doc, work, tally):
    def mean_y(name):
        r, g, b = json.load(open(os.path.join(work, name)))["mean_linear_srgb"]
        return 0.2126 * r + 0.7152 * g + 0.0722 * b
    if not mean_y("cloth_diffuse.render.json") > mean_y("cloth.render.json"):
        tally.problem("the diffuse weave is not brighter than the nylon one")


def main():
    page, which, work = sys.argv[1], sys.argv[2], sys.argv[3]
    doc = open(page, encoding="utf-8").read()
    tally = Tally()
    {"fig7": fig7, "fig9": fig9, "fig14": fig14}[which](doc, work, tally)
    png = os.path.join("docs", "img", FIGURES[which])
    if not os.path.isfile(png) or os.path.getsize(png) > MAX_BYTES:
        tally.problem(f"{png}: missing or over 300 KB")
    return tally.finish(f"{page}, {which}")


if __name__ == "__main__":
    sys.exit(main())
