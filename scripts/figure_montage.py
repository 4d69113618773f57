#!/usr/bin/python3
"""Tiles PNG images into one figure, each with a caption under it, rows of equal cells.

  figure_montage.py OUT.png --cols N [--cell PX] [--title TEXT] IMG.png=CAPTION ...

Images are scaled to --cell pixels wide (aspect kept; default: the first image's width). Used
by scripts/make-westin-fig7.sh, make-westin-fig14.sh and make-sun-fig9.sh (the figures of
docs/westin.md and docs/sun2002.md). Needs Pillow (python3-pil).
"""
import argparse
import sys

from PIL import Image, ImageDraw, ImageFont


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--cols", type=int, required=True)
    ap.add_argument("--cell", type=int, default=0)
    ap.add_argument("--title", default="")
    ap.add_argument("items", nargs="+", help="IMAGE.png=CAPTION")
    a = ap.parse_args()
    items = [it.split("=", 1) if "=" in it else (it, "") for it in a.items]
    imgs = [Image.open(p).convert("RGB") for p, _ in items]
    cell = a.cell or imgs[0].width
    imgs = [im.resize((cell, round(im.height * cell / im.width)), Image.LANCZOS) for im in imgs]
    font = ImageFont.load_default()
    line = 12  # the default bitmap font's line height
    cap_lines = max(len(c.split("\\n")) for _, c in items)
    cell_h = max(im.height for im in imgs) + cap_lines * line + 6
    rows = (len(imgs) + a.cols - 1) // a.cols
    top = line + 8 if a.title else 0
    fig = Image.new("RGB", (a.cols * (cell + 4) + 4, top + rows * cell_h + 4), "white")
    draw = ImageDraw.Draw(fig)
    if a.title:
        draw.text((6, 4), a.title, fill="black", font=font)
    for i, (im, (_, cap)) in enumerate(zip(imgs, items)):
        x, y = 4 + (i % a.cols) * (cell + 4), top + 4 + (i // a.cols) * cell_h
        fig.paste(im, (x, y))
        for k, text in enumerate(cap.split("\\n")):
            draw.text((x + 2, y + im.height + 2 + k * line), text, fill="black", font=font)
    fig.save(a.out, optimize=True)
    print(f"wrote {a.out} ({fig.width} x {fig.height})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
