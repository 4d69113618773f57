#!/usr/bin/env python3
"""Checks a `microbrdf predict` output folder the way a reader would trip over it.

    scripts/check-report.py DIR [DIR...]

- summary.json is strict JSON (no NaN/Infinity) and has every top-level section;
- every file listed in summary["outputs"] exists;
- every <img> in report.html carries a non-empty data:image/png URI (no broken image, nothing
  fetched from elsewhere), and the renders are there unless they were turned off;
- no "nan", "inf", "null", "undefined" and no empty table cell in the report's text (scripts
  excluded), and no script loaded from or referring to the network (the glTF view's embedded
  three.js modules aside: inert text whose URLs are comments, see below).
Exit status 0 when all hold; otherwise the problems are printed and the status is 1.
"""
import json
import os
import re
import sys

SECTIONS = ["versions", "settings", "material", "inputs", "ndf", "fits", "ndf_cuts", "brdf",
            "renders", "texture", "outputs", "timing"]


def strict(token):
    raise ValueError("non-finite number in summary.json: " + token)


def check(folder):
    problems = []
    with open(os.path.join(folder, "summary.json")) as f:
        s = json.load(f, parse_constant=strict)
    problems += ["summary.json: no '%s'" % k for k in SECTIONS if k not in s]
    problems += ["listed output missing: " + f for f in s.get("outputs", [])
                 if not os.path.exists(os.path.join(folder, f))]
    with open(os.path.join(folder, "report.html")) as f:
        html = f.read()
    imgs = re.findall(r"<img [^>]*>", html)
    for tag in imgs:
        m = re.search(r'src="([^"]*)"', tag)
        if not m or not m.group(1).startswith("data:image/png;base64,") or len(m.group(1)) < 100:
            problems.append("broken or external image: " + tag[:80])
    if s.get("settings", {}).get("render") and not isinstance(s.get("renders"), list):
        problems.append("renders asked for but missing: %s" % s.get("renders"))
    for r in s.get("renders", []) if isinstance(s.get("renders"), list) else []:
        if ('alt="%s"' % r["scene"]) not in html:
            problems.append("render not in the report: " + r["scene"])
    if 'src="http' in html or 'href="http' in html:
        problems.append("report fetches something from the network")
    # The glTF view's library (three.js from npm, data-npm="three@VERSION PATH") sits in inert
    # text/plain elements that the page's own module script imports from blob: URLs; its text
    # holds URLs in comments and XML namespace names, none fetched (tests/browser checks that no
    # request leaves the page). Every other script must not name a URL.
    library = r'<script type="text/plain" id="mbg-mod-[a-z_]+" data-npm="three@[0-9.]+ [A-Za-z/._]+">.*?</script>'
    scripts = re.sub(library, "", html, flags=re.S)
    if re.search(r"<script[^>]*\bsrc=", html) or re.search(r"https?://", "".join(
            re.findall(r"<script.*?</script>", scripts, flags=re.S))):
        problems.append("a script of the report refers to the network")
    text = re.sub(r"<svg.*?</svg>", "", html, flags=re.S)  # glyph outlines are not numbers
    text = re.sub(r"<script.*?</script>", "", text, flags=re.S)  # code, not what a reader sees
    text = re.sub(r'src="data:[^"]*"', "", text)
    for bad in [r"\bnan\b", r"\bNaN\b", r"\binf\b", r"\bInfinity\b", r"\bnull\b", r"\bundefined\b"]:
        for m in re.finditer(bad, text):
            problems.append("'%s' in the report: ...%s..." % (m.group(0), text[max(0, m.start() - 60):m.end() + 40]))
    if re.search(r"<td[^>]*>\s*</td>", text):
        problems.append("empty table cell in the report")
    return problems, len(imgs)


def main():
    if len(sys.argv) < 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    status = 0
    for folder in sys.argv[1:]:
        try:
            problems, n = check(folder)
        except (OSError, ValueError) as e:
            problems, n = [str(e)], 0
        if problems:
            status = 1
            print("%s: %d problem(s)" % (folder, len(problems)))
            for p in problems:
                print("  " + p)
        else:
            print("%s: ok (%d embedded images, no missing number)" % (folder, n))
    return status


if __name__ == "__main__":
    sys.exit(main())
