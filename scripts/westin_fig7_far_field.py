#!/usr/bin/python3
"""W92 Fig. 7's far-field check from the `render --json` summaries of scripts/make-westin-fig7.sh.

  westin_fig7_far_field.py WORK_DIR

Reads WORK_DIR/far_{0,90}.json (the cylinder array drawn as geometry, each cylinder far below a
pixel) and WORK_DIR/sh_{0,90}.json (the plate with the SH BRDF simulated from the same
cylinders), both of the whole image under the same light and camera, and writes
WORK_DIR/far_field.json: per orientation the mean luminance (Y of linear sRGB, Rec. 709
weights) of each and their ratio. Prints the table docs/westin.md quotes.
"""
import json
import pathlib
import sys


def luminance(summary: dict) -> float:
    r, g, b = summary["mean_linear_srgb"]
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def main() -> int:
    w = pathlib.Path(sys.argv[1])
    rows = []
    for angle, axis in ((0, "across the screen (horizontal)"), (90, "along the screen (vertical)")):
        geo = json.loads((w / f"far_{angle}.json").read_text())
        sh = json.loads((w / f"sh_{angle}.json").read_text())
        y_geo, y_sh = luminance(geo), luminance(sh)
        rows.append({"brush_angle_deg": angle, "cylinder_axes": axis, "geometry_luminance": y_geo,
                     "sh_brdf_luminance": y_sh, "ratio_geometry_over_sh": y_geo / y_sh})
        print(f"axes {axis}: geometry {y_geo:.4f}, SH BRDF {y_sh:.4f}, ratio {y_geo / y_sh:.3f}")
    (w / "far_field.json").write_text(json.dumps({"orientations": rows}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
