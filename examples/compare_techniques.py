"""Compare light-culling techniques: time against error (a notebook-style script; cells as `# %%`).

    PYTHONPATH=build/python /usr/bin/python3 examples/compare_techniques.py [OUT.png]
        [--width 320 --height 180 --device cpu]

Renders one frame of the built-in street with three techniques at a few tile sizes (and the tiled
one with native arithmetic), checks each against tileshade's double-precision reference, and plots
the frame's kernel time against the error relative to the peak (docs/accuracy.md). CI runs it at 160x90 (CTest:
Python.compare_techniques_example). Needs python3-numpy and python3-matplotlib.
"""
# %% Setup: the arguments, matplotlib without a display
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import tileshade  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("out", nargs="?", default="compare_techniques.png", help="the plot (PNG)")
parser.add_argument("--width", type=int, default=320)
parser.add_argument("--height", type=int, default=180)
parser.add_argument("--device", default="", help="as `tileshade render --device`")
parser.add_argument("--lights", type=int, default=200, help="light count of the street")
args = parser.parse_args()

# %% One frame, shared by every renderer: rasterized once, uploaded once
device = tileshade.Device(args.device)
frame = tileshade.Frame.from_scene(device, scene="builtin:street", width=args.width,
                                   height=args.height, light_count=args.lights)
print(f"{device.name}: {frame.info['light_summary']}, {args.width}x{args.height}")

# %% Each technique at each tile size, with the reference check; and the tiled technique with the
# device's native arithmetic (math="native": faster on some devices, less accurate)
variants = [("tiled", 8, "precise"), ("tiled", 16, "precise"), ("tiled", 32, "precise"),
            ("clustered", 8, "precise"), ("clustered", 16, "precise"),
            ("deferred", 16, "precise"),  # no tiles: one pass per light
            ("tiled", 16, "native")]
runs = []
for technique, tile, math in variants:
    renderer = tileshade.Renderer(device, technique, tile=tile, math=math)
    renderer.prepare(frame)  # kernels built here, never inside the timed frame
    renderer.shade(frame)  # a warm-up frame (light lists grown, caches warm)
    result = renderer.shade(frame, check=True)
    runs.append({"label": technique if math == "precise" else f"{technique} ({math})",
                 "tile": tile, "math": math, "ms": result.total_ms,
                 "error": result.check["error"]["max_rel_peak"],
                 "missed": result.check["missed"]})
    r = runs[-1]
    print(f"{r['label']:16s} tile {tile:2d}: {r['ms']:8.3f} ms  error {r['error']:.2e} of the "
          f"peak  missed {r['missed']}")

# %% Every technique misses no light and stays within the documented tolerance (1e-4 of the peak)
assert all(r["missed"] == 0 for r in runs), "a light list left out a contributing light"
assert all(r["error"] <= 1e-4 for r in runs if r["math"] == "precise"), "beyond the tolerance"

# %% Time against error
fig, ax = plt.subplots(figsize=(6, 4), dpi=100)
for label in dict.fromkeys(r["label"] for r in runs):
    mine = [r for r in runs if r["label"] == label]
    ax.plot([r["ms"] for r in mine], [max(r["error"], 1e-9) for r in mine], "o-", label=label)
    for r in mine:
        ax.annotate(str(r["tile"]), (r["ms"], max(r["error"], 1e-9)), textcoords="offset points",
                    xytext=(4, 4), fontsize=8)
ax.set_xlabel("kernel time per frame (ms; labels: tile size)")
ax.set_xscale("log")
ax.set_ylabel("max error / peak")
ax.set_yscale("log")
ax.set_title(f"builtin:street {args.width}x{args.height}, {frame.info['light_summary']}\n"
             f"{device.name}", fontsize=9)
ax.legend()
fig.tight_layout()
fig.savefig(args.out)
print(f"wrote {args.out}")
