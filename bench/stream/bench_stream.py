#!/usr/bin/env python3
"""Streaming playback on a large generated scene (docs/PLAYER.md "Streaming", issue 14's figures).

Usage: bench_stream.py [--size 5G] [--budget-mib 512] [--frames 600] [--static-frames 300]
                            [--upload-mib 8] [--lod-frames 240] [--no-lod-rocks] [--build DIR]
                            [--out DIR] [--cold] [--keep]

Makes a texture-heavy street scene of --size with pnb-make-stream-scene in $TMPDIR (deleted at
the end unless --keep) — with a rock of its own beside every panel, converted with LOD levels
(proxy + MDET), unless --no-lod-rocks — then runs fresh pnb-play processes (--headless --bench,
fixed step):
  full-load       --no-stream, one frame: time to first frame = the whole load
  stream          --stream, no budget, one frame: time to first frame, bytes read by then
  stream-path     --stream, --budget-mib, --frames along the scene's path: peak RSS, peak texture
                  storage, uploads and evictions per frame, stalls, frame-time p95
  stream-static   --stream, --budget-mib, --static-frames at the path's start: frame-time p95
                  while streaming against after the view is complete (one run: a ratio)
  lod-full        full load, --lod-frames along the path at lod.force=0: triangles without LOD
  lod             full load, the same frames with LOD selection (lod.threshold_px 1) and
                  --lod-metrics 8: triangles, and the image error against LOD 0 (PSNR)
With --cold the page cache is dropped (/proc/sys/vm/drop_caches, root) before full-load and
stream, so the disk is read too. Prints the table and the goals; writes DIR/stream.json.
The experiment sweep/experiments/stream.toml runs this (scripts/bench-stream runs that).
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, text=True, capture_output=True, **kw)


def drop_caches():
    try:
        subprocess.run(["sync"], check=True)
        with open("/proc/sys/vm/drop_caches", "w") as f:
            f.write("3\n")
        return True
    except OSError as e:
        print(f"bench-stream: cannot drop the page cache ({e}); the runs are warm", file=sys.stderr)
        return False


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", default="5G")
    ap.add_argument("--budget-mib", type=int, default=512)
    ap.add_argument("--upload-mib", type=float, default=8)
    ap.add_argument("--frames", type=int, default=600)
    ap.add_argument("--static-frames", type=int, default=300)
    ap.add_argument("--lod-frames", type=int, default=240)
    ap.add_argument("--no-lod-rocks", action="store_true")
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench", "stream"))
    ap.add_argument("--size-px", default="512x288")
    ap.add_argument("--cold", action="store_true")
    ap.add_argument("--keep", action="store_true")
    a = ap.parse_args()
    make = os.path.join(a.build, "bench", "stream", "pnb-make-stream-scene")
    play = os.path.join(a.build, "player", "pnb-play")
    for tool in (make, play):
        if not os.access(tool, os.X_OK):
            sys.exit(f"bench-stream: {tool} is missing: build first (cmake --build {a.build})")
    os.makedirs(a.out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="pnb-bench-stream-")
    env = dict(os.environ, EGL_LOG_LEVEL="fatal")
    try:
        scene = os.path.join(tmp, "street.pnb")
        made = run([make, scene, "--size", a.size] + ([] if a.no_lod_rocks else ["--lod-rocks"]))
        print(made.stdout.strip())
        file_bytes = os.path.getsize(scene)
        common = [play, scene, "--headless", "--bench", "--no-plot", "-q", "--size", a.size_px, "--fixed-dt"]
        budget = [f"--set", f"stream.budget_mib={a.budget_mib}", "--set", f"stream.upload_mib={a.upload_mib}"]
        results = {}

        def bench(name, extra, cold=False):
            out = os.path.join(a.out, name)
            shutil.rmtree(out, ignore_errors=True)
            if cold:
                drop_caches()
            run(common + ["--out", out] + extra, env=env)
            with open(os.path.join(out, "summary.json")) as f:
                results[name] = json.load(f)
            return results[name]

        full = bench("full-load", ["--no-stream", "--frames", "1"], a.cold)
        first = bench("stream", ["--stream", "--frames", "1"], a.cold)
        path = bench("stream-path", ["--stream", "--frames", str(a.frames)] + budget)
        static = bench("stream-static", ["--stream", "--camera", "0", "--frames", str(a.static_frames)] + budget)
        lod_full = lod = None
        if not a.no_lod_rocks:
            lod_full = bench("lod-full", ["--no-stream", "--frames", str(a.lod_frames), "--set", "lod.force=0"])
            lod = bench("lod", ["--no-stream", "--frames", str(a.lod_frames), "--lod-metrics", "8"])
            with open(os.path.join(a.out, "lod", "quality.csv")) as f:
                quality = list(csv.DictReader(f))
    finally:
        if not a.keep:
            shutil.rmtree(tmp, ignore_errors=True)
        else:
            print(f"kept {tmp}")

    mib = 1 << 20
    ttff_full = full["time_to_first_frame_ms"]["total"]
    ttff_stream = first["time_to_first_frame_ms"]["total"]
    sp, ss = path["streaming"], static["streaming"]
    rss_goal = (1 << 30) + a.budget_mib * mib
    p95_during, p95_after = ss.get("frame_ms_p95_streaming"), ss.get("frame_ms_p95_after")
    rows = [
        ("container", f"{file_bytes / mib:.0f} MiB ({file_bytes / (1 << 30):.2f} GiB)"),
        ("time to first frame, full load", f"{ttff_full:.0f} ms (load {full['load_ms']['total']:.0f} ms), peak RSS {full['peak_rss_bytes'] / mib:.0f} MiB"),
        ("time to first frame, streaming", f"{ttff_stream:.0f} ms after reading {first['streaming']['first_frame_bytes_read'] / mib:.1f} MiB "
                                           f"({100 * first['streaming']['first_frame_bytes_read'] / file_bytes:.2f} %)"),
        ("  ratio (goal <= 1/20)", f"1/{ttff_full / ttff_stream:.1f}"),
        (f"path, {a.frames} frames, budget {a.budget_mib} MiB", f"peak RSS {path['peak_rss_bytes'] / mib:.0f} MiB (goal <= {rss_goal / mib:.0f}), "
                                                          f"peak budgeted storage {sp['peak_bytes'] / mib:.1f} MiB "
                                                          f"(meshes at the end {sp['resident_mesh_bytes'] / mib:.1f} MiB)"),
        ("  uploads", f"{sp['uploaded_bytes'] / mib:.0f} MiB, per frame median {sp['uploaded_bytes_per_frame']['median'] / mib:.2f} / "
                      f"p95 {sp['uploaded_bytes_per_frame']['p95'] / mib:.2f} / max {sp['uploaded_bytes_per_frame']['max'] / mib:.2f} MiB; "
                      f"{sp['evictions']} evictions, {sp['refetches']} re-reads"),
        ("  frame time", f"median {sp['frame_ms_median']:.1f} ms, {sp['stalls']} stalls (> 2x median) of {path['run']['frames']} frames"),
        (f"static view, {a.static_frames} frames", f"streaming for {ss['frames_streaming']} frames; full quality at "
                                                   f"{ss.get('time_to_full_quality_ms', float('nan')):.0f} ms from start"),
        ("  frame-time p95 streaming / after (goal <= 1.5)",
         f"{p95_during:.1f} / {p95_after:.1f} ms = {p95_during / p95_after:.2f}" if p95_during and p95_after else "n/a"),
    ]
    if lod:
        tri, tri_full = lod["triangles"]["sum"], lod_full["triangles"]["sum"]
        psnr = [float(r["lod_psnr_db"]) for r in quality]
        rows += [
            (f"LOD along the path, {a.lod_frames} frames", f"{tri} of {tri_full} triangles at full detail = {100 * tri / tri_full:.1f} %; "
                                                           f"shadow {100 * lod['shadow_triangles']['sum'] / lod_full['shadow_triangles']['sum']:.1f} %"),
            ("  image error against LOD 0", f"PSNR mean {sum(psnr) / len(psnr):.2f} dB, worst {min(psnr):.2f} dB over {len(psnr)} sampled frames"),
        ]
    width = max(len(r[0]) for r in rows)
    for k, v in rows:
        print(f"{k:<{width}}  {v}")
    summary = {"file_bytes": file_bytes, "budget_mib": a.budget_mib, "upload_mib": a.upload_mib, "cold": a.cold,
               "ttff_full_ms": ttff_full, "ttff_stream_ms": ttff_stream, "ttff_ratio": ttff_stream / ttff_full,
               "runs": results}
    with open(os.path.join(a.out, "stream.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(f"wrote {os.path.join(a.out, 'stream.json')}")


if __name__ == "__main__":
    main()
