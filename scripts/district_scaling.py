#!/usr/bin/env python3
"""Time per building against district size (BENCHMARKS.md#a-district-of-many-copies).

Makes districts of NX x NY copies of a CityJSON tile (scripts/tile_cityjson.py),
runs `perclod run` on each with configs/city-batch.yaml's settings at the
distances given, under /usr/bin/time -v, and writes one CSV row per district
and a chart of seconds per building by stage against the number of buildings.

Usage: scripts/district_scaling.py [--copies 1x1,2x2,3x4] [--distances 427]
           [--perclod build/perclod] [--work DIR] [--csv FILE] [--chart FILE]
           [--chart-only]
--chart-only reads the reports and time logs a previous run left in --work.
"""
import argparse
import csv
import json
import os
import re
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TILE = os.path.join(ROOT, "..", "shared", "data", "cityjson", "3dbag_5910_delft.city.json")
SETTINGS = """display: {root}/configs/displays/paper-19in.yaml
distances: [{distances}]
up: z
views: facades,ring8el30,ring8el60,top
samples: auto
simplify: fidelity
judge_views: held_out
tileset: true
debug_images: false
"""


def log(msg):
    print(f"district_scaling: {msg}", file=sys.stderr, flush=True)


def run_one(a, n):
    """Tiles, configures and runs district n ("NXxNY"); its stderr (with
    /usr/bin/time -v's figures) goes to WORK/<n>.err."""
    nx, ny = (int(k) for k in n.split("x"))
    model = os.path.join(a.work, f"d{n}.city.json")
    if (nx, ny) == (1, 1):
        shutil.copyfile(a.tile, model)
    else:
        subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "tile_cityjson.py"), a.tile, model,
                        "--copies", str(nx), str(ny)], check=True)
    config = os.path.join(a.work, f"s{n}.yaml")
    with open(config, "w") as f:
        f.write(f"out: {os.path.join(a.work, 'out' + n)}\n")
        f.write(SETTINGS.format(root=ROOT, distances=", ".join(a.distances.split(","))))
        f.write(f"models:\n  - {model}\n")
    log(f"{n}: perclod run {config}")
    with open(os.path.join(a.work, f"{n}.err"), "w") as err:
        r = subprocess.run(["/usr/bin/time", "-v", a.perclod, "run", config], stdout=subprocess.DEVNULL, stderr=err)
    if r.returncode != 0:
        sys.exit(f"district_scaling: {n}: perclod run failed (exit {r.returncode}); see {err.name}")


def row_of(a, n):
    """The CSV row of district n from its report and time log."""
    name = f"d{n}"
    report = os.path.join(a.work, "out" + n, name, name + "_report.json")
    with open(report) as f:
        r = json.load(f)
    with open(os.path.join(a.work, f"{n}.err")) as f:
        t = f.read()
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", t).group(1).split(":")
    wall_s = sum(float(x) * 60 ** i for i, x in enumerate(reversed(wall)))
    peak_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1))
    buildings = max(len(l.get("per_building", [])) for l in r["lods"])
    stage = {k: sum(l["stage_seconds"].get(k, 0) for l in r["lods"]) for k in ("label", "label_buildings", "judge")}
    return {"copies": n, "buildings": buildings, "triangles": r["triangles"], "wall_s": round(wall_s, 1),
            "peak_mib": round(peak_kb / 1024), "model_views_s": round(stage["label"] - stage["label_buildings"], 1),
            "own_views_s": round(stage["label_buildings"], 1), "judge_s": round(stage["judge"], 1),
            "other_s": round(wall_s - stage["label"] - stage["judge"], 1),
            "ms_per_building": round(1000 * wall_s / buildings)}


def chart(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    b = [r["buildings"] for r in rows]
    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    for key, label in (("wall_s", "whole run"), ("own_views_s", "own views (labelling)"),
                       ("model_views_s", "whole-model views (labelling)"), ("judge_s", "judging"),
                       ("other_s", "load, simplify, export")):
        ax.plot(b, [1000 * r[key] / r["buildings"] for r in rows], marker="o", label=label)
    ax.set_xscale("log")
    ax.set_xticks(b)
    ax.set_xticklabels([f"{x:,}" for x in b])
    ax.set_xlabel("buildings in the district (copies of the Delft tile)")
    ax.set_ylabel("ms per building")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    log(f"chart: {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--copies", default="1x1,2x2,3x4")
    ap.add_argument("--distances", default="427")
    ap.add_argument("--perclod", default=os.path.join(ROOT, "build", "perclod"))
    ap.add_argument("--tile", default=TILE)
    ap.add_argument("--work", default="/tmp/perclod-district")
    ap.add_argument("--csv", default=None, help="default: WORK/district_scaling.csv")
    ap.add_argument("--chart", default=None, help="default: WORK/district_scaling.png")
    ap.add_argument("--chart-only", action="store_true")
    a = ap.parse_args()
    sizes = a.copies.split(",")
    if not all(re.fullmatch(r"[1-9]\d*x[1-9]\d*", n) for n in sizes):
        sys.exit(f"district_scaling: --copies takes NXxNY,... (e.g. 1x1,2x2), not '{a.copies}'")
    os.makedirs(a.work, exist_ok=True)
    if not a.chart_only:
        for n in sizes:
            run_one(a, n)
    rows = [row_of(a, n) for n in sizes]
    path = a.csv or os.path.join(a.work, "district_scaling.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    for r in rows:
        log(", ".join(f"{k} {v}" for k, v in r.items()))
    chart(rows, a.chart or os.path.join(a.work, "district_scaling.png"))


if __name__ == "__main__":
    main()
