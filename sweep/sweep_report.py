"""pnb-sweep report: a self-contained HTML page (plus the PNGs and CSV it shows) from a results
directory — per scene, the Pareto front of error against cost over every configuration swept,
the front's configurations as a table, the GPU time per pass of every configuration, and a
gallery of each configuration's last frame.

Cost is the median GPU time of a frame (pnb-play's gpu_ms.total); each headline error metric
the jobs measured gets its own front (lower is better for all of them). No network: the page
references only files written beside it.
"""
import csv
import html
import os
import shutil

# The error each metric family is judged by (pnb-play's quality columns), lower is better.
HEADLINE_ERRORS = [
    ("metric:misclassified_pct", "shadow pixels misclassified, %"),
    ("metric:weighted_error_pct", "shadow error weighted by irradiance, %"),
    ("metric:gi_corrected_rmse_pct", "GI irradiance rel. RMSE (truth noise removed), %"),
    ("metric:sky_corrected_rmse_pct", "sky irradiance rel. RMSE (truth noise removed), %"),
    ("metric:lod_pixels_over8_pct", "LOD pixels off by > 8/255, %"),
]


def pareto_front(points):
    """Indices of the points no other point beats in both cost and error (both minimised)."""
    order = sorted(range(len(points)), key=lambda i: (points[i][0], points[i][1]))
    front, best = [], float("inf")
    for i in order:
        if points[i][1] < best:
            front.append(i)
            best = points[i][1]
    return front


def label(row):
    parts = ["%s=%s" % (k[4:], v) for k, v in row.items() if k.startswith("set:")]
    return ", ".join(parts) or "(defaults)"


def write_report(columns, rows, out_dir, results_dir=None):
    """Writes out_dir/index.html, results.csv and one PNG per chart. Returns the HTML path."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise RuntimeError("the report needs matplotlib (Debian: python3-matplotlib; scripts/setup installs it)")
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        w.writerows(rows)
    body = ["<h1>pnb-sweep report</h1>",
            "<p>%d configurations. Cost: median GPU time per frame. <a href=\"results.csv\">results.csv</a></p>"
            % len(rows)]
    renderers = sorted({r.get("gl_renderer", "") for r in rows})
    body.append("<p>GL renderers: %s</p>" % html.escape(", ".join(renderers)))
    for scene in sorted({r["scene"] for r in rows}):
        srows = [r for r in rows if r["scene"] == scene]
        body.append("<h2>%s</h2>" % html.escape(scene))
        for metric, title in HEADLINE_ERRORS:
            measured = [r for r in srows if r.get(metric) not in (None, "") and r.get("gpu_ms:total") not in (None, "")]
            if not measured:
                continue
            points = [(float(r["gpu_ms:total"]), float(r[metric])) for r in measured]
            front = pareto_front(points)
            png = "%s_%s.png" % (scene, metric.split(":", 1)[1])
            fig, ax = plt.subplots(figsize=(6, 4))
            ax.scatter([p[0] for p in points], [p[1] for p in points], color="#999999", label="configurations")
            fx = [points[i][0] for i in front]
            fy = [points[i][1] for i in front]
            ax.plot(fx, fy, "o-", color="#c03020", label="Pareto front")
            for i in front:
                ax.annotate(label(measured[i]), points[i], fontsize=7, xytext=(4, 4), textcoords="offset points")
            ax.set_xlabel("GPU ms per frame (median)")
            ax.set_ylabel(title)
            ax.set_title(scene)
            ax.legend()
            fig.tight_layout()
            fig.savefig(os.path.join(out_dir, png), dpi=100)
            plt.close(fig)
            body.append("<h3>%s</h3><img src=\"%s\" alt=\"%s\">" % (html.escape(title), png, html.escape(title)))
            body.append("<table border=1 cellpadding=3><tr><th>configuration</th><th>GPU ms</th><th>%s</th></tr>"
                        % html.escape(title))
            for i in front:
                body.append("<tr><td>%s</td><td>%.2f</td><td>%.3g</td></tr>"
                            % (html.escape(label(measured[i])), points[i][0], points[i][1]))
            body.append("</table>")
        passes = [c for c in columns if c.startswith("gpu_ms:") and c != "gpu_ms:total"]
        if passes:
            png = "%s_passes.png" % scene
            fig, ax = plt.subplots(figsize=(7, 0.5 + 0.4 * len(srows)))
            left = [0.0] * len(srows)
            for p in passes:
                values = [float(r.get(p) or 0.0) for r in srows]
                ax.barh(range(len(srows)), values, left=left, label=p.split(":", 1)[1])
                left = [a + b for a, b in zip(left, values)]
            ax.set_yticks(range(len(srows)))
            ax.set_yticklabels([label(r) for r in srows], fontsize=7)
            ax.set_xlabel("GPU ms per frame (median), by pass")
            ax.legend(fontsize=7, loc="lower right")
            fig.tight_layout()
            fig.savefig(os.path.join(out_dir, png), dpi=100)
            plt.close(fig)
            body.append("<h3>GPU time per pass</h3><img src=\"%s\" alt=\"per-pass time\">" % png)
        # Gallery: each configuration's last frame, copied beside the page.
        figures = []
        for r in srows:
            frame = os.path.join(results_dir, r["key"], "frame.png") if results_dir else None
            if frame and os.path.exists(frame):
                os.makedirs(os.path.join(out_dir, "frames"), exist_ok=True)
                shutil.copyfile(frame, os.path.join(out_dir, "frames", r["key"] + ".png"))
                figures.append("<figure style=\"display:inline-block;margin:4px\"><img src=\"frames/%s.png\" "
                               "width=\"240\"><figcaption style=\"font-size:small\">%s</figcaption></figure>"
                               % (r["key"], html.escape(label(r))))
        if figures:
            body.append("<h3>Last frame of each configuration</h3>" + "".join(figures))
    page = os.path.join(out_dir, "index.html")
    with open(page, "w") as f:
        f.write("<!doctype html><html><head><meta charset=\"utf-8\"><title>pnb-sweep report</title></head>"
                "<body>\n%s\n</body></html>\n" % "\n".join(body))
    return page
