#!/usr/bin/env python3
"""Writes the 2000-stroke chisel slab (Kizamu figure 1 in spirit) as a stroke script.

A slab 0.8 x 0.8 x 0.2 of a unit domain; 2000 strokes of a cylinder tool (axis vertical,
radius 0.5-1.5 % of the domain), each at a random position, direction and length (up to 10 %
of the domain) on the top face, cutting up to 1 % of the domain deep. Fixed seed, so results
compare across machines: `scripts/make_slab.py > examples/slab2000.jsonl` reproduces the
committed file byte for byte (the CLI test checks).
"""
import json
import math
import random
import sys

SEED = 20011001
STROKES = 2000
LEVEL = 12


def main():
    rng = random.Random(SEED)
    top = 0.5 + 0.1
    header = {"kizamu": "stroke-script", "version": 1,
              "domain": {"origin": [0.0, 0.0, 0.0], "size": 1.0, "level": LEVEL, "tile_span": 6},
              "start": {"shape": "box", "centre": [0.5, 0.5, 0.5], "half": [0.4, 0.4, 0.1]}}
    out = [json.dumps(header)]
    half_length = 0.01
    for _ in range(STROKES):
        radius = round(rng.uniform(0.005, 0.015), 6)
        depth = round(rng.uniform(0.001, 0.01), 6)
        x, y = rng.uniform(0.12, 0.88), rng.uniform(0.12, 0.88)
        angle, length = rng.uniform(0.0, 2.0 * math.pi), rng.uniform(0.005, 0.1)
        z = round(top + half_length - depth, 6)
        a = [round(x, 6), round(y, 6), z]
        b = [round(x + length * math.cos(angle), 6), round(y + length * math.sin(angle), 6), z]
        out.append(json.dumps({"op": "carve", "shape": "cylinder", "radius": radius,
                               "length": 2 * half_length, "path": [a, b]}))
    sys.stdout.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
