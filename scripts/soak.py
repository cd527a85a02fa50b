#!/usr/bin/env python3
"""Soak test of batch runs killed at random moments (issue 56; not in CI).

    scripts/soak.py [--kills 50] [--full] [--seed 1] [--work DIR] [--keep]

Runs a batch once without interruption (the reference), then again and again
in a second folder, each run killed with SIGKILL at a random moment (half of
the runs with --force, so whole folders are being replaced when they die),
until it has been killed --kills times; then once more to the end. Checks:

  - after every kill: each model folder under its final name is whole (its
    manifest `complete`, every file it lists present, every file in the
    folder matching the checksum the manifest records for it, the input and settings
    hashes it records matching the model file and the reference) and equal to
    the reference's folder, and the batch's own files that exist parse;
  - at the end: the last run exits 0, no partial folder or temporary is left,
    and every output is byte-identical to the reference's, except the
    timings in the JSON reports and the HTML pages (compared without them).

The batch (default): the demo building and sibenik at 56 and 427 m, and
the Delft CityJSON tile at 427 m, with per_building: false, views: facades,
judge_views: none, debug_images: false; --full takes every model in
../shared/data at 56 and 427 m (many minutes a run). PERCLOD names the binary (default
build/perclod). Prints one line per run and a summary; exits 1 on any
failed check.
"""
import argparse
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.normpath(os.path.join(ROOT, "..", "shared", "data"))
PERCLOD = os.environ.get("PERCLOD", os.path.join(ROOT, "build", "perclod"))
# Keys whose values are measured times: left out when JSON files are compared.
TIMING_KEYS = {"seconds", "timings", "tracer_build_seconds"}
# The manifest's checksums hold the reports' hashes, which differ with their
# timings: checked against the files, not against the reference.
UNCOMPARED_KEYS = TIMING_KEYS | {"checksums"}


def batch_config(full):
    """The batch config text (out: out, relative to the folder it runs in)."""
    lines = ["# Written by scripts/soak.py", "distances: [56, 427]", "views: facades", "samples: 1",
             "per_building: false", "judge_views: none", "debug_images: false", "out: out", "models:"]
    if full:
        for folder in sorted(f for f in os.listdir(DATA) if os.path.isdir(os.path.join(DATA, f))):
            for name in sorted(os.listdir(os.path.join(DATA, folder))):
                if name.endswith(".obj") or name.endswith(".city.json"):
                    up = "z" if folder in ("ingolstadt", "cityjson") else "y"
                    lines.append("  - {model: %s, up: %s}" % (os.path.join(DATA, folder, name), up))
    else:
        lines.append("  - {model: %s/ingolstadt/bldg_4018215.obj, up: z}" % DATA)
        lines.append("  - {model: %s/sibenik/sibenik.obj, up: y}" % DATA)
        # At 56 m the 650 m tile takes 132 tiled views (9 minutes under load), at 427 m 12.
        lines.append("  - {model: %s/cityjson/3dbag_5910_delft.city.json, up: z, distances: [427]}" % DATA)
    return "\n".join(lines) + "\n"


_hashes = {}


def fnv1a64(path):
    """perclod's hash_file: "fnv1a64:<hex>" of the file's bytes (cached by size and mtime)."""
    st = os.stat(path)
    key = (path, st.st_size, st.st_mtime_ns, st.st_ino)
    if key not in _hashes:
        _hashes[key] = _fnv1a64(path)
    return _hashes[key]


def _fnv1a64(path):
    h = 14695981039346656037
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            for b in chunk:
                h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return "fnv1a64:%016x" % h


def without_timings(j):
    if isinstance(j, dict):
        return {k: without_timings(v) for k, v in j.items()
                if k not in UNCOMPARED_KEYS and not k.endswith("_seconds") and not k.startswith("seconds_")}
    if isinstance(j, list):
        return [without_timings(v) for v in j]
    return j


def comparable(path):
    """A file's content for comparing runs: JSON without timings, HTML without numbers (its timings)."""
    if path.endswith(".json"):
        with open(path, encoding="utf-8") as f:
            return without_timings(json.load(f))
    if path.endswith(".html"):
        with open(path, encoding="utf-8") as f:
            return re.sub(r"[0-9][0-9.e+-]*", "#", f.read())
    with open(path, "rb") as f:
        return f.read()


def folder_problems(folder, ref_folder, input_hashes):
    """What is wrong with a model folder under its final name (a list of strings)."""
    name = os.path.basename(folder)
    manifests = [f for f in os.listdir(folder) if f.endswith("_manifest.json")]
    if len(manifests) != 1:
        return ["%s: %d manifests" % (name, len(manifests))]
    problems = []
    with open(os.path.join(folder, manifests[0]), encoding="utf-8") as f:
        m = json.load(f)
    if m.get("complete") is not True:
        problems.append("%s: manifest not complete" % name)
    listed = list(m.get("files", {}).values())
    for lod in m.get("lods", []):
        listed += [lod.get("file"), lod.get("glb")]
    sums = m.get("checksums", {})
    for f in listed:
        if f and not os.path.isfile(os.path.join(folder, f)):
            problems.append("%s: listed file %s missing" % (name, f))
        elif f and f not in sums:
            problems.append("%s: listed file %s has no checksum" % (name, f))
    for f, h in sorted(sums.items()):
        p = os.path.join(folder, f)
        if not os.path.isfile(p):
            problems.append("%s: checksummed file %s missing" % (name, f))
        elif fnv1a64(p) != h:
            problems.append("%s: %s does not match its checksum" % (name, f))
    unlisted = {f for f in os.listdir(folder) if not f.startswith(".")} - set(sums) - set(manifests)
    if unlisted:
        problems.append("%s: files without a checksum: %s" % (name, " ".join(sorted(unlisted))))
    model_file = m.get("model", {}).get("file", "")
    if input_hashes.get(model_file) != m.get("model", {}).get("hash"):
        problems.append("%s: model hash %s is not the input's" % (name, m.get("model", {}).get("hash")))
    problems += differences(folder, ref_folder)
    return problems


def differences(folder, ref_folder):
    """Files of `folder` that differ from, or are missing in, `ref_folder` (and the reverse)."""
    mine = {f for f in os.listdir(folder) if not f.startswith(".")}
    theirs = {f for f in os.listdir(ref_folder) if not f.startswith(".")}
    out = ["%s: %s only in one run" % (os.path.basename(folder), f) for f in sorted(mine ^ theirs)]
    for f in sorted(mine & theirs):
        a, b = os.path.join(folder, f), os.path.join(ref_folder, f)
        if os.path.isdir(a) or comparable(a) != comparable(b):
            out.append("%s: %s differs from the uninterrupted run" % (os.path.basename(folder), f))
    return out


def check_after_kill(out, ref_out, input_hashes):
    problems, whole = [], 0
    for e in sorted(os.listdir(out)):
        p = os.path.join(out, e)
        if e.startswith("."):
            continue
        if os.path.isdir(p):
            problems += folder_problems(p, os.path.join(ref_out, e), input_hashes)
            whole += 1
        elif e.endswith(".json"):
            try:
                json.load(open(p, encoding="utf-8"))
            except ValueError as err:
                problems.append("%s: not whole JSON (%s)" % (e, err))
    return problems, whole


def check_final(out, ref_out, input_hashes, models):
    problems, _ = check_after_kill(out, ref_out, input_hashes)
    for dirpath, dirs, files in os.walk(out):
        for n in dirs + files:
            if ".partial-" in n or n.startswith(".tmp-"):
                problems.append("left behind: %s" % os.path.relpath(os.path.join(dirpath, n), out))
    # The batch's own files: the tileset as the reference's; the summary (whose
    # models were skipped, not done) lists every model and no failure.
    for p in differences(out, ref_out):
        if "tileset.json" in p.split(": ")[1] or "only in one run" in p:
            problems.append("top level: " + p)
    summary = json.load(open(os.path.join(out, "batch_0_of_1.json"), encoding="utf-8"))
    statuses = {m["name"]: m["status"] for m in summary["models"]}
    if sorted(statuses) != models or set(statuses.values()) - {"done", "skipped"}:
        problems.append("summary: %s" % statuses)
    return problems


def run(args, cwd, log):
    with open(log, "w") as f:
        return subprocess.Popen([PERCLOD, "run"] + args, cwd=cwd, stdout=f, stderr=subprocess.STDOUT)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--kills", type=int, default=50)
    ap.add_argument("--full", action="store_true", help="every model in ../shared/data")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--work", help="working folder (default: a new one in /tmp)")
    ap.add_argument("--keep", action="store_true", help="keep the working folder")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    work = a.work or tempfile.mkdtemp(prefix="perclod-soak-")
    os.makedirs(work, exist_ok=True)
    config = os.path.join(work, "batch.yaml")
    with open(config, "w") as f:
        f.write(batch_config(a.full))
    ref, soak = os.path.join(work, "ref"), os.path.join(work, "soak")
    for d in (ref, soak):
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
    print("soak: %s, work %s, seed %d" % (PERCLOD, work, a.seed), flush=True)

    t0 = time.time()
    rc = run([config], ref, os.path.join(work, "ref.log")).wait()
    full_time = time.time() - t0
    if rc != 0:
        sys.exit("soak: the reference run failed (exit %d, %s/ref.log)" % (rc, work))
    ref_out = os.path.join(ref, "out")
    models = sorted(e for e in os.listdir(ref_out) if os.path.isdir(os.path.join(ref_out, e)) and e[0] != ".")
    input_hashes = {}
    for e in models:
        man = [f for f in os.listdir(os.path.join(ref_out, e)) if f.endswith("_manifest.json")][0]
        model_file = json.load(open(os.path.join(ref_out, e, man)))["model"]["file"]
        input_hashes[model_file] = fnv1a64(model_file)
    print("soak: reference run %.0f s, %d models: %s" % (full_time, len(models), " ".join(models)), flush=True)

    kills = runs = checked = 0
    failures = []
    out = os.path.join(soak, "out")
    start = time.time()
    while kills < a.kills:
        runs += 1
        force = os.path.isdir(out) and rng.random() < 0.5
        p = run([config] + (["--force"] if force else []), soak, os.path.join(work, "soak-%d.log" % runs))
        delay = rng.uniform(0.05, full_time)
        try:
            rc = p.wait(timeout=delay)
            what = "finished (exit %d)" % rc
            if rc != 0:
                failures.append("run %d exited %d (%s/soak-%d.log)" % (runs, rc, work, runs))
        except subprocess.TimeoutExpired:
            p.send_signal(signal.SIGKILL)
            p.wait()
            kills += 1
            what = "killed at %.1f s (kill %d)" % (delay, kills)
        problems, whole = check_after_kill(out, ref_out, input_hashes) if os.path.isdir(out) else ([], 0)
        checked += whole
        failures += ["run %d: %s" % (runs, x) for x in problems]
        print("soak: run %d%s %s; %d whole model folders checked%s" %
              (runs, " --force" if force else "", what, whole, "; " + "; ".join(problems) if problems else ""),
              flush=True)
    rc = run([config], soak, os.path.join(work, "soak-final.log")).wait()
    if rc != 0:
        failures.append("the final run exited %d" % rc)
    problems = check_final(out, ref_out, input_hashes, models)
    failures += ["final: " + x for x in problems]
    print("soak: %d kills in %d runs (%.0f min), %d model folders checked after kills; final run exit %d, "
          "%d models byte-identical to the reference (timings aside): %s" %
          (kills, runs, (time.time() - start) / 60, checked, rc, len(models),
           "PASS" if not failures else "FAIL (%d problems)" % len(failures)), flush=True)
    for f in failures[:50]:
        print("soak: FAIL: " + f)
    if not a.keep and not failures:
        shutil.rmtree(work, ignore_errors=True)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
