#!/usr/bin/env python3
"""Draws the scatterplot with crossing lines of issue 21: 1500x800, 400 dots of radius 3 to 13
in five colours and 60 random grey lines 2 px wide, on white. A picture that once cost the
mesh's solver most of a second (many folds to repair). Needs pillow.

Usage: crossing_lines.py OUT.png [--seed N]"""
import argparse
import random

from PIL import Image, ImageDraw


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--seed", type=int, default=7)
    a = p.parse_args()
    rng = random.Random(a.seed)
    w, h = 1500, 800
    img = Image.new("RGB", (w, h), "white")
    d = ImageDraw.Draw(img)
    for _ in range(60):
        g = rng.randint(90, 190)
        d.line([(rng.uniform(0, w), rng.uniform(0, h)), (rng.uniform(0, w), rng.uniform(0, h))],
               fill=(g, g, g), width=2)
    colours = [(31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189)]
    for _ in range(400):
        r = rng.uniform(3, 13)
        x, y = rng.uniform(r, w - r), rng.uniform(r, h - r)
        d.ellipse([x - r, y - r, x + r, y + r], fill=rng.choice(colours))
    img.save(a.out)


if __name__ == "__main__":
    main()
