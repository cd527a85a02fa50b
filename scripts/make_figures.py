#!/usr/bin/python3
"""Figures for README.md and docs/, made from perclod's own outputs.

  scripts/make_figures.py perception  -> docs/perception_56m_427m.png
      render, vision-simulated and difference images of the demo building's
      +x facade at 56 m and 427 m (runs `perclod label` with the paper's one sample per pixel).
  scripts/make_figures.py marking     -> docs/marking_56m.png
      the marking-colour renders at 56 m and from d/4.

Needs Debian's python3-matplotlib (run with /usr/bin/python3; scripts/setup.sh installs it) and build/perclod.
"""
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODEL = os.path.join(ROOT, "data/ingolstadt/bldg_4018215.obj")
CLI = os.path.join(ROOT, "build/perclod")
FACADE = "+x"


def label(out, distance):
    subprocess.run([CLI, "label", MODEL, "--up", "z", "-d", str(distance), "--views", FACADE, "--samples", "1", "-o", out],
                   check=True, stdout=subprocess.DEVNULL)
    return os.path.join(out, f"bldg_4018215_{FACADE}_{distance}m")


def crop_box(render, margin=12):
    """Bounding box of the non-background (non-white) pixels, with a margin."""
    fg = np.any(render[:, :, :3] < 0.999, axis=2)
    ys, xs = np.nonzero(fg)
    h, w = fg.shape
    return (max(ys.min() - margin, 0), min(ys.max() + margin, h), max(xs.min() - margin, 0),
            min(xs.max() + margin, w))


def perception_figure(path):
    with tempfile.TemporaryDirectory() as tmp:
        rows = []
        for d in (56, 427):
            base = label(tmp, d)
            render = mpimg.imread(base + ".png")
            y0, y1, x0, x1 = crop_box(render)
            rows.append((d, [mpimg.imread(base + s)[y0:y1, x0:x1] for s in
                             (".png", "_simulated.png", "_difference.png")]))
        fig, axes = plt.subplots(2, 3, figsize=(12, 7.5))
        for r, (d, images) in enumerate(rows):
            for c, (img, title) in enumerate(zip(images, ("render", "vision-simulated", "difference"))):
                ax = axes[r][c]
                ax.imshow(img, cmap="gray", vmin=0, vmax=1, interpolation="nearest")
                ax.set_title(f"{title}, {d} m ({img.shape[1]}x{img.shape[0]} px crop)", fontsize=9)
                ax.axis("off")
        fig.suptitle("Ingolstadt building 4018215, +x facade, paper display (29.64 ppd): "
                     "black = perceptible, grey = imperceptible detail", fontsize=10)
        fig.tight_layout()
        fig.savefig(path, dpi=110)


def marking_figure(path):
    with tempfile.TemporaryDirectory() as tmp:
        base = label(tmp, 56)
        fig, axes = plt.subplots(1, 2, figsize=(12, 5))
        for ax, (suffix, title) in zip(axes, (("_marking.png", "labelled at 56 m, seen from 56 m"),
                                             ("_marking_near.png", "the same labels seen from 14 m"))):
            img = mpimg.imread(base + suffix)
            if suffix == "_marking.png":
                y0, y1, x0, x1 = crop_box(img)
                img = img[y0:y1, x0:x1]
            ax.imshow(img, interpolation="nearest")
            ax.set_title(title, fontsize=9)
            ax.axis("off")
        fig.suptitle("Marking colours: green perceptible, red imperceptible, blue undisplayable", fontsize=10)
        fig.tight_layout()
        fig.savefig(path, dpi=110)


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "perception"
    os.makedirs(os.path.join(ROOT, "docs"), exist_ok=True)
    if what == "perception":
        perception_figure(os.path.join(ROOT, "docs/perception_56m_427m.png"))
    elif what == "marking":
        marking_figure(os.path.join(ROOT, "docs/marking_56m.png"))
    else:
        sys.exit(f"unknown figure '{what}' (perception | marking)")
