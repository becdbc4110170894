#!/usr/bin/env python3
"""Plot pnb-play per-frame timings.

    plot_frames.py FRAMES_CSV OUT_PNG [--title T]
    plot_frames.py FRAMES_CSV OUT_PNG --compare OTHER_CSV [--labels A B] [--title T]

FRAMES_CSV has a header row with at least the columns frame, time_s (camera-path time),
cpu_ms and gpu_total_ms, plus any number of gpu_<pass>_ms columns (gpu_gbuffer_ms,
gpu_lighting_ms, ...). Empty cells mean "no value" (e.g. a GPU timer not available yet).

The default plot stacks the per-pass GPU times as areas and draws the CPU frame time (and the
wall-clock frame time, frame_ms, when present) as lines, against path time. A streaming run's CSV
(resident_bytes, needed_bytes, stream_upload_bytes) adds a panel below: texture
storage resident and needed, and the bytes uploaded each frame. With --compare, the total GPU frame time of both runs is overlaid instead
(e.g. deferred vs forward over the same camera path). The PNG is written atomically.

Exit status: 0 on success, 2 on a usage error or a missing/malformed CSV (message on stderr).
"""

import argparse
import csv
import math
import os
import statistics
import sys

REQUIRED = ("frame", "time_s", "cpu_ms", "gpu_total_ms")
# Optional columns plotted when present (newer pnb-play; streaming runs).
OPTIONAL = ("frame_ms", "resident_bytes", "needed_bytes", "stream_upload_bytes")


class CsvError(Exception):
    pass


def fail(message):
    print(f"plot_frames.py: error: {message}", file=sys.stderr)
    sys.exit(2)


def parse_number(text, path, line, column):
    text = text.strip()
    if text == "":
        return math.nan
    try:
        value = float(text)
    except ValueError:
        raise CsvError(f"{path}:{line}: column '{column}' is not a number: {text!r}") from None
    return value


def read_frames(path):
    """Returns (columns, pass_columns) where columns maps a name to a list of floats (NaN when
    empty) and pass_columns lists the gpu_<pass>_ms names in file order."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise CsvError(f"cannot read {path}: {e.strerror or e}") from None
    except (UnicodeDecodeError, csv.Error) as e:
        raise CsvError(f"{path}: not a CSV file: {e}") from None
    if not rows:
        raise CsvError(f"{path}: empty file (expected a header row)")
    header = [h.strip() for h in rows[0]]
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise CsvError(f"{path}: header lacks column(s) {', '.join(missing)} "
                       f"(found: {', '.join(header) or 'nothing'})")
    if len(set(header)) != len(header):
        raise CsvError(f"{path}: duplicate column names in the header")
    passes = [h for h in header
              if h.startswith("gpu_") and h.endswith("_ms") and h != "gpu_total_ms"]
    columns = {h: [] for h in header}
    for index, row in enumerate(rows[1:], start=2):
        if not row or all(cell.strip() == "" for cell in row):
            continue  # blank line
        if len(row) != len(header):
            raise CsvError(f"{path}:{index}: {len(row)} fields, the header has {len(header)}")
        for name, cell in zip(header, row):
            if name in REQUIRED or name in OPTIONAL or name in passes:
                columns[name].append(parse_number(cell, path, index, name))
    if not columns["time_s"]:
        raise CsvError(f"{path}: no data rows")
    if any(math.isnan(t) for t in columns["time_s"]):
        raise CsvError(f"{path}: every row needs a time_s value")
    return columns, passes


def median(values):
    finite = [v for v in values if not math.isnan(v)]
    return statistics.median(finite) if finite else math.nan


def fmt_ms(value):
    return "n/a" if math.isnan(value) else f"{value:.2f} ms"


def pass_label(column):
    return column[len("gpu_"):-len("_ms")]


def plot_single(plt, columns, passes, title):
    import numpy as np

    t = np.array(columns["time_s"])
    order = np.argsort(t, kind="stable")
    t = t[order]
    streaming = "resident_bytes" in columns
    if streaming:  # a second panel: texture storage and uploads (streaming runs)
        fig, (ax, sx) = plt.subplots(2, 1, figsize=(11, 8), sharex=True, height_ratios=(3, 2))
    else:
        fig, ax = plt.subplots(figsize=(11, 5.5))
    bottom = np.zeros(len(t))
    if passes:
        values = np.array([columns[p] for p in passes])[:, order]
        # A frame without any pass value is a gap, not a zero; a single missing pass counts as 0.
        no_data = np.all(np.isnan(values), axis=0)
        colours = plt.get_cmap("tab10" if len(passes) <= 10 else "tab20")
        for i, name in enumerate(passes):
            top = bottom + np.nan_to_num(values[i])
            lower = np.where(no_data, np.nan, bottom)
            upper = np.where(no_data, np.nan, top)
            ax.fill_between(t, lower, upper, linewidth=0, alpha=0.85,
                            color=colours(i % colours.N), label=f"GPU {pass_label(name)}")
            bottom = top
    ax.plot(t, np.array(columns["gpu_total_ms"])[order], color="black", linewidth=0.8,
            linestyle=":", label="GPU total")
    ax.plot(t, np.array(columns["cpu_ms"])[order], color="crimson", linewidth=1.2,
            label="CPU frame")
    if "frame_ms" in columns:
        ax.plot(t, np.array(columns["frame_ms"])[order], color="grey", linewidth=0.8,
                label="frame (wall)")
    if streaming:
        mib = 1.0 / 1048576.0
        sx.plot(t, np.array(columns["resident_bytes"])[order] * mib, color="tab:blue",
                label="textures resident (MiB)")
        sx.plot(t, np.array(columns["needed_bytes"])[order] * mib, color="tab:green",
                linestyle="--", label="needed by the view (MiB)")
        sx.bar(t, np.array(columns["stream_upload_bytes"])[order] * mib, width=(t[-1] - t[0]) / max(len(t), 1),
               color="tab:orange", alpha=0.6, label="uploaded this frame (MiB)")
        sx.set_xlabel("path time (s)")
        sx.set_ylabel("MiB")
        sx.set_ylim(bottom=0)
        sx.grid(True, alpha=0.3)
        sx.legend(loc="upper right", fontsize="small")
    else:
        ax.set_xlabel("path time (s)")
    ax.set_ylabel("frame time (ms)")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize="small", ncol=2)
    summary = (f"median GPU total {fmt_ms(median(columns['gpu_total_ms']))}, "
               f"median CPU {fmt_ms(median(columns['cpu_ms']))}, {len(t)} frames")
    ax.set_title(f"{title}\n{summary}" if title else summary)
    fig.tight_layout()
    return fig


def plot_compare(plt, runs, title):
    import numpy as np

    fig, ax = plt.subplots(figsize=(11, 5.5))
    medians = []
    for (label, columns), colour in zip(runs, ("tab:blue", "tab:orange")):
        t = np.array(columns["time_s"])
        order = np.argsort(t, kind="stable")
        total = np.array(columns["gpu_total_ms"])[order]
        m = median(columns["gpu_total_ms"])
        medians.append(f"{label} {fmt_ms(m)}")
        ax.plot(t[order], total, color=colour, linewidth=1.2,
                label=f"{label} (median {fmt_ms(m)})")
        if not math.isnan(m):
            ax.axhline(m, color=colour, linewidth=0.8, linestyle="--")
    ax.set_xlabel("path time (s)")
    ax.set_ylabel("GPU frame time (ms)")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize="small")
    summary = "median GPU total: " + ", ".join(medians)
    ax.set_title(f"{title}\n{summary}" if title else summary)
    fig.tight_layout()
    return fig


def save_atomically(fig, out_path):
    directory = os.path.dirname(os.path.abspath(out_path))
    if not os.path.isdir(directory):
        raise CsvError(f"cannot write {out_path}: directory {directory} does not exist")
    temp = os.path.join(directory, f".{os.path.basename(out_path)}.tmp.{os.getpid()}")
    try:
        fig.savefig(temp, dpi=110, format="png")
        os.replace(temp, out_path)
    except OSError as e:
        raise CsvError(f"cannot write {out_path}: {e.strerror or e}") from None
    finally:
        if os.path.exists(temp):
            os.unlink(temp)


def default_labels(a, b):
    """File stems, or the paths when the stems are equal (run1/frames.csv vs run2/frames.csv)."""
    stems = [os.path.splitext(os.path.basename(p))[0] for p in (a, b)]
    return stems if stems[0] != stems[1] else [a, b]


def main(argv):
    parser = argparse.ArgumentParser(
        prog="plot_frames.py", description="Plot pnb-play per-frame CPU/GPU timings.")
    parser.add_argument("frames_csv", help="per-frame CSV written by pnb-play")
    parser.add_argument("out_png", help="output PNG")
    parser.add_argument("--title", default="", help="plot title (a summary line is added)")
    parser.add_argument("--compare", metavar="OTHER_CSV",
                        help="overlay the total GPU frame time of a second run")
    parser.add_argument("--labels", nargs=2, metavar=("A", "B"),
                        help="legend labels of FRAMES_CSV and OTHER_CSV (with --compare)")
    args = parser.parse_args(argv)
    if args.labels and not args.compare:
        parser.error("--labels needs --compare")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        fail(f"matplotlib is not available for {sys.executable} ({e}); "
             "install python3-matplotlib")

    try:
        columns, passes = read_frames(args.frames_csv)
        if args.compare:
            other, _ = read_frames(args.compare)
            labels = args.labels or default_labels(args.frames_csv, args.compare)
            fig = plot_compare(plt, [(labels[0], columns), (labels[1], other)], args.title)
        else:
            fig = plot_single(plt, columns, passes, args.title)
        save_atomically(fig, args.out_png)
    except CsvError as e:
        fail(str(e))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
