#!/usr/bin/env python3
"""Plots and a Markdown report from `tileshade bench` results.

    python3 bench/plot.py OUT/bench.csv [more.csv | bench.json | OUT ...] --out DIR [--title T]

Reads one or more bench.csv files (shards of one sweep, or several sweeps: rows are concatenated,
a repeated header line is skipped, a (configuration, frame) measured twice keeps the last row) or
bench.json files; a folder stands for its bench.csv (else its bench.json). Writes into DIR, as PNG
and SVG:
  frame_time_*.png         frame time over the camera path per technique (the paper's Figure 2)
  lighting_*.png           lighting computations per frame (the paper's Figure 3)
  kernels_*.png            stacked per-kernel median times per configuration
  vs_tile_*.png            median frame time vs tile size
  vs_light_count_*.png     median frame time vs number of lights
  vs_light_range_*.png     median frame time vs light range (radius)
  scaling_*.png            with several light counts: median frame time (solid) and binning time
                           (dashed: the bin_* kernels and scan) against lights, log-log, per
                           technique, so where each one stops scaling shows as a steeper line
  pareto_*.png             with `bench --error`: speed against error per scene and device, median
                           frame time (x) against max error / peak (y, log) and against PSNR,
                           the Pareto-optimal configurations marked and connected
and report.md: the devices and their calibration, a summary table per configuration (median,
min-max, wall time, % of the device limit, error), the recommended tile size per scene and
device (fastest median), the Pareto front per scene and device with the fastest configuration
with PSNR >= 50 dB and the fastest exact one, and the figures.
"""
import argparse
import csv
import json
import math
import os
import re
import sys
import textwrap
from collections import OrderedDict, defaultdict

plt = None  # matplotlib.pyplot, imported once the input has been read (load_matplotlib)

# Columns of bench.csv after the sweep dimensions (which sit between config_id and device_name).
NUMERIC = {
    "frame", "lights", "geometry_pixels", "total_ms", "wall_ms", "upload_ms", "compile_ms",
    "raster_ms", "warmup", "repeat", "lighting_computations", "evaluations", "gbuffer_bytes_read",
    "nonfinite_pixels", "list_min", "list_mean", "list_max", "min_bytes", "min_flops", "bandwidth_gbs", "peak_gflops",
    "limit_ms", "limit_pct", "reference_contributing", "err_max_abs", "err_rmse", "err_psnr_db",
    "err_max_rel_peak", "err_p50", "err_p99", "err_p999", "err_shading_max_rel_peak",
    "shadow_ms", "shadow_wrong_pct", "shadow_err_max_rel_peak", "shadow_err_rmse",
    "shadow_err_p99", "shadow_err_psnr_db", "shadow_exact_ms",
}
MAX_PANELS = 12  # figures per kind, at most
# Columns every row needs (the figures are keyed and sorted by them).
REQUIRED = ("config_id", "technique", "tile", "device_name", "frame", "total_ms")


class InputError(Exception):
    """Input plot.py cannot use: one line "plot.py: error: ..." and exit status 1."""


def fail(message):
    print("plot.py: error: " + message, file=sys.stderr)
    sys.exit(1)


def shown(text, limit=60):
    """A value as quoted in an error line, cut to `limit` characters."""
    return repr(text if len(text) <= limit else text[:limit] + "...")


def check_row(row, where):
    """Refuses a row without its key columns or with text where a number belongs."""
    for k in ("config_id", "frame"):
        if not row.get(k):
            raise InputError("%s: no %s" % (where, k))
    for k in NUMERIC:
        v = row.get(k)
        if v is None or v == "":
            continue
        try:
            float(v)
        except ValueError:
            raise InputError("%s: column %s is not a number: %s" % (where, k, shown(v)))
    for item in (row.get("kernels") or "").split(";"):
        if "=" in item:
            try:
                float(item.split("=", 1)[1])
            except ValueError:
                raise InputError("%s: kernel time is not a number: %s" % (where, shown(item)))


def number(text):
    if text is None or text == "":
        return float("nan")
    try:
        return float(text)
    except ValueError:
        return float("nan")


def load_csv(path):
    rows, dims = [], []
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = None
        for fields in reader:
            if not fields:
                continue
            if header is None:
                header = fields
                missing = [c for c in REQUIRED if c not in header]
                if missing:
                    raise InputError("%s: no column %s (not a bench.csv?)" % (path, ", ".join(missing)))
                dims = header[header.index("config_id") + 1:header.index("device_name")]
                continue
            if fields == header:
                continue
            where = "%s line %d" % (path, reader.line_num)
            if len(fields) != len(header):
                raise InputError("%s: %d field(s), the header has %d" % (where, len(fields), len(header)))
            row = dict(zip(header, fields))
            check_row(row, where)
            rows.append(row)
    if header is None:
        raise InputError("%s is empty (no header line)" % path)
    return rows, dims


def load_json(path):
    with open(path) as f:
        try:
            doc = json.load(f)
        except json.JSONDecodeError as e:
            raise InputError("%s is not JSON: %s" % (path, e))
        except RecursionError:
            raise InputError("%s nests too deeply" % path)
    if not isinstance(doc, dict) or not isinstance(doc.get("rows", []), list):
        raise InputError('%s: no "rows" list (not a bench.json?)' % path)
    rows, dims = [], []

    def text(v):
        return "" if v is None else str(v)

    for i, r in enumerate(doc.get("rows", [])):
        where = "%s row %d" % (path, i)
        if not isinstance(r, dict) or not isinstance(r.get("config", {}), dict):
            raise InputError("%s is not a bench row" % where)
        flat = {"config_id": text(r.get("config_id"))}
        config = r.get("config", {})
        for k in ("technique", "tile"):
            if k not in config:
                raise InputError("%s: no config.%s" % (where, k))
        for k, v in config.items():
            flat[k] = str(v)
            if k not in dims:
                dims.append(k)
        for k in ("device_name", "frame", "lights", "geometry_pixels", "total_ms", "wall_ms",
                  "upload_ms", "compile_ms", "raster_ms", "lighting_computations", "evaluations",
                  "gbuffer_bytes_read", "reference_contributing"):
            if k in r and r[k] is not None:
                flat[k] = str(r[k])
        for name, obj in r.items():
            if name in ("limit", "error") or name.startswith("error_"):
                if obj is not None and not isinstance(obj, dict):
                    raise InputError("%s: %s is not an object" % (where, name))
        for k, v in (r.get("limit") or {}).items():
            flat[k] = text(v)
        for k, v in (r.get("error") or {}).items():
            flat["err_" + k] = text(v)
        # Further error objects (e.g. "error_vs_physical") as err_vs_physical_*, for --error-prefix.
        for name, obj in r.items():
            if name.startswith("error_") and isinstance(obj, dict):
                for k, v in obj.items():
                    flat["err_" + name[len("error_"):] + "_" + k] = text(v)
        if "missed_contributions" in r:
            flat["missed_contributions"] = text(r["missed_contributions"])
        kernels = r.get("kernels", [])
        if not isinstance(kernels, list) or not all(
                isinstance(k, dict) and "name" in k and "ms" in k for k in kernels):
            raise InputError("%s: kernels is not a list of {name, ms}" % where)
        flat["kernels"] = ";".join("%s=%s" % (k["name"], k["ms"]) for k in kernels)
        check_row(flat, where)
        rows.append(flat)
    return rows, dims


def load(paths):
    rows, dims = [], []
    for p in paths:
        try:
            r, d = load_json(p) if p.endswith(".json") else load_csv(p)
        except UnicodeDecodeError:
            raise InputError("%s is not UTF-8 text" % p)
        except csv.Error as e:
            raise InputError("%s: %s" % (p, e))
        for k in d:
            if k not in dims:
                dims.append(k)
        for row in r:
            row["_source"] = p
        rows.extend(r)
    # The last measurement of a (configuration, frame) wins.
    latest = OrderedDict()
    for row in rows:
        latest[(row.get("config_id"), row.get("frame"))] = row
    rows = list(latest.values())
    for row in rows:
        for k in NUMERIC:
            if k in row:
                row[k] = number(row[k])
        row["_kernels"] = OrderedDict()
        for item in (row.get("kernels") or "").split(";"):
            if "=" in item:
                name, ms = item.split("=", 1)
                row["_kernels"][name] = number(ms)
    return rows, dims


def median(values):
    v = sorted(x for x in values if isinstance(x, float) and math.isfinite(x))
    if not v:
        return float("nan")
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def finite(values):
    return [x for x in values if isinstance(x, float) and math.isfinite(x)]


# The techniques that draw the scene themselves (TechniqueInfo::drawsScene in
# src/techniques/registry.cpp; BenchPlot.DrawsSceneListIsTheRegistrys holds the two equal):
# their geometry passes are inside total_ms, while a G-buffer technique's is the frame's
# raster_ms.
DRAWS_SCENE = {"tiled-forward", "tiled-forward-prez", "clustered-forward", "forward", "forward-single"}


def frame_ms(row, with_shadow_maps, with_geometry):
    """A row's time: its kernels (total_ms), plus the shadow maps' drawing (shadow_ms) with
    either option, plus the G-buffer pass (raster_ms) of a G-buffer technique with_geometry."""
    def extra(name):  # an absent or empty column adds nothing
        v = row.get(name)
        return v if isinstance(v, float) and math.isfinite(v) else 0.0
    t = row.get("total_ms", float("nan"))
    if with_shadow_maps or with_geometry:
        t += extra("shadow_ms")
    if with_geometry and row.get("technique") not in DRAWS_SCENE:
        t += extra("raster_ms")
    return t


def summarize(rows, dims, with_shadow_maps=False, with_geometry=False):
    by = OrderedDict()
    for row in rows:
        by.setdefault(row["config_id"], []).append(row)
    out = []
    for cid, rs in by.items():
        rs.sort(key=lambda r: r["frame"])
        s = {d: rs[0].get(d, "") for d in dims}
        s["config_id"] = cid
        s["device_name"] = rs[0].get("device_name", "")
        s["rows"] = rs
        s["frames"] = len(rs)
        total = finite([frame_ms(r, with_shadow_maps, with_geometry) for r in rs])
        s["median"] = median(total)
        s["min"] = min(total) if total else float("nan")
        s["max"] = max(total) if total else float("nan")
        s["mean"] = sum(total) / len(total) if total else float("nan")
        s["wall"] = median([r.get("wall_ms") for r in rs])
        s["compile"] = max(finite([r.get("compile_ms") for r in rs]) or [float("nan")])
        s["lights_n"] = median([r.get("lights") for r in rs])
        s["lighting"] = median([r.get("lighting_computations") for r in rs])
        s["limit_pct"] = median([r.get("limit_pct") for r in rs])
        bases = {r.get("flops_basis", "") for r in rs} - {""}
        s["basis"] = bases.pop() if len(bases) == 1 else ("mixed" if bases else "")
        kernels = OrderedDict()
        for r in rs:
            for k, v in r["_kernels"].items():
                kernels.setdefault(k, []).append(v)
        s["kernels"] = OrderedDict((k, median(v)) for k, v in kernels.items())
        errs = finite([r.get("err_max_rel_peak") for r in rs])
        s["err_rel"] = max(errs) if errs else float("nan")
        psnr = [r.get("err_psnr_db") for r in rs if isinstance(r.get("err_psnr_db"), float)
                and not math.isnan(r.get("err_psnr_db"))]
        s["psnr"] = min(psnr) if psnr else float("nan")
        out.append(s)
    return out


def tile_key(t):
    m = re.match(r"(\d+)x(\d+)", t or "")
    if not m:
        return (0, 0, t)
    w, h = int(m.group(1)), int(m.group(2))
    return (w * h, w, t)


def slug(text):
    s = re.sub(r"[^A-Za-z0-9]+", "-", text).strip("-").lower()
    return s[:90] or "all"


def fmt(v, digits=2):
    if not isinstance(v, float) or math.isnan(v):
        return "-"
    if math.isinf(v):
        return "inf"
    return "%.*f" % (digits, v)


class Report:
    def __init__(self, out_dir):
        self.out = out_dir
        self.figures = []  # (section, title, file)

    def save(self, fig, name, section, title):
        used = {f for _, _, f in self.figures}
        unique, k = name, 2
        while unique + ".png" in used:  # two panels with the same title keep both figures
            unique, k = "%s-%d" % (name, k), k + 1
        name = unique
        base = os.path.join(self.out, name)
        fig.tight_layout()
        fig.savefig(base + ".png", dpi=110)
        fig.savefig(base + ".svg")
        plt.close(fig)
        self.figures.append((section, title, name + ".png"))


def varying(summaries, dims, exclude):
    return [d for d in dims if d not in exclude and len({s.get(d) for s in summaries}) > 1]


PANEL_DEFAULTS = {"culling": "rect", "math": "precise", "slices": "16", "seed": "1",
                  "device": "default", "lanes": "auto"}


def panel_title(values):
    parts = []
    for k, v in values:
        if k in ("light_count", "light_range", "light_threshold") and v in ("-1", "0"):
            continue
        if k in PANEL_DEFAULTS and v == PANEL_DEFAULTS[k] and len(values) > 4:
            continue  # a default knob: left out of a long title (other values stay: unique names)
        parts.append("%s=%s" % (k, v) if k not in ("scene", "light_set", "resolution", "gbuffer")
                     else v.replace("builtin:", ""))
    return ", ".join(parts)


def panels(summaries, dims, exclude):
    """Groups summaries by every dimension not in `exclude` (the axes and series of a figure)."""
    keys = [d for d in dims if d not in exclude]
    groups = OrderedDict()
    for s in summaries:
        k = tuple((d, s.get(d, "")) for d in keys)
        groups.setdefault(k, []).append(s)
    return groups


def series_label(s, with_tile):
    return s["technique"] + (" " + s["tile"] if with_tile and s.get("tile") else "")


def best_tile_per_technique(group):
    best = OrderedDict()
    for s in group:
        t = s["technique"]
        if t not in best or s["median"] < best[t]["median"]:
            best[t] = s
    return best


def plot_over_frames(report, summaries, dims, field, ylabel, prefix, section, title_what):
    made = 0
    for key, group in panels(summaries, dims, {"technique", "tile"}).items():
        if max(s["frames"] for s in group) < 2 or made >= MAX_PANELS:
            continue
        fig, ax = plt.subplots(figsize=(8, 4.2))
        for t, s in best_tile_per_technique(group).items():
            xs = [r["frame"] for r in s["rows"]]
            ys = [r.get(field, float("nan")) for r in s["rows"]]
            ax.plot(xs, ys, marker="o", ms=3, label=series_label(s, len(group) > 1 and
                                                                 len({g["tile"] for g in group}) > 1))
        ax.set_xlabel("frame of the camera path")
        ax.set_ylabel(ylabel)
        if field == "lighting_computations":
            ax.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
        else:
            ax.set_ylim(bottom=0)
        title = panel_title(key)
        ax.set_title("%s\n%s" % (title_what, title), fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        report.save(fig, "%s_%s" % (prefix, slug(title)), section, title)
        made += 1


def plot_kernels(report, summaries, dims):
    made = 0
    for key, group in panels(summaries, dims, {"technique", "tile"}).items():
        if made >= MAX_PANELS:
            break
        group = sorted(group, key=lambda s: (s["technique"], tile_key(s["tile"])))[:40]
        names = []
        for s in group:
            for k in s["kernels"]:
                if k not in names:
                    names.append(k)
        fig, ax = plt.subplots(figsize=(max(5, 0.55 * len(group) + 2), 4.5))
        bottom = [0.0] * len(group)
        labels = [series_label(s, True) for s in group]
        for k in names:
            vals = [s["kernels"].get(k, 0.0) if math.isfinite(s["kernels"].get(k, 0.0)) else 0.0
                    for s in group]
            ax.bar(range(len(group)), vals, bottom=bottom, label=k)
            bottom = [b + v for b, v in zip(bottom, vals)]
        ax.set_xticks(range(len(group)))
        ax.set_xticklabels(labels, rotation=60, ha="right", fontsize=7)
        ax.set_ylabel("median kernel time (ms)")
        title = panel_title(key)
        ax.set_title("per-kernel median times\n" + title, fontsize=9)
        ax.legend(fontsize=7, ncol=2)
        ax.grid(axis="y", alpha=0.3)
        report.save(fig, "kernels_%s" % slug(title), "Per-kernel times", title)
        made += 1


def plot_vs(report, summaries, dims, dim, xlabel, prefix, section, xvalue, logy=False):
    made = 0
    exclude = {"technique", "tile", dim}
    for key, group in panels(summaries, dims, exclude).items():
        xs_all = {s.get(dim) for s in group}
        if len(xs_all) < 2 or made >= MAX_PANELS:
            continue
        fig, ax = plt.subplots(figsize=(7, 4.2))
        series = OrderedDict()
        with_tile = len({s["tile"] for s in group}) > 1 and dim != "tile"
        for s in group:
            series.setdefault(series_label(s, with_tile) if dim != "tile" else s["technique"],
                              []).append(s)
        plotted = False
        for label, ss in series.items():
            pts = sorted(((xvalue(s), s) for s in ss if xvalue(s) is not None), key=lambda p: p[0])
            if len(pts) < 2:
                continue
            xs = [p[0] for p in pts]
            ys = [p[1]["median"] for p in pts]
            lo = [p[1]["median"] - p[1]["min"] for p in pts]
            hi = [p[1]["max"] - p[1]["median"] for p in pts]
            ax.errorbar(xs, ys, yerr=[lo, hi], marker="o", ms=3, capsize=2, label=label)
            plotted = True
        if not plotted:
            plt.close(fig)
            continue
        if dim == "tile":
            ticks = sorted(xs_all, key=tile_key)
            ax.set_xticks(range(len(ticks)))
            ax.set_xticklabels(ticks)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("frame time, median over frames (ms)")
        if logy:
            ax.set_yscale("log")
        else:
            ax.set_ylim(bottom=0)
        title = panel_title(key)
        ax.set_title("%s\n%s" % (section, title), fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        report.save(fig, "%s_%s" % (prefix, slug(title)), section, title)
        made += 1


BINNING_KERNEL = re.compile(r"^(bin_|scan$)")  # the light grid's passes (techniques/tile_grid.h)


def binning_ms(s):
    """Median time of a configuration's binning kernels, or None when it has none."""
    times = [v for k, v in s["kernels"].items() if BINNING_KERNEL.match(k) and math.isfinite(v)]
    return sum(times) if times else None


def plot_scaling(report, summaries, dims):
    """Frame and binning time against the number of lights, log-log (issue 19)."""
    made = 0
    for key, group in panels(summaries, dims, {"technique", "tile", "light_count"}).items():
        lights = {s["lights_n"] for s in group if math.isfinite(s["lights_n"]) and s["lights_n"] > 0}
        if len(lights) < 2 or made >= MAX_PANELS:
            continue
        fig, ax = plt.subplots(figsize=(7, 4.6))
        series = OrderedDict()
        with_tile = len({s["tile"] for s in group}) > 1
        for s in group:
            if math.isfinite(s["lights_n"]) and s["lights_n"] > 0 and s["median"] > 0:
                series.setdefault(series_label(s, with_tile), []).append(s)
        plotted = False
        for label, ss in series.items():
            ss.sort(key=lambda s: s["lights_n"])
            if len(ss) < 2:
                continue
            xs = [s["lights_n"] for s in ss]
            line, = ax.plot(xs, [s["median"] for s in ss], marker="o", ms=3, label=label)
            binned = [(s["lights_n"], binning_ms(s)) for s in ss]
            binned = [(x, y) for x, y in binned if y is not None and y > 0]
            if len(binned) >= 2:
                ax.plot([x for x, _ in binned], [y for _, y in binned], marker="s", ms=3,
                        ls="--", color=line.get_color(), label=label + " binning")
            plotted = True
        if not plotted:
            plt.close(fig)
            continue
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("number of lights")
        ax.set_ylabel("median time (ms)")
        title = panel_title(key)
        ax.set_title("Frame (solid) and binning (dashed) time vs lights\n" + textwrap.fill(title, 100),
                     fontsize=8)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7, ncol=2)
        report.save(fig, "scaling_%s" % slug(title), "Scaling with the number of lights", title)
        made += 1


# ---- speed against error (issue 5) ----

EXACT_REL = 2e-5     # "exact": max error / peak within fp32 rounding (docs/accuracy.md)
PSNR_GOAL = 50.0     # dB, the "good enough" line of the report
ERROR_FLOOR = 1e-9   # errors of exactly 0 are drawn here (a log axis has no 0)
# Sweep dimensions that are accuracy/speed knobs of one rendering; every other dimension (scene,
# lights, resolution, device, ...) defines the scene and device a Pareto front is drawn for.
KNOBS = ["technique", "tile", "slices", "culling", "gbuffer", "math", "light_threshold", "lanes",
         "shadow_map_size", "shadow_filter", "shadow_bias"]


def error_of(s, prefix):
    """Worst max-error/peak and PSNR over a configuration's error frames, missed contributions."""
    # Infinite errors (frames with NaN/inf pixels) are kept: the worst frame decides.
    rel = [number(str(r.get(prefix + "max_rel_peak", ""))) for r in s["rows"]]
    rel = [x for x in rel if not math.isnan(x)]
    psnr = [number(str(r.get(prefix + "psnr_db", ""))) for r in s["rows"]]
    psnr = [p for p in psnr if not math.isnan(p)]
    missed = finite([number(str(r.get("missed_contributions", ""))) for r in s["rows"]])
    return (max(rel) if rel else float("nan"), min(psnr) if psnr else float("nan"),
            max(missed) if missed else None)


def knob_label(s, knobs):
    parts = []
    for k in knobs:
        v = str(s.get(k, ""))
        if k == "light_threshold":
            parts.append("t=" + v if v not in ("", "0") else "t=scene")
        elif k == "slices":
            if s.get("technique") == "clustered":
                parts.append(v + " slices")
        elif k == "tile":
            parts.append(v)
        else:
            parts.append(v)
    return " ".join(p for p in parts if p)


def pareto_front(points):
    """Points (time, error, item) not dominated by a faster-or-equal one with lower-or-equal error
    (one strictly better); sorted by time."""
    pts = sorted(points, key=lambda p: (p[0], p[1]))
    front, best = [], float("inf")
    for t, e, item in pts:
        if e < best:
            front.append((t, e, item))
            best = e
    return front


def speed_error_groups(summaries, dims, prefix):
    context = [d for d in dims if d not in KNOBS and d != "device"]
    groups = OrderedDict()
    for s in summaries:
        rel, psnr, missed = error_of(s, prefix)
        if math.isnan(rel) or not math.isfinite(s["median"]):
            continue
        if math.isinf(rel):  # NaN/inf pixels: no place on an error axis
            print("plot.py: %s left out of the speed-error plots: its images have NaN/inf pixels"
                  % s["config_id"], file=sys.stderr)
            continue
        s["_rel"], s["_psnr"], s["_missed"] = rel, psnr, missed
        s["_exact"] = rel <= EXACT_REL and (missed is None or missed == 0)
        key = (s["device_name"],) + tuple((d, s.get(d, "")) for d in context)
        groups.setdefault(key, []).append(s)
    return groups


def group_title(key):
    device, rest = key[0], key[1:]
    text = panel_title([(d, v) for d, v in rest if d not in ("light_count", "light_range", "seed")
                        or v not in ("-1", "0", "1")])
    return text, device


def plot_speed_error(report, summaries, dims, prefix, time_label="sum of kernels"):
    """One figure per scene and device; returns [(title, device, group, knobs, front_rel)].
    The time axis is logarithmic where the times span more than 20x (shadow-map sizes)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    out = []
    for key, group in speed_error_groups(summaries, dims, prefix).items():
        knobs = [k for k in KNOBS if k in dims and len({s.get(k) for s in group}) > 1]
        title, device = group_title(key)
        front = [p[2] for p in pareto_front([(s["median"], s["_rel"], s) for s in group])]
        front_psnr = [p[2] for p in pareto_front(
            [(s["median"], -s["_psnr"], s) for s in group if not math.isnan(s["_psnr"])])]
        out.append((title, device, group, knobs, front))
        if len(out) > MAX_PANELS:
            continue
        # Front members are numbered (1, 2, ... by time on the error front, then letters for
        # PSNR-front members not on it) and named in a key under the plots.
        tag = OrderedDict()
        for i, s in enumerate(front):
            tag[s["config_id"]] = (str(i + 1), s)
        for s in front_psnr:
            if s["config_id"] not in tag:
                tag[s["config_id"]] = (chr(ord("a") + len(tag) - len(front)), s)
        finite_psnr = [s["_psnr"] for s in group if math.isfinite(s["_psnr"])]
        psnr_ceiling = max(finite_psnr + [PSNR_GOAL]) + 15.0  # where an infinite PSNR is drawn
        techniques = sorted({s.get("technique", "") for s in group})
        formats = sorted({s.get("gbuffer", "") for s in group})
        colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        shapes = ["o", "s", "^", "D", "v", "P", "X", "*"]
        color = {t: colors[i % len(colors)] for i, t in enumerate(techniques)}
        shape = {g: shapes[i % len(shapes)] for i, g in enumerate(formats)}

        def rel_y(s):
            return max(s["_rel"], ERROR_FLOOR)

        def psnr_y(s):
            return s["_psnr"] if math.isfinite(s["_psnr"]) else psnr_ceiling

        key_lines = ["%s: %s" % (t, knob_label(s, knobs) or s.get("technique", ""))
                     for t, s in tag.values()]
        ncol = 2 if len(key_lines) > 5 else 1
        rows_needed = max((len(key_lines) + ncol - 1) // ncol, 4)  # 4: the legend's rows
        fig = plt.figure(figsize=(13, 5.4 + 0.22 * rows_needed))
        grid = fig.add_gridspec(2, 2, height_ratios=[5.4, 0.3 + 0.22 * rows_needed])
        ax, bx = fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[0, 1])
        kx = fig.add_subplot(grid[1, :])
        kx.axis("off")
        for s in group:
            style = dict(color=color[s.get("technique", "")], marker=shape[s.get("gbuffer", "")],
                         ms=7, ls="none", alpha=0.85,
                         mfc=color[s.get("technique", "")] if s["_exact"] else "white")
            ax.plot([s["median"]], [rel_y(s)], **style)
            if not math.isnan(s["_psnr"]):
                bx.plot([s["median"]], [psnr_y(s)], **style)
        for axis, pts, yf in ((ax, front, rel_y), (bx, front_psnr, psnr_y)):
            axis.plot([s["median"] for s in pts], [yf(s) for s in pts], color="black", lw=1.2,
                      zorder=0, drawstyle="steps-post")
            for i, s in enumerate(pts):
                axis.plot([s["median"]], [yf(s)], marker="o", ms=13, mfc="none", mec="black",
                          ls="none")
                axis.annotate(tag[s["config_id"]][0], (s["median"], yf(s)),
                              textcoords="offset points", xytext=(7, 6 if i % 2 == 0 else -14),
                              fontsize=8, fontweight="bold")
        ax.set_yscale("log")
        lo = min([rel_y(s) for s in group] + [EXACT_REL])
        hi = max([rel_y(s) for s in group] + [EXACT_REL])
        ax.set_ylim(lo / 3.0, hi * 3.0)
        ax.axhline(EXACT_REL, color="grey", ls=":", lw=1)
        ax.annotate("exact: fp32 rounding (%.0e)" % EXACT_REL, (0.01, EXACT_REL),
                    xycoords=("axes fraction", "data"), fontsize=7, va="bottom", color="grey")
        if any(s["_rel"] <= ERROR_FLOOR for s in group):
            ax.axhline(ERROR_FLOOR, color="grey", ls="--", lw=0.8)
            ax.annotate("error 0, drawn at %.0e" % ERROR_FLOOR, (0.01, ERROR_FLOOR),
                        xycoords=("axes fraction", "data"), fontsize=7, va="bottom",
                        color="grey")
        ax.set_ylabel("max error / reference peak (worst frame, log)")
        bx.axhline(PSNR_GOAL, color="grey", ls=":", lw=1)
        bx.annotate("%g dB" % PSNR_GOAL, (0.01, PSNR_GOAL), xycoords=("axes fraction", "data"),
                    fontsize=7, va="bottom", color="grey")
        if any(math.isinf(s["_psnr"]) for s in group):
            bx.axhline(psnr_ceiling, color="grey", ls="--", lw=0.8)
            bx.annotate("PSNR infinite (error 0), drawn here", (0.01, psnr_ceiling),
                        xycoords=("axes fraction", "data"), fontsize=7, va="bottom",
                        color="grey")
        bx.set_ylabel("PSNR (dB, worst frame; higher is better)")
        times = [s["median"] for s in group if s["median"] > 0]
        wide = bool(times) and max(times) > 20.0 * min(times)
        for a in (ax, bx):
            a.set_xlabel("frame time, median over frames (ms, %s%s)"
                         % (time_label, ", log" if wide else ""))
            if wide:
                a.set_xscale("log")
            a.grid(alpha=0.3, which="both")
        handles = [Patch(color=color[t], label=t) for t in techniques]
        handles += [Line2D([], [], color="dimgrey", marker=shape[g], ls="none", label=g)
                    for g in formats if g]
        handles += [Line2D([], [], color="dimgrey", marker="o", mfc="white", ls="none",
                           label="not exact (hollow)"),
                    Line2D([], [], color="black", lw=1.2, label="Pareto front (circled)")]
        kx.legend(handles=handles, fontsize=7, loc="upper right", ncol=2)
        ax.set_title("max error / peak against time", fontsize=9)
        bx.set_title("PSNR against time", fontsize=9)
        per_col = rows_needed
        for c in range(ncol):
            kx.text(0.01 + 0.31 * c, 1.0, "\n".join(key_lines[c * per_col:(c + 1) * per_col]),
                    transform=kx.transAxes, va="top", ha="left", fontsize=8, family="monospace")
        fig.suptitle("speed against error (columns %s*) — %s — %s" % (prefix, title, device),
                     fontsize=9)
        report.save(fig, "pareto_%s" % slug(title + " " + device), "Speed against error",
                    "%s — %s" % (title, device))
    return out


def speed_error_lines(groups, prefix):
    if not groups:
        return []
    lines = ["## Speed against error (Pareto front)", ""]
    if prefix == "err_":
        reference = (
            "These are the errors `tileshade bench --error` writes: against the scene reference, "
            "the windowed model in double from the fp32 G-buffer with the scene's own light "
            "ranges, so storage precision (fp16, packed), `light_threshold`, arithmetic and "
            "culling all show (`--error-prefix err_vs_stored_` on bench.json isolates the last "
            "two; bounds in docs/accuracy.md).")
    else:
        reference = "Error columns `%s*` (chosen with --error-prefix)." % prefix
    has_missed = any(s["_missed"] is not None for g in groups for s in g[2])
    lines.append(
        "Time = median over the timed frames of the kernels' total; error = worst over the error "
        "frames of the `%smax_rel_peak` and `%spsnr_db` columns (max error relative to the "
        "reference's peak pixel, and PSNR). %s A configuration is on the Pareto front when no "
        "other one is at least as fast and at least as exact (one of them strictly). **Exact** = "
        "max error / peak ≤ %.0e (fp32 rounding)%s. Errors of exactly 0 are drawn at %.0e (a log "
        "axis has no 0), infinite PSNRs at the top of the PSNR plot."
        % (prefix, prefix, reference, EXACT_REL,
           " and zero missed light contributions" if has_missed else
           " (missed light contributions are not in these results; the tests check they are 0)",
           ERROR_FLOOR))
    lines.append("")
    for title, device, group, knobs, front in groups:
        cols = knobs or ["technique"]
        lines.append("### %s — %s" % (title, device))
        lines.append("")
        lines.append("| " + " | ".join(cols + ["median ms", "max err / peak", "PSNR dB",
                                               "exact"]) + " |")
        lines.append("|" + "---|" * len(cols) + "---:|---:|---:|---|")
        for s in front:
            lines.append("| " + " | ".join([str(s.get(k, "")) for k in cols] + [
                fmt(s["median"], 3), "%.2e" % s["_rel"], fmt(s["_psnr"], 1),
                "yes" if s["_exact"] else "no"]) + " |")
        lines.append("")

        def describe(s):
            return "%s — %s ms, max error / peak %.2e, PSNR %s dB" % (
                knob_label(s, cols) or s.get("technique", ""), fmt(s["median"], 3), s["_rel"],
                fmt(s["_psnr"], 1))
        good = [s for s in group if not math.isnan(s["_psnr"]) and s["_psnr"] >= PSNR_GOAL]
        exact = [s for s in group if s["_exact"]]
        lines.append("- Fastest configuration with PSNR ≥ %g dB: %s" % (
            PSNR_GOAL, describe(min(good, key=lambda s: s["median"])) if good else "none"))
        lines.append("- Fastest exact configuration: %s" % (
            describe(min(exact, key=lambda s: s["median"])) if exact else "none"))
        lines.append("- %d configurations, %d on the front." % (len(group), len(front)))
        lines.append("")
    return lines


def recommendations(summaries, dims):
    """Fastest median tile per (device, scene, lights, resolution, precision, technique)."""
    keys = [d for d in dims if d not in ("tile", "device")]
    groups = OrderedDict()
    for s in summaries:
        k = (s["device_name"],) + tuple(s.get(d, "") for d in keys)
        groups.setdefault(k, []).append(s)
    out = []
    for k, group in groups.items():
        if len({s["tile"] for s in group}) < 2:
            continue
        best = min(group, key=lambda s: s["median"])
        worst = max(group, key=lambda s: s["median"])
        out.append((best, worst, sorted(group, key=lambda s: tile_key(s["tile"]))))
    return out


def write_report(report, rows, summaries, dims, paths, title, pareto_lines=(),
                 time_basis="sum of the kernels' profiled times"):
    lines = ["# %s" % title, ""]
    lines.append("Inputs: " + ", ".join("`%s`" % p for p in paths) +
                 " — %d rows, %d configurations." % (len(rows), len(summaries)))
    lines.append("")
    devices = OrderedDict()
    for r in rows:
        d = r.get("device_name", "")
        if d not in devices:
            devices[d] = (r.get("bandwidth_gbs"), r.get("peak_gflops"))
    lines.append("## Devices")
    lines.append("")
    lines.append("| device | copy bandwidth (GB/s) | peak (GFLOP/s) |")
    lines.append("|---|---:|---:|")
    for d, (bw, pk) in devices.items():
        lines.append("| %s | %s | %s |" % (d, fmt(bw, 1), fmt(pk, 1)))
    lines.append("")

    shown = ["technique", "tile", "gbuffer"] + varying(summaries, dims,
                                                       {"technique", "tile", "gbuffer"})
    has_err = any(math.isfinite(s["err_rel"]) for s in summaries)
    lines.append("## Summary per configuration")
    lines.append("")
    lines.append("Frame time = " + time_basis + "; median and (min–max) over the "
                 "timed frames; wall = host time from upload to readback; % limit = device-limit "
                 "time / measured kernel time (evaluations from the reference, or * the "
                 "technique's own count).")
    lines.append("")
    head = shown + ["frames", "median ms", "min–max ms", "wall ms", "compile ms", "% limit",
                    "per-kernel median ms"] + (["max err / peak", "min PSNR dB"] if has_err else [])
    lines.append("| " + " | ".join(head) + " |")
    lines.append("|" + "---|" * len(shown) + "---:|" * 6 + "---|" + ("---:|---:|" if has_err else ""))
    for s in summaries:
        kern = " ".join("%s %s" % (k, fmt(v, 3)) for k, v in s["kernels"].items())
        star = "" if s["basis"] == "reference" else ("*" if s["basis"] == "evaluations" else "~")
        pct = fmt(s["limit_pct"], 1)
        cells = [str(s.get(d, "")) for d in shown] + [
            str(s["frames"]), fmt(s["median"], 3), "%s–%s" % (fmt(s["min"], 3), fmt(s["max"], 3)),
            fmt(s["wall"], 2), fmt(s["compile"], 0), pct + (star if pct != "-" else ""), kern]
        if has_err:
            cells += ["%.2e" % s["err_rel"] if math.isfinite(s["err_rel"]) else "-", fmt(s["psnr"], 1)]
        lines.append("| " + " | ".join(cells) + " |")
    lines.append("")

    recs = recommendations(summaries, dims)
    if recs:
        lines.append("## Recommended tile size (fastest median)")
        lines.append("")
        other = varying(summaries, dims, {"tile", "device", "technique"})
        lines.append("| device | " + " | ".join(other + ["technique", "best tile", "median ms",
                                                         "slowest tile", "median ms", "all tiles (ms)"]) + " |")
        lines.append("|---|" + "---|" * (len(other) + 1) + "---|---:|---|---:|---|")
        for best, worst, group in recs:
            alltiles = ", ".join("%s %s" % (s["tile"], fmt(s["median"], 2)) for s in group)
            lines.append("| %s | " % best["device_name"] + " | ".join(
                [str(best.get(d, "")) for d in other] +
                [best["technique"], "**%s**" % best["tile"], fmt(best["median"], 3),
                 worst["tile"], fmt(worst["median"], 3), alltiles]) + " |")
        lines.append("")

    lines.extend(pareto_lines)

    sections = OrderedDict()
    for section, t, f in report.figures:
        sections.setdefault(section, []).append((t, f))
    for section, figs in sections.items():
        lines.append("## " + section)
        lines.append("")
        for t, f in figs:
            lines.append("![%s](%s)" % (t, f))
            lines.append("")
    with open(os.path.join(report.out, "report.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


class OneLineParser(argparse.ArgumentParser):
    """argparse with its errors in one line, like plot.py's others."""

    def error(self, message):
        fail(message + " (see --help)")


def load_matplotlib():
    global plt
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as pyplot
    except ImportError as e:
        fail("the figures need matplotlib (Debian: python3-matplotlib): %s" % e)
    plt = pyplot


def main(argv):
    try:
        plot(argv)
    except InputError as e:
        fail(str(e))
    except OSError as e:
        fail("%s: %s" % (e.filename, e.strerror) if e.filename else str(e))


def plot(argv):
    ap = OneLineParser(description=__doc__.split("\n")[0])
    ap.add_argument("inputs", nargs="+",
                    help="bench.csv or bench.json files, or bench output folders")
    ap.add_argument("--out", required=True, help="output folder for plots and report.md")
    ap.add_argument("--title", default="tileshade bench report")
    ap.add_argument("--error-prefix", default="err_",
                    help="error columns of the speed/error plots: PREFIXmax_rel_peak and "
                         "PREFIXpsnr_db (default err_, what bench --error writes)")
    ap.add_argument("--time-with-shadow-maps", action="store_true",
                    help="time = total_ms + shadow_ms (the kernels and the frame's shadow-map "
                         "drawing), e.g. with --error-prefix shadow_err_ (bench --shadow-error)")
    ap.add_argument("--time-with-geometry", action="store_true",
                    help="time = the whole frame: total_ms + shadow_ms, plus raster_ms (the "
                         "G-buffer pass) for the G-buffer techniques; the forward techniques' "
                         "geometry passes are inside their total_ms (forward against deferred)")
    a = ap.parse_args(argv)
    for i, p in enumerate(a.inputs):
        if os.path.isdir(p):
            for name in ("bench.csv", "bench.json"):
                if os.path.exists(os.path.join(p, name)):
                    a.inputs[i] = os.path.join(p, name)
                    break
            else:
                raise InputError("no bench.csv or bench.json in %s" % p)
        elif not os.path.exists(p):
            raise InputError("no such file: %s" % p)
    rows, dims = load(a.inputs)
    if not rows:
        raise InputError("no rows in " + ", ".join(a.inputs))
    load_matplotlib()
    os.makedirs(a.out, exist_ok=True)
    summaries = summarize(rows, dims, a.time_with_shadow_maps, a.time_with_geometry)
    report = Report(a.out)

    plot_over_frames(report, summaries, dims, "total_ms", "frame time (ms, sum of kernels)",
                     "frame_time", "Frame time over the camera path", "frame time")
    plot_over_frames(report, summaries, dims, "lighting_computations", "lighting computations",
                     "lighting", "Lighting computations per frame", "lighting computations")
    plot_kernels(report, summaries, dims)
    if "tile" in dims:
        def tile_x(s, order=sorted({x["tile"] for x in summaries}, key=tile_key)):
            return order.index(s["tile"])
        plot_vs(report, summaries, dims, "tile", "tile size (pixels)", "vs_tile",
                "Frame time vs tile size", tile_x)
    if "light_count" in dims:
        plot_vs(report, summaries, dims, "light_count", "number of lights", "vs_light_count",
                "Frame time vs number of lights",
                lambda s: s["lights_n"] if math.isfinite(s["lights_n"]) else None)
        plot_scaling(report, summaries, dims)
    if "light_range" in dims:
        plot_vs(report, summaries, dims, "light_range", "light range (scene units)",
                "vs_light_range", "Frame time vs light range",
                lambda s: number(s.get("light_range")) if number(s.get("light_range")) > 0 else None)
    pareto = plot_speed_error(report, summaries, dims, a.error_prefix,
                              "the frame, geometry passes included" if a.time_with_geometry
                              else "kernels + shadow-map drawing" if a.time_with_shadow_maps
                              else "sum of kernels")
    write_report(report, rows, summaries, dims, a.inputs, a.title,
                 speed_error_lines(pareto, a.error_prefix),
                 "total_ms + shadow_ms, + raster_ms (the G-buffer pass) for the G-buffer "
                 "techniques" if a.time_with_geometry
                 else "total_ms + shadow_ms" if a.time_with_shadow_maps
                 else "sum of the kernels' profiled times")
    print("plot.py: %d rows, %d configurations, %d figures -> %s/report.md"
          % (len(rows), len(summaries), len(report.figures), a.out))


if __name__ == "__main__":
    main(sys.argv[1:])
