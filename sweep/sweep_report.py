"""pnb-sweep report: a self-contained HTML page (plus the PNGs and CSV it shows) from a results
directory. Per scene: the Pareto front of each measured error against its cost over every
configuration swept, the front's configurations as a table, the GPU time per pass of every
configuration and along the path for the front's, load time against the raw-bytes floor, and a gallery of each configuration's last
measured frame beside its error maps. Then the numerical-extremes table of the ground-truth
tests, when given. Command experiments (kind = "command", sweep_command.py) get a table of their
jobs' figures, and the page opens with an index of every experiment file in the repository.

Render errors are judged against the median GPU time of a frame (pnb-play's gpu_ms.total); the
converter's errors (quantisation, texture compression) against the container's size. Lower is
better for every error. No network: the page references only files written beside it.
"""
import csv
import html
import json
import os
import re
import shutil
import statistics

from budget_search import pareto_front  # one definition of the front: the budget search's

# (column, title, cost column, cost title): each error's front is drawn against its own cost.
GPU = ("gpu_ms:total", "GPU ms per frame (median)")
SIZE = ("convert:output_bytes", "container MiB")
HEADLINE_ERRORS = [
    # The whole frame against its path-traced truth (pnb-judge --frame-metrics): what a user sees,
    # every knob at once. The displayed image's FLIP first, the headline.
    ("metric:frame_flip_ldr", "whole frame: LDR-FLIP of the displayed image") + GPU,
    ("metric:frame_flip_hdr", "whole frame: HDR-FLIP of the linear image") + GPU,
    ("metric:frame_relmse", "whole frame: relative MSE of the linear image") + GPU,
    ("metric:misclassified_pct", "shadow pixels misclassified, %") + GPU,
    ("metric:weighted_error_pct", "shadow error weighted by irradiance, %") + GPU,
    # Indirect light is judged against the best constant ambient in the same pixels (< 1: better
    # than a constant; both RMSEs with the truth's noise removed), the scorecard's headline.
    ("metric:gi_rmse_over_constant", "GI irradiance RMSE / best constant's", ) + GPU,
    ("metric:sky_rmse_over_constant", "sky irradiance RMSE / best constant's") + GPU,
    ("metric:lod_pixels_over8_pct", "LOD pixels off by > 8/255, %") + GPU,
    ("convert:max_position_error", "mesh quantisation: max position error, scene units") + SIZE,
    ("convert:max_normal_error_deg", "mesh quantisation: max normal error, degrees") + SIZE,
    ("convert:texture_rmse8", "texture compression: worst texture RMSE, 8-bit levels") + SIZE,
]
# The truth's own noise, shown beside the error it bounds: an error near it says nothing.
TRUTH_NOISE = {"metric:frame_relmse": ("metric:frame_truth_noise_relmse", "truth's noise (relMSE)")}
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LOAD_PHASES = ("open", "read", "decode", "upload", "compile")  # pnb-play's summary.json load_ms




def labeller(rows):
    """A function naming a row by the settings that vary among `rows` ("technique=pssm,
    cascades=4"): what is the same for all of them says nothing and makes labels unreadable."""
    keys = [k for k in dict.fromkeys(k for r in rows for k in r if k.startswith("set:"))
            if len({r.get(k, "") for r in rows}) > 1]

    def name(row):
        return ", ".join("%s=%s" % (k.rsplit(".", 1)[-1], row[k]) for k in keys if row.get(k, "") != "") \
            or "(defaults)"
    return name


def conversion_label(row):
    """The pnb-convert options a row's convert.* settings stand for: "--quantize --max-texture-size 512"."""
    parts = []
    for k, v in sorted(row.items()):
        if k.startswith("set:convert.") and v != "false":
            parts.append("--" + k[12:] + ("" if v == "true" else " " + v))
    return " ".join(parts) or "(no converter options)"


def number(row, column):
    v = row.get(column)
    return None if v in (None, "") else float(v)


def scale_cost(column, value):
    return value / 2 ** 20 if column == "convert:output_bytes" else value


def log_if_wide(ax, axis, values):
    """A log scale where values span more than 50x (a shadows-off point at 56 % would flatten
    every technique at 0.1 %); zeros are drawn at half the smallest positive value."""
    positive = [v for v in values if v > 0]
    if not positive or max(positive) / min(positive) <= 50:
        return values
    (ax.set_yscale if axis == "y" else ax.set_xscale)("log")
    low = min(positive) / 2
    return [v if v > 0 else low for v in values]


def front_section(plt, scene, rows, metric, title, cost, cost_title, out_dir):
    measured = [r for r in rows if number(r, metric) is not None and number(r, cost) is not None]
    if cost == "convert:output_bytes":
        # One point per conversion, and only when conversions were swept.
        by_conversion = {}
        for r in measured:
            by_conversion.setdefault(conversion_label(r), r)
        measured = list(by_conversion.values())
        # Nothing to trade when no conversion cost any of this error (no textures to compress).
        if len(measured) < 2 or not any(number(r, metric) for r in measured):
            return []
        name = conversion_label
    else:
        name = labeller(rows)
    if not measured:
        return []
    # One front per GL renderer: results from several GPUs (one results directory, one sweep per
    # GPU model) are compared, never mixed into one front.
    renderers = sorted({r.get("gl_renderer", "") for r in measured})
    png = "%s_%s.png" % (scene, metric.split(":", 1)[1])
    fig, ax = plt.subplots(figsize=(7, 4.5))
    head = "<th>GL renderer</th>" if len(renderers) > 1 else ""
    noise_column, noise_title = TRUTH_NOISE.get(metric, (None, None))
    table = ["<table border=1 cellpadding=3><tr><th>#</th>%s<th>configuration</th><th>%s</th><th>%s</th>%s</tr>"
             % (head, html.escape(cost_title), html.escape(title),
                "<th>%s</th>" % html.escape(noise_title) if noise_column else "")]
    colours = ["#c03020", "#2060c0", "#20a040", "#a040c0", "#c08020"]
    values = [(scale_cost(cost, number(r, cost)), number(r, metric)) for r in measured]
    # Where each point is drawn (a log axis puts zeros at a floor); the table keeps the values.
    drawn = list(zip(log_if_wide(ax, "x", [v[0] for v in values]), log_if_wide(ax, "y", [v[1] for v in values])))
    n_front = 0
    for n, renderer in enumerate(renderers):
        mine = [i for i, r in enumerate(measured) if r.get("gl_renderer", "") == renderer]
        front = [mine[k] for k in pareto_front([values[i] for i in mine])]
        colour = colours[n % len(colours)]
        tag = (" (%s)" % renderer) if len(renderers) > 1 else ""
        ax.scatter([drawn[i][0] for i in mine], [drawn[i][1] for i in mine], color=colour, alpha=0.35, s=14,
                   label="configurations" + tag)
        ax.plot([drawn[i][0] for i in front], [drawn[i][1] for i in front], "o-", color=colour,
                label="Pareto front" + tag)
        # Numbers on the chart, names in the table: fronts of 10+ configurations stay readable.
        for i in front:
            n_front += 1
            ax.annotate(str(n_front), drawn[i], fontsize=7, xytext=(3, 3), textcoords="offset points")
            noise = number(measured[i], noise_column) if noise_column else None
            table.append("<tr><td>%d</td>%s<td>%s</td><td>%.3g</td><td>%.3g</td>%s</tr>"
                         % (n_front, "<td>%s</td>" % html.escape(renderer) if head else "",
                            html.escape(name(measured[i])), values[i][0], values[i][1],
                            "" if not noise_column else "<td>%s</td>" % ("%.3g" % noise if noise is not None else "")))
    table.append("</table>")
    ax.set_xlabel(cost_title)
    ax.set_ylabel(title, fontsize=8)
    ax.set_title(scene)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, png), dpi=100)
    plt.close(fig)
    return ["<h3>%s</h3><img src=\"%s\" alt=\"%s\">" % (html.escape(title), png, html.escape(title))] + table


def passes_section(plt, scene, rows, columns, out_dir):
    passes = [c for c in columns if c.startswith("gpu_ms:") and c != "gpu_ms:total"]
    if not passes:
        return []
    png = "%s_passes.png" % scene
    fig, ax = plt.subplots(figsize=(8, 1.2 + 0.4 * len(rows)))
    left = [0.0] * len(rows)
    for p in passes:
        values = [number(r, p) or 0.0 for r in rows]
        ax.barh(range(len(rows)), values, left=left, label=p.split(":", 1)[1])
        left = [a + b for a, b in zip(left, values)]
    name = labeller(rows)
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels([name(r) for r in rows], fontsize=7)
    ax.set_xlabel("GPU ms per frame (median over the path), by pass")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, png), dpi=100)
    plt.close(fig)
    return ["<h3>GPU time per pass, median of each configuration</h3><img src=\"%s\" alt=\"per-pass time\">" % png]


def gi_cost_section(rows, columns):
    """GI's cost as a share of the frame, per configuration with GI: its own passes (gpu_ms:gi_*:
    RSM, injection, geometry, propagation or the probes' update) over its frame, and its frame
    over the same scene's GI-off frame (set:gi.enabled=false: the look-up inside lighting counts
    too). Measured at the sweep's size; sweep/examples/gi-cost.toml runs the GI sweep at 1280x720."""
    gi_passes = [c for c in columns if c.startswith("gpu_ms:gi_")]
    def gi_off(r):  # a bool from job.json, a string from results.csv
        return str(r.get("set:gi.enabled", "")).lower() == "false"
    off = [number(r, GPU[0]) for r in rows if gi_off(r) and number(r, GPU[0])]
    with_gi = [r for r in rows if not gi_off(r) and number(r, GPU[0])]
    if not gi_passes or not with_gi:
        return []
    base = sorted(off)[len(off) // 2] if off else None
    name = labeller(rows)
    sizes = sorted({r.get("size", "") for r in with_gi})
    out = ["<h3>GI cost, share of the frame (%s)</h3>" % html.escape(", ".join(sizes)),
           "<table border=\"1\" cellspacing=\"0\" cellpadding=\"3\"><tr><th>configuration</th>"
           "<th>GPU ms per frame</th><th>GI passes ms</th><th>GI passes / frame</th>"
           "<th>frame / GI-off frame</th></tr>"]
    for r in sorted(with_gi, key=lambda r: number(r, GPU[0])):
        total = number(r, GPU[0])
        gi = sum(number(r, c) or 0.0 for c in gi_passes)
        vs_off = "+%.0f %%" % (100.0 * (total / base - 1.0)) if base else "(no GI-off job)"
        out.append("<tr><td>%s</td><td>%.1f</td><td>%.1f</td><td>%.0f %%</td><td>%s</td></tr>"
                   % (html.escape(name(r)), total, gi, 100.0 * gi / total, vs_off))
    out.append("</table>")
    if base:
        out.append("<p>GI off: %.1f ms per frame (median of its jobs).</p>" % base)
    return out


def light_count_section(plt, rows, out_dir):
    """Frame time against the light count, for scenes that differ only in a trailing light count
    ("light-field-8" ... "light-field-1024", sweep/examples/lights.toml): one line per
    configuration, and a table of each configuration's frame over its own at the fewest lights
    (the issue's "1024 lights within 2x of 8" yardstick)."""
    families = {}
    for r in rows:
        m = re.match(r"^(.*)-(\d+)$", r["scene"])
        if m and number(r, GPU[0]):
            families.setdefault(m.group(1), []).append((int(m.group(2)), r))
    out = []
    for family, members in sorted(families.items()):
        counts = sorted({c for c, _ in members})
        if len(counts) < 2:
            continue
        name = labeller([r for _, r in members])
        lines = {}
        for c, r in members:
            lines.setdefault(name(r), {})[c] = number(r, GPU[0])
        png = "%s_light_count.png" % family
        fig, ax = plt.subplots(figsize=(7, 4))
        for label, by_count in sorted(lines.items()):
            xs = sorted(by_count)
            ax.plot(xs, [by_count[x] for x in xs], marker="o", label=label)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xlabel("lights in the scene")
        ax.set_ylabel(GPU[1])
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(out_dir, png), dpi=100)
        plt.close(fig)
        out.append("<h2>Frame time by light count: %s</h2><img src=\"%s\" alt=\"frame time by light count\">"
                   % (html.escape(family), png))
        out.append("<table border=\"1\" cellspacing=\"0\" cellpadding=\"3\"><tr><th>configuration</th>%s</tr>"
                   % "".join("<th>%d lights</th>" % c for c in counts))
        for label, by_count in sorted(lines.items()):
            base = by_count.get(counts[0])
            cells = []
            for c in counts:
                v = by_count.get(c)
                cells.append("<td>%s</td>" % ("" if v is None else
                                              "%.1f ms" % v + (" (%.2fx)" % (v / base) if base and c != counts[0] else "")))
            out.append("<tr><td>%s</td>%s</tr>" % (html.escape(label), "".join(cells)))
        out.append("</table>")
    return out


def path_section(plt, scene, rows, results_dir, out_dir, limit=6):
    """GPU time per pass along the camera path (frames.csv) for the configurations worth a look:
    those on a render error's Pareto front, else the first ones, at most `limit`."""
    chosen = []
    for metric, _, cost, _ in HEADLINE_ERRORS:
        if cost != GPU[0]:
            continue
        measured = [r for r in rows if number(r, metric) is not None and number(r, cost) is not None]
        for i in pareto_front([(number(r, cost), number(r, metric)) for r in measured]):
            if measured[i] not in chosen:
                chosen.append(measured[i])
    chosen = (chosen or rows)[:limit]
    name = labeller(rows)
    series = []
    for r in chosen:
        path = os.path.join(results_dir, r["key"], "frames.csv")
        if os.path.exists(path):
            with open(path, newline="") as f:
                series.append((r, list(csv.DictReader(f))))
    series = [(r, frames) for r, frames in series if frames]
    if not series:
        return []
    passes = list(dict.fromkeys(c for _, frames in series for c in frames[0]
                                if c.startswith("gpu_") and c.endswith("_ms") and c != "gpu_total_ms"))
    png = "%s_path.png" % scene
    cols = min(3, len(series))
    rows_n = (len(series) + cols - 1) // cols
    fig, axes = plt.subplots(rows_n, cols, figsize=(4 * cols, 2.8 * rows_n), sharey=True, squeeze=False)
    for ax, (r, frames) in zip(axes.flat, series):
        x = [int(f["frame"]) for f in frames]
        ax.stackplot(x, *[[float(f.get(p) or 0) for f in frames] for p in passes],
                     labels=[p[4:-3] for p in passes])
        ax.set_title(name(r), fontsize=7)
        ax.set_xlabel("frame", fontsize=7)
    for ax in list(axes.flat)[len(series):]:
        ax.axis("off")
    axes.flat[0].set_ylabel("GPU ms")
    axes.flat[0].legend(fontsize=6, loc="upper left")
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, png), dpi=100)
    plt.close(fig)
    return ["<h3>GPU time per pass along the path</h3><p>The configurations on a Pareto front above "
            "(at most %d), frame by frame.</p><img src=\"%s\" alt=\"per-pass time along the path\">"
            % (limit, png)]


def load_section(plt, scene, rows, out_dir):
    """Load time per conversion: the median of every job's load by phase (each job is one fresh
    pnb-play process on a warm page cache), min-max whiskers, and the raw-bytes floor (the same
    file mapped and copied into fresh memory) as a black tick."""
    groups = {}
    for r in rows:
        if number(r, "load_ms:total") is not None:
            groups.setdefault(conversion_label(r), []).append(r)
    if not groups:
        return []
    names = sorted(groups)
    png = "%s_load.png" % scene
    fig, ax = plt.subplots(figsize=(8, 1.2 + 0.45 * len(names)))
    left = [0.0] * len(names)
    for p in LOAD_PHASES:
        values = [statistics.median(number(r, "load_ms:" + p) or 0.0 for r in groups[n]) for n in names]
        ax.barh(range(len(names)), values, left=left, label=p)
        left = [a + b for a, b in zip(left, values)]
    table = ["<table border=1 cellpadding=3><tr><th>conversion</th><th>MiB</th><th>loads</th>"
             "<th>load ms, median (min-max)</th><th>floor ms</th><th>x floor</th></tr>"]
    for i, n in enumerate(names):
        totals = [number(r, "load_ms:total") for r in groups[n]]
        med = statistics.median(totals)
        ax.errorbar([med], [i], xerr=[[med - min(totals)], [max(totals) - med]], color="k", capsize=3, lw=0.8)
        floors = [number(r, "load_ms:floor") for r in groups[n] if number(r, "load_ms:floor") is not None]
        floor = statistics.median(floors) if floors else None
        if floor is not None:
            ax.plot([floor, floor], [i - 0.4, i + 0.4], color="k", lw=2.5)
        mib = (number(groups[n][0], "load:file_bytes") or 0) / 2 ** 20
        table.append("<tr><td>%s</td><td>%.2f</td><td>%d</td><td>%.2f (%.2f-%.2f)</td><td>%s</td><td>%s</td></tr>"
                     % (html.escape(n), mib, len(totals), med, min(totals), max(totals),
                        "%.3f" % floor if floor is not None else "not measured",
                        "%.1f" % (med / floor) if floor else ""))
    table.append("</table>")
    ax.set_yticks(range(len(names)))
    ax.set_yticklabels(names, fontsize=7)
    ax.set_xlabel("load ms to GPU-ready, by phase (black tick: raw-bytes floor)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, png), dpi=100)
    plt.close(fig)
    return ["<h3>Load time</h3><img src=\"%s\" alt=\"load time\">" % png] + table + [
        "<p>Each bar: the median over the jobs that played this container (one pnb-play process "
        "each, page cache warm); whiskers min-max. Floor: mmap + memcpy of the container's bytes "
        "into fresh memory right after (pnb_load_probe --loader floor): no loader can have its "
        "bytes faster.</p>"]


def gallery_section(rows, results_dir, out_dir):
    """Each configuration's last measured frame with the error maps of that frame beside it."""
    figures, legend = [], {}
    name = labeller(rows)
    for r in rows:
        job = os.path.join(results_dir, r["key"])
        if not os.path.exists(os.path.join(job, "frame.png")):
            continue
        os.makedirs(os.path.join(out_dir, "frames"), exist_ok=True)
        images = [("frame.png", "frame")]
        if os.path.exists(os.path.join(job, "error_maps.json")):
            with open(os.path.join(job, "error_maps.json")) as f:
                maps = json.load(f).get("maps", [])  # pnb-play --error-maps (docs/PLAYER.md)
            for m in maps:
                images.append((m["file"], "%s: %s" % (m["metric"], m["file"])))
                legend[m["file"]] = "; ".join("%s: %s" % (e["colour"], e["meaning"]) for e in m.get("legend", []))
        cells = []
        for file, caption in images:
            if not os.path.exists(os.path.join(job, file)):
                continue
            dest = "%s_%s" % (r["key"], file)
            shutil.copyfile(os.path.join(job, file), os.path.join(out_dir, "frames", dest))
            cells.append("<img src=\"frames/%s\" width=\"200\" title=\"%s\" alt=\"%s\">"
                         % (dest, html.escape(caption), html.escape(caption)))
        text = html.escape(name(r))
        figures.append("<figure style=\"display:inline-block;margin:4px;vertical-align:top\">%s"
                       "<figcaption style=\"font-size:small;max-width:%dpx\">%s</figcaption></figure>"
                       % ("".join(cells), 204 * len(cells), text))
    if not figures:
        return []
    # Every job writes the same legends: said once, above the images.
    keys = "".join("<li>%s: %s</li>" % (html.escape(k), html.escape(v)) for k, v in legend.items())
    return ["<h3>Last measured frame of each configuration, with its error maps</h3>"] + \
        (["<ul style=\"font-size:small\">%s</ul>" % keys] if keys else []) + figures


def budget_files(results_dir):
    """The budget searches written into a results directory (pnb_sweep.py budget: budget-<scene>.json)."""
    if not results_dir or not os.path.isdir(results_dir):
        return []
    return sorted(os.path.join(results_dir, f) for f in os.listdir(results_dir)
                  if f.startswith("budget-") and f.endswith(".json"))


def budget_section(plt, path, out_dir):
    """One budget search's answer: the budget, the configuration with the lowest error within it
    beside the defaults (each measured twice, and whether the advantage is within noise), and
    every configuration it measured against the budget, with the front."""
    with open(path) as f:
        b = json.load(f)
    scene, error = b["scene"], b["error"]
    out = ["<h2>Budget search: %s</h2>" % html.escape(scene)]
    reference = "the defaults' cost" if b.get("ratio_to") == "defaults" else "the cheaper of the defaults and the floor"
    given = "%.3g x %.3f ms, %s" % (b["budget_ratio"], b["ratio_reference_ms"], reference) \
        if b.get("budget_ratio") and b.get("ratio_reference_ms") else "given"
    out.append("<p>Minimising %s at %s over %d frames; budget %s GPU ms per frame (%s). %d configurations "
               "measured.</p>" % (html.escape(error), html.escape(b["size"]), b["frames"],
                                  "%.3f" % b["budget_ms"] if b.get("budget_ms") is not None else "?",
                                  html.escape(given), len(b.get("configurations", []))))
    if not b.get("answer"):
        return out + ["<p><b>No answer:</b> %s</p>" % html.escape(b.get("message", ""))]
    w, d = b["answer"], b["defaults"]
    out.append("<table border=1 cellpadding=3><tr><th></th><th>configuration</th><th>GPU ms</th><th>%s</th>"
               "<th>measured again: ms, %s</th></tr>" % (html.escape(error), html.escape(error)))
    for label, r, again in (("best within the budget", w, b["verdict"].get("winner_again")),
                            ("defaults", d, b["verdict"].get("defaults_again"))):
        describe = " ".join("%s=%s" % kv for kv in sorted(r["settings"].items())) or "(defaults)"
        out.append("<tr><td>%s</td><td>%s</td><td>%.3f</td><td>%.4g</td><td>%s</td></tr>"
                   % (label, html.escape(describe), r["cost"], r["error"],
                      "%.3f, %.4g" % (again["cost"], again["error"]) if again else "not measured"))
    out.append("</table><p>%s%s</p>" % (html.escape(b["verdict"]["text"]), ". The defaults are on the front: "
                                        "nothing measured is both cheaper and more accurate"
                                        if b.get("defaults_on_front") else ""))
    for r in b["verdict"].get("near_misses", []):
        out.append("<p>Over the budget within the cost's noise, and more accurate: %s (%.3f ms, %.4g)</p>"
                   % (html.escape(" ".join("%s=%s" % kv for kv in sorted(r["settings"].items())) or "(defaults)"),
                      r["cost"], r["error"]))
    measured = [r for r in b["configurations"] if r and "failed" not in r]
    png = "budget_%s.png" % scene
    fig, ax = plt.subplots(figsize=(7, 4.5))
    front = b["front"]
    # Drawn on a log scale where the errors span more than 50x (shadows off beside the rest).
    ys = log_if_wide(ax, "y", [r["error"] for r in measured + front + [d, w]])
    n, k = len(measured), len(front)
    ax.scatter([r["cost"] for r in measured], ys[:n], color="#2060c0", alpha=0.4, s=14,
               label="configurations measured")
    ax.plot([r["cost"] for r in front], ys[n:n + k], "o-", color="#c03020", label="Pareto front")
    ax.axvline(b["budget_ms"], color="k", ls="--", lw=1, label="budget")
    ax.plot([d["cost"]], [ys[-2]], "s", color="#20a040", ms=9, label="defaults")
    ax.plot([w["cost"]], [ys[-1]], "*", color="#c08020", ms=14, label="best within the budget")
    ax.set_xlabel(GPU[1])
    ax.set_ylabel(error)
    ax.set_title("%s: budget search" % scene)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, png), dpi=100)
    plt.close(fig)
    out.append("<img src=\"%s\" alt=\"budget search\">" % png)
    out.append("<table border=1 cellpadding=3><tr><th>front: GPU ms</th><th>%s</th><th>configuration</th></tr>"
               % html.escape(error))
    for r in front:
        out.append("<tr><td>%.3f</td><td>%.4g</td><td>%s</td></tr>" % (
            r["cost"], r["error"], html.escape(" ".join("%s=%s" % kv for kv in sorted(r["settings"].items()))
                                               or "(defaults)")))
    out.append("</table>")
    return out


def extremes_section(path):
    """The ground-truth extremes matrix (bench/extremes/matrix.py, run by the test
    reference.extremes_matrix and by scripts/bench-extremes): per technique, each row's error at
    each unit scale, out-of-band cells marked."""
    with open(path, newline="") as f:
        cells = list(csv.DictReader(f))
    if not cells:
        return []
    scales = sorted({c["scale"] for c in cells}, key=float)
    body = ["<h2>Numerical extremes</h2>",
            "<p>From %s: each row one scene variant (unit scale, far origin, grazing sun, tiny near "
            "plane), each column a unit of length; cells: misclassified %% / irradiance-weighted "
            "error %% against Embree; <b>red</b>: outside the band the test asserts, or not finite.</p>"
            % html.escape(path)]
    for t in sorted({c["technique"] for c in cells}):
        body.append("<h3>%s</h3><table border=1 cellpadding=3><tr><th>row</th>%s</tr>"
                    % (html.escape(t.upper()), "".join("<th>x%s</th>" % html.escape(s) for s in scales)))
        for row in dict.fromkeys(c["row"] for c in cells if c["technique"] == t):
            tds = []
            for s in scales:
                c = next((c for c in cells if c["row"] == row and c["scale"] == s and c["technique"] == t), None)
                if c is None:
                    tds.append("<td></td>")
                    continue
                bad = c.get("in_band") != "yes"
                tds.append("<td%s>%.3f / %.3f</td>" % (" style=\"color:#c00000;font-weight:bold\"" if bad else "",
                                                       float(c["misclassified_pct"]), float(c["weighted_error_pct"])))
            body.append("<tr><td>%s</td>%s</tr>" % (html.escape(row), "".join(tds)))
        body.append("</table>")
    return body


def command_section(rows, results_dir):
    """Command experiments' jobs (kind = "command"): per experiment, a table of each job's
    figures (one column per job: its axis values and extra arguments), and its log."""
    out = []
    for name in sorted({r["scene"] for r in rows}):
        erows = [r for r in rows if r["scene"] == name]
        figures = []
        for r in erows:
            figures += [c for c in r if c.startswith("fig:") and c not in figures and r[c] not in ("", None)]

        def head(r):
            what = " ".join(["%s=%s" % (c[4:], r[c]) for c in sorted(r) if c.startswith("set:")] +
                            ([r["args"]] if r.get("args") else []))
            link = html.escape(r["key"])
            if results_dir:
                link = "<a href=\"%s\">%s</a>" % (html.escape(os.path.join(os.path.abspath(results_dir), r["key"],
                                                                           "log.txt")), link)
            return "%s<br>%s" % (html.escape(what or "(defaults)"), link)

        def cell(v):  # numbers (also as results.csv's text) right-aligned, 6 significant digits
            if v in ("", None):
                return "<td></td>"
            if not isinstance(v, bool) and v not in ("True", "False"):
                try:
                    return "<td align=right>%.6g</td>" % float(v)
                except ValueError:
                    pass
            return "<td>%s</td>" % html.escape(str(v))

        out.append("<h2>%s (command)</h2><table border=1 cellpadding=3><tr><th>figure</th>%s</tr>"
                   % (html.escape(name), "".join("<th>%s</th>" % head(r) for r in erows)))
        for f in figures:
            out.append("<tr><td>%s</td>%s</tr>" % (html.escape(f[4:]), "".join(cell(r.get(f)) for r in erows)))
        out.append("</table>")
    return out


def index_section(experiments):
    """The experiment files of the repository, each with what it measures and its jobs."""
    out = ["<h2>Experiments</h2><p>Every experiment file (<code>pnb_sweep.py list</code>); run one with "
           "<code>sweep/pnb_sweep.py run --local FILE</code> or <code>experiment FILE</code>.</p>",
           "<table border=1 cellpadding=3><tr><th>file</th><th>kind</th><th>jobs</th><th>measures</th></tr>"]
    for e in experiments:
        out.append("<tr><td>%s</td><td>%s</td><td align=right>%s</td><td>%s</td></tr>" % (
            html.escape(os.path.relpath(e["path"], REPO)), html.escape(e["kind"]),
            e["jobs"] if e["error"] is None else "", html.escape(e["error"] or e["description"])))
    out.append("</table>")
    return out


def write_report(columns, rows, out_dir, results_dir=None, extremes=None, experiments=None):
    """Writes out_dir/index.html, results.csv and one PNG per chart. Returns the HTML path.
    Command experiments' rows get a table of their figures; `experiments` (pnb_sweep's
    experiment_index) an index of every experiment file."""
    command_rows = [r for r in rows if r.get("kind") == "command"]
    play_rows = [r for r in rows if r.get("kind") != "command"]
    plt = None
    if play_rows:  # command figures are tables: no matplotlib needed for them alone
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
        except ImportError:
            raise RuntimeError("the report needs matplotlib (Debian: python3-matplotlib; scripts/setup installs it)")
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "results.csv.tmp"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        w.writerows(rows)
    os.replace(os.path.join(out_dir, "results.csv.tmp"), os.path.join(out_dir, "results.csv"))
    body = ["<h1>pnb-sweep report</h1>",
            "<p>%d configurations. <a href=\"results.csv\">results.csv</a></p>" % len(rows)]
    # scripts/gallery's sheets beside the report (scripts/demo writes them to ../gallery): the
    # Khronos sample models as the player draws them next to the sample viewer's screenshots.
    if os.path.exists(os.path.join(out_dir, "..", "gallery", "index.html")):
        body.append("<p><a href=\"../gallery/index.html\">Conformance gallery</a>: the Khronos "
                    "glTF sample models, ours next to the sample viewer's screenshot, each judged "
                    "by its own criterion.</p>")
    if experiments:
        body += index_section(experiments)
    body += command_section(command_rows, results_dir)
    rows = play_rows
    if not rows:
        return finish_page(out_dir, body)
    renderers = sorted({r.get("gl_renderer", "") for r in rows})
    body.append("<p>GL renderers: %s</p>" % html.escape(", ".join(renderers)))
    body += light_count_section(plt, rows, out_dir)
    for scene in sorted({r["scene"] for r in rows}):
        srows = [r for r in rows if r["scene"] == scene]
        body.append("<h2>%s</h2>" % html.escape(scene))
        for metric, title, cost, cost_title in HEADLINE_ERRORS:
            body += front_section(plt, scene, srows, metric, title, cost, cost_title, out_dir)
        body += passes_section(plt, scene, srows, columns, out_dir)
        body += gi_cost_section(srows, columns)
        body += load_section(plt, scene, srows, out_dir)
        if results_dir:
            body += path_section(plt, scene, srows, results_dir, out_dir)
            body += gallery_section(srows, results_dir, out_dir)
    for path in budget_files(results_dir):
        body += budget_section(plt, path, out_dir)
    if extremes:
        body += extremes_section(extremes)
    else:
        body.append("<h2>Numerical extremes</h2><p>Not included: give <code>--extremes</code> the "
                    "matrix.csv of <code>scripts/bench-extremes</code> or of the test "
                    "<code>reference.extremes_matrix</code>.</p>")
    return finish_page(out_dir, body)


def finish_page(out_dir, body):
    page = os.path.join(out_dir, "index.html")
    with open(page + ".tmp", "w") as f:
        f.write("<!doctype html><html><head><meta charset=\"utf-8\"><title>pnb-sweep report</title></head>"
                "<body>\n%s\n</body></html>\n" % "\n".join(body))
    os.replace(page + ".tmp", page)
    return page
