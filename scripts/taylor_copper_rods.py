#!/usr/bin/env python3
"""The copper Taylor rods of docs/method.md §12 with a library material.

Writes one scene per measured rod from scenes/axisymmetric/taylor_copper.toml
(the rod's length, radius and speed, the spacing for ACROSS particles across
the radius, the library material MATERIAL for rod and wall), runs each with
the solver and prints the final length (the far end's mean height over the
last 30 us plus half a spacing) and the foot's radius (the probe `foot`, its
largest value plus half a spacing) against the measured length.

    scripts/taylor_copper_rods.py --material copper_ofhc_za [--across 15]
        [--bin target/release/sphcontact] [--out out/taylor_rods]
"""
import argparse
import csv
import os
import re
import subprocess
import sys

# (laboratory, L0 mm, D0 mm, V m/s, measured final length mm), as compiled in
# docs/method.md §12.
RODS = [
    ("Wilkins & Guinan 1973", 23.47, 7.62, 183.0, 16.80),
    ("Wilkins & Guinan 1973", 23.47, 7.62, 204.0, 15.70),
    ("Wilkins & Guinan 1973", 23.47, 7.62, 210.0, 15.09),
    ("Gust 1982", 30.0, 6.0, 180.0, 20.01),
    ("Jones et al. 1987", 25.4, 7.62, 178.0, 17.25),
    ("Jones et al. 1987", 25.4, 7.62, 203.0, 15.60),
    ("Johnson & Cook 1983", 25.4, 7.62, 130.0, 19.56),
    ("Johnson & Cook 1983", 25.4, 7.62, 146.0, 18.69),
    ("Johnson & Cook 1983", 25.4, 7.62, 190.0, 16.21),
]


def scene(template, material, length, diameter, speed, across):
    r = diameter / 2e3
    l = length / 1e3
    dx = r / across
    s = template
    # The material: the library entry, for rod and wall alike.
    s = re.sub(r"\[materials\.copper\].*?(?=\n\[\[bodies\]\])",
               f'[materials.copper]\nlibrary = "{material}"\n', s, flags=re.S)
    s = s.replace("spacing = 2.54e-4", f"spacing = {dx!r}")
    s = s.replace("velocity = [0.0, -190.0]", f"velocity = [0.0, {-speed!r}]")
    s = s.replace("max = [0.00381, 0.0254]", f"max = [{r!r}, {l!r}]")
    s = s.replace("min = [0.0, -0.001016], max = [0.0127, 0.0]",
                  f"min = [0.0, {-4 * dx!r}], max = [{10 * r / 3!r}, 0.0]")
    s = s.replace("at = [0.000127, 0.025273]", f"at = [{dx / 2!r}, {l - dx / 2!r}]")
    s = s.replace("at = [0.003683, 0.000127]", f"at = [{r - dx / 2!r}, {dx / 2!r}]")
    s = s.replace("at = [0.000127, 0.000127]", f"at = [{dx / 2!r}, {dx / 2!r}]")
    return s, dx


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--material", required=True)
    ap.add_argument("--across", type=int, default=15)
    ap.add_argument("--bin", default="target/release/sphcontact")
    ap.add_argument("--out", default="out/taylor_rods")
    ap.add_argument("--backend", default="cpu")
    a = ap.parse_args()
    template = open("scenes/axisymmetric/taylor_copper.toml").read()
    os.makedirs(a.out, exist_ok=True)
    print("| test (L0 × D0, mm) | V, m/s | measured Lf, mm | computed, mm | error | foot radius, mm |")
    print("|---|---|---|---|---|---|")
    for lab, l0, d0, v, lf in RODS:
        text, dx = scene(template, a.material, l0, d0, v, a.across)
        name = f"{a.material}_{l0:g}x{d0:g}_{v:g}"
        path = os.path.join(a.out, name + ".toml")
        open(path, "w").write(text)
        out = os.path.join(a.out, name)
        rc = subprocess.run([a.bin, "run", path, "--out", out, "--backend", a.backend, "--quiet"]).returncode
        if rc != 0:
            print(f"| {lab} ({l0:g} × {d0:g}) | {v:g} | {lf:.2f} | failed (exit {rc}) | | |")
            continue
        rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
        end = float(rows[-1]["time"])
        late = [float(r["top"]) for r in rows if float(r["time"]) >= end - 30e-6]
        length = (sum(late) / len(late) + dx / 2) * 1e3
        foot = (max(float(r["foot"]) for r in rows) + dx / 2) * 1e3
        print(f"| {lab} ({l0:g} × {d0:g}) | {v:g} | {lf:.2f} | {length:.2f} | {100 * (length / lf - 1):+.1f} % | {foot:.2f} |")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
