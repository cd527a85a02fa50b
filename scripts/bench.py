#!/usr/bin/python3
"""perclod's benchmarks in one command: CSV for every run, PNG charts, and a
Markdown summary that BENCHMARKS.md quotes.

  scripts/bench.py [--out DIR] [--sections tracers,simplifiers,stability,scaling]
                   [--build DIR] [--smoke] [--charts-only]

Sections (each writes DIR/<name>.csv and its charts):
  tracers      bench_raycast: octree, Embree rtcIntersect1 / rtcIntersect16 /
               verify and the OSMesa ID buffer at 1 and 2 threads on generated
               facades of 10k..2M triangles and the 53-building block.
  simplifiers  bench_fidelity: fidelity (several e_I), paper, bounded, cluster,
               qem, OpenMesh's Decimater and meshoptimizer (count and error sweeps) judged from
               labelling and held-out views on the real models at 56/132/427 m;
               butteraugli on one held-out view per LOD (bench_fidelity
               --pairs); bench_simplify: time and memory beside meshoptimizer
               and OpenMesh's Decimater on a 1M facade and the block.
  sweeps       bench_fidelity --set: the perceptual pipeline's settings one at
               a time (resolution, DWT levels, CSF constant, fir vs weights,
               threshold T, label ratio, samples per pixel, view set) on the
               demo: labelling time, triangles and fidelity of the default LOD.
  stability    bench_labels --section stability: label flips under a
               +-0.25 px shift, by count, by traced samples and by size class
               (views pooled, the default, and perceptible-in-any-view beside it);
               bench_fidelity --label-shift: what those flips change in the
               fidelity and paper LODs.
  scaling      perclod run on generated facades of 10k..2M triangles and on
               one facade with 4..29 views per distance: wall time, CPU and peak memory
               (/usr/bin/time), with the fitted exponent.

  failures     perclod run on the inputs where methods fail: coplanar
               duplicates, a side seen at 85 degrees, UTM coordinates,
               a non-manifold soup, single-pixel ornaments, a model under 500
               pixels, a view whose eye stands inside a neighbouring building,
               the eye 1 m from the model: what perclod reports and
               how its LOD scores.

--smoke runs every section on tiny inputs (the CI test suite does, to keep
this script and the bench programs working); its figures mean nothing.
--charts-only redraws charts and summary from the CSVs already in DIR.

Needs build/ with the bench programs (PERCLOD_BUILD_BENCH, on by default),
python3-matplotlib, butteraugli and /usr/bin/time (scripts/setup.sh installs
them). Run it on a quiet machine: the timings are wall-clock.
"""
import argparse
import csv
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from obj_to_cityjson import read_obj  # noqa: E402  (the scripts' one OBJ reader)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_VIEWS = "facades,ring8el30,ring8el60,top"  # perclod's kDefaultViews (pipeline/render/include/perclod/views.h)
SECTIONS = ("tracers", "simplifiers", "sweeps", "stability", "scaling", "failures")

# --smoke: bench_fidelity at a quarter of the display's resolution (a
# sixteenth of the pixels to label, render and judge; 24 -> 5 s for the
# simplifiers section's run). The smoke checks the machinery, and its
# figures mean nothing anyway.
SMOKE_FIDELITY = ["--set", "resolution=0.25"]

# The perceptual pipeline's settings, one at a time from the default
# (bench_fidelity --set KEY=VALUE; "default" changes nothing).
SWEEPS = [("default", []), ("resolution=1.5", ["resolution=1.5"]), ("levels=3", ["levels=3"]),
          ("levels=4", ["levels=4"]), ("levels=6", ["levels=6"]), ("csf_k=0.114", ["csf_k=0.114"]),
          ("csf=weights", ["csf=weights"]), ("threshold=2", ["threshold=2"]), ("threshold=4", ["threshold=4"]),
          ("ratio=0.3", ["ratio=0.3"]), ("ratio=0.7", ["ratio=0.7"]), ("samples=1", ["samples=1"]),
          ("samples=2", ["samples=2"]), ("samples=8", ["samples=8"]), ("views=facades", ["views=facades"]),
          ("views=facades,ring8el30", ["views=facades,ring8el30"]),
          ("views=facades,ring8el30,top", ["views=facades,ring8el30,top"])]


def log(msg):
    print(f"bench: {msg}", file=sys.stderr, flush=True)


def fail(msg):
    print(f"bench: error: {msg}", file=sys.stderr)
    sys.exit(1)


def run(cmd, stdout_path=None):
    """Runs cmd; its stdout goes to stdout_path (the bench's own table)."""
    log(" ".join(cmd))
    t0 = time.time()
    with open(stdout_path, "w") if stdout_path else open(os.devnull, "w") as out:
        r = subprocess.run(cmd, stdout=out, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        fail(f"{os.path.basename(cmd[0])} exited {r.returncode}:\n{r.stderr[-2000:]}")
    log(f"  done in {time.time() - t0:.0f} s")
    return r


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def machine():
    info = {"cpu": platform.processor() or platform.machine(), "cores": os.cpu_count(),
            "python": platform.python_version(), "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    info["cpu"] = line.split(":", 1)[1].strip()
                    break
        with open("/proc/meminfo") as f:
            info["memory_gib"] = round(int(f.readline().split()[1]) / 2**20, 1)
    except OSError:
        pass
    try:
        info["commit"] = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                                        text=True).stdout.strip()
    except OSError:
        pass
    return info


# ---- running -----------------------------------------------------------------


def run_tracers(a, out):
    sizes = "5000" if a.smoke else "10000,50000,200000,500000,1000000,2000000"
    cmd = [a.bin("bench_raycast"), "1" if a.smoke else "3", "--sizes", sizes, "--csv", out("tracers.csv")]
    if a.smoke:
        cmd.append("--no-real")
    run(cmd, out("tracers.txt"))


def run_simplifiers(a, out):
    butteraugli = shutil.which("butteraugli")  # checked first: the benches take minutes
    if not butteraugli:
        fail("butteraugli is missing (apt-get install butteraugli, or scripts/setup.sh)")
    pairs = out("pairs")
    shutil.rmtree(pairs, ignore_errors=True)
    os.makedirs(pairs)
    if a.smoke:
        fid = ["--models", "demo", "--distances", "427", "--e-imperceptible", "1"] + SMOKE_FIDELITY
        simp = ["--runs", "1", "--facade-triangles", "5000", "--skip-decimater", "--no-city"]
    else:
        fid = ["--models", "demo,han,sibenik,sponza", "--distances", "56,132,427", "--e-imperceptible", "0.5,1,2,4"]
        simp = ["--runs", "3"]
    run([a.bin("bench_fidelity")] + fid + ["--csv", out("fidelity.csv"), "--pairs", pairs], out("fidelity.txt"))
    run([a.bin("bench_simplify")] + simp + ["--csv", out("simplify_time.csv")], out("simplify_time.txt"))
    rows = []
    for name in sorted(os.listdir(pairs)):
        if not name.endswith("_original.png"):
            continue
        tag = name[: -len("_original.png")]
        for other in sorted(os.listdir(pairs)):
            if other.startswith(tag + "_") and other != name:
                r = subprocess.run([butteraugli, os.path.join(pairs, name), os.path.join(pairs, other)],
                                   capture_output=True, text=True)
                if r.returncode != 0:
                    fail(f"butteraugli on {other}: {r.stderr.strip()}")
                model, dist = tag.rsplit("_", 1)
                rows.append({"model": model, "distance": dist.rstrip("m"), "method": other[len(tag) + 1: -4],
                             "butteraugli": r.stdout.strip()})
    with open(out("butteraugli.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["model", "distance", "method", "butteraugli"])
        w.writeheader()
        w.writerows(rows)


def run_sweeps(a, out):
    # The smoke: the default and one --set that costs no more (resolution=1.5
    # would render 2.25x the pixels).
    sweeps = [SWEEPS[0], SWEEPS[2]] if a.smoke else SWEEPS
    args = ["--models", "demo", "--distances", "427" if a.smoke else "56,132,427", "--e-imperceptible", "0.5",
            "--only-fidelity"] + (SMOKE_FIDELITY if a.smoke else [])
    merged, header = [], None
    with open(out("sweeps.txt"), "w") as txt:
        for name, sets in sweeps:
            part = out("sweep_part.csv")
            cmd = [a.bin("bench_fidelity")] + args + ["--csv", part]
            for kv in sets:
                cmd += ["--set", kv]
            run(cmd, out("sweep_part.txt"))
            with open(part) as f:
                lines = f.read().splitlines()
            header = "setting," + lines[0]
            method = lines[0].split(",").index("method")
            # The fidelity LOD's rows only: bench_fidelity also prints the
            # original moved by a quarter pixel (section 1's noise floor).
            merged += [f'"{name}",{line}' for line in lines[1:]  # names hold commas
                       if next(csv.reader([line]))[method].startswith("fidelity")]
            with open(out("sweep_part.txt")) as f:
                txt.write(f"## {name}\n" + f.read())
            os.remove(part)
            os.remove(out("sweep_part.txt"))
    with open(out("sweeps.csv"), "w") as f:
        f.write("\n".join([header] + merged) + "\n")


def run_stability(a, out):
    """The +-0.25 px shift on every model; a one-pixel shift, vertex noise and
    a finer display on the demo and han. One CSV, one row per perturbation."""
    if a.smoke:
        common = ["--distances", "427", "--samples", "1", "--views", "facades"]
        runs = [("shift", ["--models", "demo"]), ("resolution", ["--models", "demo", "--perturb", "resolution"])]
    else:
        common = ["--distances", "56,132,427", "--samples", "auto", "--views", DEFAULT_VIEWS]  # the defaults
        runs = [("shift", ["--models", "demo,han,block"]),
                ("shift_any", ["--models", "demo,han", "--rule", "any"]),  # the paper's rule, beside it
                ("shift1px", ["--models", "demo,han", "--shift-scale", "4"]),
                ("noise", ["--models", "demo,han", "--perturb", "noise"]),
                ("resolution", ["--models", "demo,han", "--perturb", "resolution"])]
    merged, header = [], None
    with open(out("stability.txt"), "w") as txt:
        for name, args in runs:
            part = out(f"stability_{name}.csv")
            run([a.bin("bench_labels"), "--section", "stability"] + args + common + ["--csv", part],
                out(f"stability_{name}.txt"))
            with open(part) as f:
                lines = f.read().splitlines()
            header = lines[0]
            merged += lines[1:]
            os.remove(part)
            with open(out(f"stability_{name}.txt")) as f:
                txt.write(f.read())
            os.remove(out(f"stability_{name}.txt"))
    with open(out("stability.csv"), "w") as f:
        f.write("\n".join([header] + merged) + "\n")
    # What the flips change in the LOD: fidelity and paper LODs from the
    # labels of the model moved by -1/4, 0 and +1/4 px, judged against the
    # unmoved model (bench_fidelity --label-shift).
    models, dists = ("demo", "427") if a.smoke else ("demo,han", "56,132,427")
    run([a.bin("bench_fidelity"), "--models", models, "--distances", dists, "--e-imperceptible", "0.5",
         "--only-fidelity", "--label-shift", "--csv", out("stability_lod.csv")] + (SMOKE_FIDELITY if a.smoke else []),
        out("stability_lod.txt"))


def timed_run(a, work, model, views, distances, name):
    """perclod run of `model` under /usr/bin/time: (wall s, CPU %, peak MiB,
    labelling views + tiles over all distances, judged views)."""
    cfg = os.path.join(work, name + ".yaml")
    with open(cfg, "w") as f:
        f.write(f"model: {model}\nup: z\ndistances: [{', '.join(str(d) for d in distances)}]\n"
                f"views: {views}\nsamples: auto\ndebug_images: false\nout: {os.path.join(work, 'out-' + name)}\n")
    timing = os.path.join(work, "time.txt")
    cmd = ["/usr/bin/time", "-f", "%e %P %M", "-o", timing, a.bin("perclod"), "run", cfg]
    log(" ".join(cmd[5:]))
    r = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        fail(f"perclod run {cfg} exited {r.returncode}:\n{r.stderr[-2000:]}")
    wall, cpu, peak = open(timing).read().split()[-3:]
    stem = os.path.splitext(os.path.basename(model))[0]
    with open(os.path.join(work, "out-" + name, stem + "_report.json")) as f:
        lods = json.load(f)["lods"]
    shutil.rmtree(os.path.join(work, "out-" + name), ignore_errors=True)
    return (float(wall), float(cpu.rstrip("%")), int(peak) / 1024, sum(len(x["views"]) for x in lods),
            sum(judged_views(x) for x in lods))


def judged_views(lod):
    """How many views judged a LOD: its listed ones, but of buildings judged
    alone every view (the report lists each building's worst)."""
    alone = lod.get("judged_alone")
    if not alone:
        return len(lod["lod_vs_original"])
    return sum(1 for v in lod["lod_vs_original"] if "building" not in v) + alone["views"]


def timed_workdir(out, name):
    """A fresh scratch folder for a section that times perclod with /usr/bin/time."""
    if not os.access("/usr/bin/time", os.X_OK):
        fail("/usr/bin/time is missing (apt-get install time, or scripts/setup.sh)")
    work = out(name)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    return work


def run_scaling(a, out):
    work = timed_workdir(out, "scaling-work")
    sizes = [2000, 5000] if a.smoke else [10000, 30000, 100000, 300000, 1000000, 2000000]
    distances = [427] if a.smoke else [56, 132, 427]
    view_sets = ["facades"] if a.smoke else ["facades", "facades,obliques", "facades,ring8el30", "facades,ring8el30,top",
                                             DEFAULT_VIEWS, "facades,ring8el15/30/60,top"]
    rows = []
    models = {}
    for n in sizes:
        model = os.path.join(work, f"facade_{n}.obj")
        subprocess.run([a.bin("perclod"), "generate", "facade", "--triangles", str(n), model], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        info = json.loads(subprocess.run([a.bin("perclod"), "info", model, "--json"], check=True, capture_output=True,
                                         text=True).stdout)
        models[n] = (model, info["triangles"])
    for n in sizes:
        model, tris = models[n]
        wall, cpu, peak, nl, nj = timed_run(a, work, model, DEFAULT_VIEWS, distances, f"size{n}")
        rows.append({"kind": "triangles", "triangles": tris, "views": DEFAULT_VIEWS, "wall_s": wall,
                     "cpu_percent": cpu, "peak_mib": round(peak, 1), "labelling_views": nl, "judged_views": nj})
    model, tris = models[sizes[len(sizes) // 2]]
    for vs in view_sets:
        wall, cpu, peak, nl, nj = timed_run(a, work, model, vs, distances, "views")
        rows.append({"kind": "views", "triangles": tris, "views": vs, "wall_s": wall, "cpu_percent": cpu,
                     "peak_mib": round(peak, 1), "labelling_views": nl, "judged_views": nj})
    for m, _ in models.values():
        os.remove(m)
    shutil.rmtree(work, ignore_errors=True)
    with open(out("scaling.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


# ---- failure cases -------------------------------------------------------------


def write_obj(path, parts, offset=(0.0, 0.0, 0.0), soup=False):
    """parts: [(name, [(p0, p1, p2), ...])]. soup: every triangle its own vertices."""
    verts, faces, index = [], [], {}
    for name, tris in parts:
        faces.append(f"o {name}")
        for t in tris:
            ids = []
            for p in t:
                key = None if soup else p
                if key is None or key not in index:
                    verts.append(p)
                    if key is not None:
                        index[key] = len(verts)
                    ids.append(len(verts))
                else:
                    ids.append(index[key])
            faces.append("f %d %d %d" % tuple(ids))
    with open(path, "w") as f:
        for p in verts:
            f.write("v %.4f %.4f %.4f\n" % (p[0] + offset[0], p[1] + offset[1], p[2] + offset[2]))
        f.write("\n".join(faces) + "\n")


def box_tris(lo, hi):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    c = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1),
         (x0, y1, z1)]
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return [(c[q[0]], c[q[a]], c[q[a + 1]]) for q in quads for a in (1, 2)]


def facade_parts(width=20.0, height=10.0, depth=12.0, cols=10, rows=4, ornament=None):
    """A block with windows (frame boxes) on its +x face; ornament: cube edge in m for a grid of studs."""
    parts = [("body", box_tris((0, 0, 0), (depth, width, height)))]
    for r in range(rows):
        for c in range(cols):
            y0, z0 = 0.6 + c * width / cols, 0.8 + r * height / rows
            parts.append((f"win_{r}_{c}", box_tris((depth, y0, z0), (depth + 0.12, y0 + 1.0, z0 + 1.4))))
    if ornament:
        n_y, n_z = int(width / (4 * ornament)), int(height / (4 * ornament))
        tris = []
        for i in range(n_y):
            for j in range(n_z):
                y, z = (i + 0.5) * width / n_y, (j + 0.5) * height / n_z
                tris += box_tris((depth, y, z), (depth + ornament, y + ornament, z + ornament))
        parts.append(("ornaments", tris))
    return parts


def worst_held(lod, held):
    """The worst changed fraction, SSIM and silhouette of the held-out views;
    of buildings judged alone, the report's worst over all of them (it lists
    each building's worst visible view only)."""
    if lod.get("judged_alone"):
        w = lod["fidelity"]["worst"]
        return dict(worst_changed=round(w["changed_fraction"], 5), worst_ssim=round(w["ssim_covered"], 5),
                    worst_silhouette=round(w["silhouette_mismatch"], 5))
    return dict(worst_changed=round(max(j["changed_fraction"] for j in held), 5),
                worst_ssim=round(min(j["ssim_covered"] for j in held), 5),
                worst_silhouette=round(max(j["silhouette_mismatch"] for j in held), 5))


def run_case(a, work, name, stem, model, distances, views=DEFAULT_VIEWS, extra=""):
    """perclod run on `model` (files named after `stem`): one row per distance
    of what the report says, or one row with the error."""
    out_dir = os.path.join(work, "out-" + stem)
    cfg = os.path.join(work, stem + ".yaml")
    with open(cfg, "w") as f:
        f.write(f"model: {model}\nup: z\ndistances: [{', '.join(str(d) for d in distances)}]\nviews: {views}\n"
                f"samples: auto\ndebug_images: false\nout: {out_dir}\n{extra}")
    timing = os.path.join(work, "time.txt")
    t0 = time.time()
    r = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", timing, a.bin("perclod"), "run", cfg], capture_output=True,
                       text=True)
    row = {"case": name, "exit": r.returncode, "seconds": round(time.time() - t0, 1),
           "peak_mib": round(int(open(timing).read().split()[-1]) / 1024)}
    if r.returncode != 0:
        row["error"] = r.stderr.strip().splitlines()[-1][:200] if r.stderr.strip() else ""
        return [row]
    stem = os.path.splitext(os.path.basename(model))[0]
    with open(os.path.join(out_dir, stem + "_report.json")) as f:
        rep = json.load(f)
    rows = []
    for lod in rep["lods"]:
        judged = lod["lod_vs_original"]
        held = [j for j in judged if j.get("set") == "held_out"] or judged
        agree = [v["octree_vs_embree"]["real_disagreements"] for v in lod["views"] if "octree_vs_embree" in v]
        rows.append(dict(row, distance=lod["distance"], triangles=rep["triangles"],
                         perceptible=lod["labels"]["perceptible"], imperceptible=lod["labels"]["imperceptible"],
                         undisplayable=lod["labels"]["undisplayable"], outside_views=lod["outside_views"],
                         labelling_views=len(lod["views"]),
                         # none when each building's own views alone made the labels
                         min_covered_px=min((v["covered_pixels"] for v in lod["views"]), default=""),
                         lod_triangles=lod["simplify"]["triangles_after"]["total"],
                         **worst_held(lod, held),
                         real_disagreements=sum(agree) if agree else "",
                         eyes_inside_others=sum(b.get("eyes_inside_other_buildings", 0)
                                                for b in lod.get("per_building", [])),
                         warnings=len(rep.get("warnings", []))))
    shutil.rmtree(out_dir, ignore_errors=True)
    return rows


def run_failures(a, out):
    work = timed_workdir(out, "failures-work")
    demo = os.path.join(ROOT, "data/ingolstadt/bldg_4018215.obj")
    demo_parts = read_obj_parts(demo)
    d = [427] if a.smoke else [56, 132, 427]
    # The smoke labels from the four facades (and a case's own extra views).
    base_views = "facades" if a.smoke else DEFAULT_VIEWS
    cases = []  # (name, parts or path, distances, views, extra, writer options)
    facade = facade_parts()
    dup = facade + [("dup_" + n, t) for n, t in facade if n.startswith("win")]
    cases.append(("reference facade", facade, d, base_views, "", {}))
    cases.append(("coplanar duplicates", dup, d, base_views, "", {}))
    cases.append(("+ views at 85 degrees, verify", facade, d, base_views + ",az85el0,az95el0", "verify: true\n", {}))
    cases.append(("demo building", demo_parts, d, base_views, "", {}))
    cases.append(("demo at UTM 500 km / 5400 km", demo_parts, d, base_views, "",
                  {"offset": (500000.0, 5400000.0, 300.0)}))
    cases.append(("demo as a triangle soup", demo_parts, d, base_views, "", {"soup": True}))
    cases.append(("single-pixel ornaments", facade_parts(ornament=0.1), [132, 427] if not a.smoke else [427],
                  base_views, "", {}))
    kiosk = [("kiosk", box_tris((0, 0, 0), (2, 2, 3))), ("roof", box_tris((-0.2, -0.2, 3), (2.2, 2.2, 3.15)))]
    cases.append(("under 500 pixels", kiosk, [427], base_views, "", {}))
    # Per building, a small building's views at 56 m stand inside its big
    # neighbour (a hall 36 m away): those views see the hall from inside.
    neighbours = [("kiosk", box_tris((0, 0, 0), (4, 4, 4))), ("hall", box_tris((40, -30, 0), (120, 30, 40)))]
    cases.append(("eye inside a neighbour (per building)", neighbours, [427] if a.smoke else [56], base_views,
                  "per_building: true\n", {}))
    if not a.smoke:
        cases.append(("eye 1 m from the model", facade, [1], "facades", "judge_views: none\n", {}))
    smoke_display = os.path.join(work, "quarter.yaml")  # the paper's display at a quarter of its resolution
    with open(smoke_display, "w") as f:
        f.write("name: paper-19in-quarter\nwidth: 320\nheight: 256\ndpi: 21.5675\nviewer_distance_m: 0.5\n")
    rows = []
    for i, (name, parts, dists, views, extra, opts) in enumerate(cases):
        if a.smoke:  # a quarter of the display, as the other smoke runs (SMOKE_FIDELITY)
            extra += f"display: {smoke_display}\n"
        model = os.path.join(work, f"case{i}.obj")
        write_obj(model, parts, **opts)
        log(f"failure case: {name}")
        rows += run_case(a, work, name, f"case{i}", model, dists, views, extra)
    shutil.rmtree(work, ignore_errors=True)
    keys = list(dict.fromkeys(k for r in rows for k in r))
    with open(out("failures.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)


def read_obj_parts(path):
    """A triangulated OBJ's triangles grouped by `o`/`g` name, in file order: for the failure cases."""
    vertices, groups, order = read_obj(path)
    return [(name, [tuple(vertices[c] for c in face) for face in groups[name]]) for name in order if groups[name]]


# ---- charts --------------------------------------------------------------------

def save(fig, path, dpi, rect=None):
    """Lays out (tight, within `rect`), writes and closes `fig`; returns `path`."""
    fig.tight_layout(rect=rect)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path


TRACER_STYLE = {"octree": ("perclod octree", "C0"), "embree_intersect1": ("Embree rtcIntersect1", "C1"),
                "embree_intersect16": ("Embree rtcIntersect16", "C2"), "embree_verify": ("Embree verify", "C3"),
                "osmesa_id_buffer": ("OSMesa ID buffer", "C4")}


def chart_tracers(rows, path):
    rows = [r for r in rows if r["scene"].startswith("facade_") and r["view"] == "fills"]
    if not rows:
        return None
    fig, ax = plt.subplots(figsize=(10, 5))
    for tracer, (label, color) in TRACER_STYLE.items():
        for threads, ls in (("1", "--"), ("2", "-"), ("0", "-")):
            pts = sorted((int(r["triangles"]), float(r["mrays"])) for r in rows
                         if r["tracer"] == tracer and r["threads"] == threads)
            if not pts:
                continue
            suffix = "" if threads == "0" else f", {threads} thread{'s' if threads == '2' else ''}"
            ax.plot([p[0] for p in pts], [p[1] for p in pts], ls, marker="o", color=color, label=label + suffix)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangles (generated facade)")
    ax.set_ylabel("Mrays/s (1280x1024 primary rays, view filling the width)")
    ax.set_title("Primary-ray throughput")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    return save(fig, path, 110)


METHOD_STYLE = [  # prefix, label, colour, marker
    ("fidelity floor search", "perclod fidelity_target: {} (the floor search)", "C9", "*"),
    ("fidelity", "perclod fidelity (e_I sweep)", "C0", "o"),
    ("paper", "perclod paper", "C3", "s"),
    ("bounded", "perclod bounded k=1", "C2", "^"),
    ("cluster", "perclod cluster k=1", "C5", "v"),
    ("qem", "plain qem", "C7", "x"),
    ("decimater", "OpenMesh Decimater", "C8", "+"),
    ("meshopt", "meshoptimizer (count and error sweeps)", "C1", "."),
    ("culled meshopt", "meshoptimizer after a visibility cull (81 views at 2x)", "C4", "d"),
]


def method_family(method):
    for prefix, label, color, marker in METHOD_STYLE:
        if method.startswith(prefix):
            return prefix, label, color, marker
    return None


def fidelity_points(rows):
    """(model, distance) -> family -> [(triangles, worst SSIM, worst changed, seconds, worst visible ratio)]."""
    out = {}
    for r in rows:
        fam = method_family(r["method"])
        if not fam or not r["held_ssim"]:
            continue
        key = (r["model"], float(r["distance"]))
        ssim = min(float(r["lab_ssim"]), float(r["held_ssim"]))
        changed = max(float(r["lab_changed"]), float(r["held_changed"]))
        visible = float(r["visible_worst"]) if r.get("visible_worst") else float("nan")
        out.setdefault(key, {}).setdefault(fam[0], []).append(
            (int(r["triangles"]), ssim, changed, float(r["seconds"] or 0), visible))
    return out


def envelope(points, higher_better=True):
    """The fewest triangles reaching each fidelity: the lower-right envelope."""
    best, out = None, []
    for t, f in sorted(points):
        if best is None or (f > best if higher_better else f < best):
            best = f
            out.append((t, f))
    return out


def chart_fidelity(rows, path, measure):
    pts = fidelity_points(rows)
    if not pts:
        return None
    models = sorted({k[0] for k in pts}, key=lambda m: ["demo", "han", "sibenik", "sponza", "block", "facade"].index(m)
                    if m in ["demo", "han", "sibenik", "sponza", "block", "facade"] else 99)
    dists = sorted({k[1] for k in pts})
    fig, axes = plt.subplots(len(models), len(dists), figsize=(4.2 * len(dists), 3.3 * len(models)), squeeze=False)
    idx = {"ssim": 1, "changed": 2, "visible": 4}[measure]
    for i, m in enumerate(models):
        for j, d in enumerate(dists):
            ax = axes[i][j]
            for prefix, label, color, marker in METHOD_STYLE:
                p = pts.get((m, d), {}).get(prefix, [])
                if not p:
                    continue
                xy = [(q[0], q[idx]) for q in p if not math.isnan(q[idx])]
                ax.scatter([q[0] for q in xy], [q[1] for q in xy], color=color, marker=marker, s=18, label=label,
                           zorder=3)
                if prefix in ("fidelity", "meshopt", "culled meshopt") and xy:
                    env = envelope(xy, higher_better=(measure == "ssim"))
                    ax.plot([q[0] for q in env], [q[1] for q in env], color=color, lw=1)
            ax.set_xscale("log")
            if measure == "changed":
                ax.set_yscale("symlog", linthresh=0.01)
                ax.axhline(0.02, color="k", lw=0.6, ls=":")
            if measure == "visible":  # the quarter-pixel floor
                ax.set_yscale("log")
                ax.axhline(1.0, color="k", lw=0.8, ls="--")
            ax.set_title(f"{m}, {d:g} m", fontsize=9)
            ax.grid(True, which="both", alpha=0.3)
            if i == len(models) - 1:
                ax.set_xlabel("triangles")
            if j == 0:
                ax.set_ylabel({"ssim": "worst-view covered SSIM", "changed": "worst-view changed fraction",
                               "visible": "worst visible ratio (floor = 1)"}[measure])
    handles, labels = axes[0][0].get_legend_handles_labels()
    for row in axes:
        for ax in row:
            for h, lab in zip(*ax.get_legend_handles_labels()):
                if lab not in labels:
                    handles.append(h)
                    labels.append(lab)
    ncol = 3 if len(dists) >= 3 else 1
    fig.legend(handles, labels, loc="lower center", ncol=ncol, fontsize=8)
    rows_of_legend = math.ceil(len(labels) / ncol)
    return save(fig, path, 90, rect=(0, min(0.5, 0.25 * rows_of_legend / (3.3 * len(models))), 1, 1))


def chart_fidelity_time(rows, path):
    pts = fidelity_points(rows)
    if not pts:
        return None
    fig, ax = plt.subplots(figsize=(7.5, 5))
    seen = set()
    for (m, d), fams in sorted(pts.items()):
        for prefix, label, color, marker in METHOD_STYLE:
            for t, ssim, _, sec, _visible in fams.get(prefix, []):
                ax.scatter(max(sec, 1e-4), ssim, color=color, marker=marker, s=16,
                           label=None if prefix in seen else label)
                seen.add(prefix)
    ax.set_xscale("log")
    ax.set_xlabel("simplification time, s (one thread; every model and distance)")
    ax.set_ylabel("worst-view covered SSIM")
    ax.set_title("Fidelity against simplification time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    return save(fig, path, 110)


def chart_sweeps(rows, path):
    if not rows:
        return None
    dists = sorted({float(r["distance"]) for r in rows})
    fig, axes = plt.subplots(1, 2, figsize=(13, 5))
    markers = "os^vDPX*<>ph+x1234"
    settings = list(dict.fromkeys(r["setting"] for r in rows))
    for k, name in enumerate(settings):
        pts = [r for r in rows if r["setting"] == name]
        for ax, xkey, xlab in ((axes[0], "triangles", "LOD triangles (default fidelity LOD)"),
                               (axes[1], "label_seconds", "labelling time, s (all views of one distance)")):
            ax.scatter([float(r[xkey]) for r in pts],
                       [min(float(r["lab_ssim"]), float(r["held_ssim"])) for r in pts],
                       marker=markers[k % len(markers)], s=30, label=name,
                       color=plt.cm.tab20(k % 20))
            ax.set_xlabel(xlab)
    for ax in axes:
        ax.set_xscale("log")
        ax.set_ylabel("worst-view covered SSIM")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_title(f"Settings one at a time (demo; {', '.join(f'{d:g}' for d in dists)} m)", fontsize=10)
    axes[1].legend(fontsize=7, ncol=2)
    return save(fig, path, 100)


def fit_exponent(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((x - mx) ** 2 for x in lx)
    return sum((x - mx) * (y - my) for x, y in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def chart_scaling(rows, path):
    tri = sorted((int(r["triangles"]), float(r["wall_s"]), float(r["peak_mib"]), float(r["cpu_percent"]))
                 for r in rows if r["kind"] == "triangles")
    views = [r for r in rows if r["kind"] == "views"]
    if len(tri) < 2:
        return None, {}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    xs = [t[0] for t in tri]
    k_time, k_mem = fit_exponent(xs, [t[1] for t in tri]), fit_exponent(xs, [t[2] for t in tri])
    ax = axes[0]
    ax.plot(xs, [t[1] for t in tri], "o-", color="C0", label=f"wall time (fitted exponent {k_time:.2f})")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangles (generated facade)")
    ax.set_ylabel("wall s")
    ax2 = ax.twinx()
    ax2.plot(xs, [t[2] for t in tri], "s--", color="C1", label=f"peak memory (fitted exponent {k_mem:.2f})")
    ax2.set_yscale("log")
    ax2.set_ylabel("peak MiB")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=8, loc="upper left")
    size_views = next(r["views"] for r in rows if r["kind"] == "triangles")
    ax.set_title(f"perclod run against input size ({view_count(size_views)} views per distance)")
    ax.grid(True, which="both", alpha=0.3)
    ax = axes[1]
    if views:
        counts = [view_count(v["views"]) for v in views]
        ax.plot(counts, [float(v["wall_s"]) for v in views], "o-", color="C0")
        for c, v in zip(counts, views):
            ax.annotate(v["views"], (c, float(v["wall_s"])), fontsize=6, rotation=20)
        ax.set_xlabel("labelling views per distance (before tiling)")
        ax.set_ylabel("wall s")
        ax.set_title(f"perclod run against the view set ({views[0]['triangles']} triangles)")
        ax.grid(True, alpha=0.3)
    return save(fig, path, 110), {"time": k_time, "memory": k_mem}


def view_count(spec):
    n = 0
    for part in spec.split(","):
        if part == "facades" or part == "obliques":
            n += 4
        elif part == "top":
            n += 1
        elif part.startswith("ring"):
            body = part[4:]
            if "el" in body:
                az, els = body.split("el", 1)
                n += int(az) * len(els.split("/"))
            else:
                n += int(body) * 3
        else:
            n += 1
    return n


def chart_stability(rows, path):
    if not rows:
        return None
    fig, axes = plt.subplots(1, 2, figsize=(14, 4.8), gridspec_kw={"width_ratios": [1, 1.6]})
    shift = [r for r in rows if r.get("perturb", "shift") == "shift"]
    ax = axes[0]
    classes = [("lt1px", "< 1 px"), ("1_10px", "1-10 px"), ("10_100px", "10-100 px"), ("ge100px", ">= 100 px")]
    width = 0.8 / len(classes)
    for k, (key, name) in enumerate(classes):
        ax.bar([i + (k - 1.5) * width for i in range(len(shift))], [float(r["flip_" + key]) for r in shift], width,
               label=f"triangles {name}")
    ax.set_xticks(range(len(shift)))
    ax.set_xticklabels([f"{r['model']} {float(r['distance']):g} m" for r in shift], rotation=35, fontsize=7)
    ax.set_ylabel("% of visible triangles whose label flips")
    ax.set_title("+-0.25 px shift: flips by projected triangle size", fontsize=10)
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=7)
    ax = axes[1]
    x = range(len(rows))
    pi = [float(r["flip_pi_weighted"]) for r in rows]
    vu = [float(r["flip_vu_weighted"]) for r in rows]
    ax.bar(x, pi, label="perceptible <-> imperceptible", color="C3")
    ax.bar(x, vu, bottom=pi, label="visible <-> undisplayable", color="C0")
    ax.axhline(2, color="k", lw=0.6, ls=":", label="target for the 0.25 px shift (2%)")
    ax.set_xticks(list(x))
    ax.set_xticklabels([f"{r['model']} {float(r['distance']):g} m, {r.get('perturb', 'shift')}" for r in rows],
                       rotation=60, fontsize=6, ha="right")
    ax.set_ylabel("% of traced samples on flipped triangles")
    ax.set_title("Flips weighted by traced samples, every perturbation", fontsize=10)
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=7)
    return save(fig, path, 110)


# ---- summary ---------------------------------------------------------------------


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def worst_cells(r):
    """A bench_fidelity row's worst view over its labelling and held-out sets:
    changed, SSIM, silhouette, as table cells."""
    return [f"{100 * max(float(r['lab_changed']), float(r['held_changed'])):.2f}%",
            f"{min(float(r['lab_ssim']), float(r['held_ssim'])):.4f}",
            f"{100 * max(float(r['lab_silhouette']), float(r['held_silhouette'])):.2f}%"]


def summarize(out, charts, exponents):
    # The machine the run measured on (machine.json, written when the run
    # started), not the one redrawing the charts (--charts-only).
    ran_on = machine()
    if os.path.exists(out("machine.json")):
        with open(out("machine.json")) as f:
            ran_on = json.load(f)
    parts = [f"# Benchmark summary\n\nMachine: `{json.dumps(ran_on)}`\n"]
    tr = read_csv(out("tracers.csv"))
    if tr:
        by = {}
        for r in tr:
            by[(r["scene"], r["triangles"], r["view"], r["threads"], r["tracer"])] = float(r["mrays"])
        rows = []
        for (scene, tris, view, threads, tracer), v in sorted(by.items(), key=lambda kv: (int(kv[0][1]), kv[0][2])):
            if tracer != "octree":
                continue
            e16 = by.get((scene, tris, view, threads, "embree_intersect16"))
            e1 = by.get((scene, tris, view, threads, "embree_intersect1"))
            idb = by.get((scene, tris, view, "0", "osmesa_id_buffer"))
            rows.append([scene, tris, view, threads, f"{v:.2f}", f"{e1:.2f}", f"{e16:.2f}",
                         f"{idb:.2f}" if idb else "", f"{v / e16:.2f}"])
        parts.append("## Tracers (Mrays/s)\n\n" + md_table(
            ["scene", "triangles", "view", "threads", "octree", "rtcIntersect1", "rtcIntersect16", "ID buffer",
             "octree / rtcIntersect16"], rows))
    fid = read_csv(out("fidelity.csv"))
    same = [r for r in fid if r["method"].startswith("same_ssim")]
    if same:
        rows = []
        for r in same:
            note = r["note"].split()
            rows.append([r["model"], r["distance"], r["method"].split()[1], r["triangles"], r["lab_ssim"], note[1],
                         note[3]])
        parts.append("## Triangles at equal worst-view SSIM: fidelity / meshoptimizer\n\n" + md_table(
            ["model", "d m", "setting", "fidelity tris", "worst SSIM", "meshopt tris (envelope)", "ratio"], rows))
    equal = [r for r in fid if r["method"].startswith("equal_")]
    if equal:
        rows = []
        for r in equal:
            what, peer, setting = r["method"].split()
            note = r["note"].split()
            rows.append([r["model"], r["distance"], what[len("equal_"):], peer, setting, r["triangles"], r["lab_ssim"],
                         note[1], note[3]])
        parts.append("## Triangles at equal fidelity beside each peer (worst view; visible: the judge's ratio, "
                     "floor = 1)\n\n" + md_table(
                         ["model", "d m", "measure", "peer", "setting", "perclod tris", "figure", "peer tris (envelope)",
                          "ratio"], rows))
    if fid:
        rows = [[r["model"], r["distance"], r["method"], r["triangles"], r["seconds"],
                 *worst_cells(r),
                 f"{100 * float(r['hausdorff_rel']):.3f}%", r["note"]]
                for r in fid if not r["method"].startswith(("same_ssim", "equal_", "meshopt sweep", "meshopt error",
                                                            "culled meshopt sweep"))]
        parts.append("## Every LOD (worst view of labelling and held-out sets)\n\n" + md_table(
            ["model", "d m", "method", "triangles", "simplify s", "changed", "SSIM", "silhouette", "Hausdorff/diag",
             "note"], rows))
    ba = read_csv(out("butteraugli.csv"))
    if ba:
        parts.append("## butteraugli, held-out view az22.5el45 (lower is closer; ~1 is a just-noticeable change)\n\n"
                     + md_table(["model", "d m", "LOD", "butteraugli"],
                                [[r["model"], r["distance"], r["method"], r["butteraugli"]] for r in ba]))
    st = read_csv(out("simplify_time.csv"))
    if st:
        parts.append("## Simplification time and memory (bench_simplify, medians)\n\n" + md_table(
            ["model", "input", "method", "s", "CPU s", "triangles", "peak MB"],
            [[r["model"], r["input_triangles"], r["method"], r["seconds"], r.get("cpu_seconds", ""), r["triangles"],
              r["peak_mb"]] for r in st]))
    sw = read_csv(out("sweeps.csv"))
    if sw:
        parts.append("## Settings of the perceptual pipeline, one at a time (demo, default fidelity LOD)\n\n" + md_table(
            ["setting", "d m", "label s", "triangles", "worst changed", "worst SSIM", "worst silhouette"],
            [[r["setting"], r["distance"], r["label_seconds"], r["triangles"],
              *worst_cells(r)] for r in sw]))
    sb = read_csv(out("stability.csv"))
    if sb:
        parts.append("## Label stability (% of visible triangles)\n\n" + md_table(
            ["model", "perturbation", "d m", "views", "spp", "visible", "P<->I count", "vis<->U count", "P<->I weighted",
             "vis<->U weighted", "<1 px", "1-10 px", "10-100 px", ">=100 px"],
            [[r["model"], r.get("perturb", "shift"), r["distance"], r["views"], r["samples"], r["visible"], r["flip_pi_count"],
              r["flip_vu_count"], r["flip_pi_weighted"], r["flip_vu_weighted"], r["flip_lt1px"], r["flip_1_10px"],
              r["flip_10_100px"], r["flip_ge100px"]] for r in sb]))
    sl = [r for r in read_csv(out("stability_lod.csv")) if " (labels " in r["method"]]
    if sl:
        parts.append("## What label flips change in the LOD (labels of the model moved by -1/4, 0, +1/4 px)\n\n" +
                     md_table(["model", "d m", "LOD, labels", "triangles", "worst changed", "worst SSIM",
                               "worst silhouette"],
                              [[r["model"], r["distance"], r["method"], r["triangles"], *worst_cells(r)]
                               for r in sl]))
    sc = read_csv(out("scaling.csv"))
    if sc:
        parts.append("## perclod run scaling\n\n" + md_table(
            ["kind", "triangles", "views", "labelling views (all distances, tiles)", "judged views", "wall s",
             "CPU %", "peak MiB"],
            [[r["kind"], r["triangles"], r["views"], r.get("labelling_views", ""), r.get("judged_views", ""),
              r["wall_s"], r["cpu_percent"], r["peak_mib"]] for r in sc]))
        if exponents:
            parts.append(f"Fitted exponents (log-log least squares over the size rows): wall time "
                         f"{exponents['time']:.2f}, peak memory {exponents['memory']:.2f}.")
    fc = read_csv(out("failures.csv"))
    if fc:
        cols = ["case", "exit", "distance", "triangles", "perceptible", "imperceptible", "undisplayable",
                "outside_views", "labelling_views", "min_covered_px", "lod_triangles", "worst_changed", "worst_ssim",
                "worst_silhouette", "real_disagreements", "warnings", "seconds", "peak_mib", "error"]
        cols = [c for c in cols if c in fc[0]]
        parts.append("## Failure cases (perclod run, samples auto; worst held-out view)\n\n" + md_table(
            cols, [[r.get(c, "") for c in cols] for r in fc]))
    parts.append("## Charts\n\n" + "\n".join(f"- `{os.path.basename(c)}`" for c in charts if c))
    with open(out("summary.md"), "w") as f:
        f.write("\n\n".join(parts) + "\n")


def charts(out):
    made = [chart_tracers(read_csv(out("tracers.csv")), out("tracers.png"))]
    fid = read_csv(out("fidelity.csv"))
    made.append(chart_fidelity(fid, out("fidelity_ssim.png"), "ssim"))
    made.append(chart_fidelity(fid, out("fidelity_changed.png"), "changed"))
    made.append(chart_fidelity(fid, out("fidelity_visible.png"), "visible"))
    made.append(chart_fidelity_time(fid, out("fidelity_time.png")))
    made.append(chart_sweeps(read_csv(out("sweeps.csv")), out("sweeps.png")))
    path, exponents = chart_scaling(read_csv(out("scaling.csv")), out("scaling.png"))
    made.append(path)
    made.append(chart_stability(read_csv(out("stability.csv")), out("stability.png")))
    summarize(out, made, exponents)
    return [m for m in made if m]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=os.path.join(ROOT, "bench-results"), help="output folder (default bench-results/)")
    p.add_argument("--sections", default=",".join(SECTIONS), help="comma-separated: " + ", ".join(SECTIONS))
    p.add_argument("--build", default=os.path.join(ROOT, "build"), help="build folder (default build/)")
    p.add_argument("--smoke", action="store_true", help="tiny inputs: checks the machinery, not the figures")
    p.add_argument("--charts-only", action="store_true", help="redraw charts and summary from DIR's CSVs")
    a = p.parse_args()
    sections = [s for s in a.sections.split(",") if s]
    for s in sections:
        if s not in SECTIONS:
            p.error(f"unknown section '{s}' (one of {', '.join(SECTIONS)})")

    def binary(name):
        for sub in ("tests", "."):
            path = os.path.join(a.build, sub, name)
            if os.access(path, os.X_OK):
                return path
        fail(f"{name} not found under {a.build}: build first (scripts/setup.sh; PERCLOD_BUILD_BENCH=ON)")

    a.bin = binary
    a.out = os.path.abspath(a.out)
    os.makedirs(a.out, exist_ok=True)

    def out(name):
        return os.path.join(a.out, name)

    if not a.charts_only:
        with open(out("machine.json"), "w") as f:
            json.dump(machine(), f, indent=2)
        for s in sections:
            t0 = time.time()
            globals()["run_" + s](a, out)
            log(f"section {s}: {time.time() - t0:.0f} s")
    made = charts(out)
    log(f"charts: {', '.join(os.path.basename(m) for m in made)}; summary: {out('summary.md')}")
    if a.smoke:  # every section asked for produced rows and its chart
        expect = {"tracers": ["tracers.csv", "tracers.png"],
                  "simplifiers": ["fidelity.csv", "simplify_time.csv", "butteraugli.csv", "fidelity_ssim.png", "fidelity_visible.png",
                                  "fidelity_time.png"],
                  "sweeps": ["sweeps.csv", "sweeps.png"], "failures": ["failures.csv"],
                  "stability": ["stability.csv", "stability_lod.csv", "stability.png"], "scaling": ["scaling.csv", "scaling.png"]}
        for s in sections:
            for name in expect[s]:
                path = out(name)
                if not os.path.exists(path) or os.path.getsize(path) == 0:
                    fail(f"smoke: {name} was not written")
                if name.endswith(".csv") and len(read_csv(path)) == 0:
                    fail(f"smoke: {name} has no rows")
        # Every failure case runs at the smoke's sizes: an error there is the
        # machinery's (a config key, a writer), not a case's finding.
        if "failures" in sections:
            for r in read_csv(out("failures.csv")):
                if r["exit"] != "0":
                    fail(f"smoke: failure case '{r['case']}' exited {r['exit']}: {r.get('error', '')}")
        log("smoke: every section wrote rows and charts")


if __name__ == "__main__":
    main()
