#!/usr/bin/env python3
"""Cross-check of the judge's perceptual measure against butteraugli.

Reads a bench_fidelity CSV made with --pairs DIR (and --pairs-all for more
rows), scores every row's pair image (column pair_image, the held-out view
az22.5el45 of that LOD) against its model and distance's original with
butteraugli, and reports the rank agreement with butteraugli of

  - pair_visible: the judge's visible_ratio of that view (visible difference
    over the view's quarter-pixel floor),
  - pair_changed: the view's changed fraction,
  - 1 - pair_ssim: the view's covered-region SSIM,

as Spearman's rho and Kendall's tau-b over all rows with a pair, and per
model and distance. Writes the joined rows to --out (CSV).

  scripts/judge_vs_butteraugli.py --csv FIDELITY.csv --pairs DIR --out OUT.csv
"""
import argparse
import csv
import hashlib
import os
import shutil
import subprocess
import sys


def ranks(xs):
    """Average ranks (1-based), ties sharing the mean of their positions."""
    order = sorted(range(len(xs)), key=lambda i: xs[i])
    r = [0.0] * len(xs)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and xs[order[j + 1]] == xs[order[i]]:
            j += 1
        for k in range(i, j + 1):
            r[order[k]] = (i + j) / 2 + 1
        i = j + 1
    return r


def pearson(a, b):
    n = len(a)
    ma, mb = sum(a) / n, sum(b) / n
    sab = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    sa = sum((x - ma) ** 2 for x in a) ** 0.5
    sb = sum((y - mb) ** 2 for y in b) ** 0.5
    return sab / (sa * sb) if sa > 0 and sb > 0 else float("nan")


def spearman(a, b):
    return pearson(ranks(a), ranks(b))


def kendall_tau_b(a, b):
    n = len(a)
    conc = disc = ties_a = ties_b = 0
    for i in range(n):
        for j in range(i + 1, n):
            da, db = a[i] - a[j], b[i] - b[j]
            if da == 0 and db == 0:
                continue
            if da == 0:
                ties_a += 1
            elif db == 0:
                ties_b += 1
            elif (da > 0) == (db > 0):
                conc += 1
            else:
                disc += 1
    denom = ((conc + disc + ties_a) * (conc + disc + ties_b)) ** 0.5
    return (conc - disc) / denom if denom > 0 else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--csv", required=True, help="bench_fidelity --csv output (with --pairs)")
    ap.add_argument("--pairs", required=True, help="the --pairs directory")
    ap.add_argument("--out", required=True, help="joined rows with butteraugli (CSV)")
    a = ap.parse_args()
    ba = shutil.which("butteraugli")
    if not ba:
        sys.exit("butteraugli is missing (apt-get install butteraugli, or scripts/setup.sh)")
    with open(a.csv) as f:
        rows = [r for r in csv.DictReader(f) if r.get("pair_image")]
    scores = {}
    for r in rows:
        img = r["pair_image"]
        if img in scores:
            r["butteraugli"] = scores[img]
            continue
        original = os.path.join(a.pairs, f"{r['model']}_{r['distance']}m_original.png")
        p = subprocess.run([ba, original, os.path.join(a.pairs, img)], capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"butteraugli on {img}: {p.stderr.strip()}")
        scores[img] = r["butteraugli"] = float(p.stdout.split()[0])
    fields = ["model", "distance", "method", "triangles", "note", "pair_image", "butteraugli", "pair_visible",
              "pair_changed", "pair_ssim", "visible_worst", "visible_median", "held_changed", "held_ssim"]
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)

    def report(label, sub):
        b = [float(r["butteraugli"]) for r in sub]
        measures = {"visible ratio": [float(r["pair_visible"]) for r in sub],
                    "changed fraction": [float(r["pair_changed"]) for r in sub],
                    "1 - SSIM": [1 - float(r["pair_ssim"]) for r in sub]}
        cells = [f"{spearman(m, b):+.3f} / {kendall_tau_b(m, b):+.3f}" for m in measures.values()]
        print(f"| {label} | {len(sub)} | " + " | ".join(cells) + " |")

    print("Rank agreement with butteraugli (Spearman rho / Kendall tau-b)\n")
    print("| rows | n | visible ratio | changed fraction | 1 - SSIM |")
    print("|---|---|---|---|---|")
    report("all", rows)
    for key in sorted({(r["model"], float(r["distance"])) for r in rows}):
        report(f"{key[0]}, {key[1]:g} m", [r for r in rows if (r["model"], float(r["distance"])) == key])
    named = [r for r in rows if not r["method"].startswith(("meshopt sweep", "meshopt error"))]
    if 0 < len(named) < len(rows):
        report("all but the meshoptimizer sweeps", named)
    # The near-lossless end, where a judge must tell LODs apart, chosen by
    # the reference metric (butteraugli ~1 is a just-noticeable difference).
    near = [r for r in rows if float(r["butteraugli"]) <= 10]
    if 2 < len(near) < len(rows):
        report("butteraugli <= 10", near)
    # One row per distinct image: a stalled meshoptimizer sweep makes the
    # same LOD at several targets, which would count one pair many times.
    unique = {}
    for r in rows:
        with open(os.path.join(a.pairs, r["pair_image"]), "rb") as f:
            digest = hashlib.sha1(f.read()).hexdigest()
        unique.setdefault((r["model"], r["distance"], digest), r)
    distinct = list(unique.values())
    if len(distinct) < len(rows):
        report("all, distinct images", distinct)
        for key in sorted({(r["model"], float(r["distance"])) for r in distinct}):
            report(f"{key[0]}, {key[1]:g} m, distinct", [r for r in distinct
                                                           if (r["model"], float(r["distance"])) == key])
        report("distinct, butteraugli <= 10", [r for r in distinct if float(r["butteraugli"]) <= 10])
    # Where the two disagree most: per model and distance, the distinct rows
    # whose ranks by visible ratio and by butteraugli lie furthest apart.
    print("\nLargest rank disagreements (distinct images; rank 1 = closest to the original)\n")
    print("| model, d | method | tris | visible ratio (rank) | butteraugli (rank) | changed % (rank) |")
    print("|---|---|---|---|---|---|")
    for key in sorted({(r["model"], float(r["distance"])) for r in distinct}):
        sub = [r for r in distinct if (r["model"], float(r["distance"])) == key]
        rv = ranks([float(r["pair_visible"]) for r in sub])
        rb = ranks([float(r["butteraugli"]) for r in sub])
        rc = ranks([float(r["pair_changed"]) for r in sub])
        worst = sorted(range(len(sub)), key=lambda i: -abs(rv[i] - rb[i]))[:3]
        for i in worst:
            r = sub[i]
            print(f"| {key[0]}, {key[1]:g} m | {r['method']} {r['note'][:12]} | {r['triangles']} | "
                  f"{float(r['pair_visible']):.3f} ({rv[i]:g}) | {float(r['butteraugli']):.2f} ({rb[i]:g}) | "
                  f"{100 * float(r['pair_changed']):.2f} ({rc[i]:g}) |")


if __name__ == "__main__":
    main()
