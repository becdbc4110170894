#!/usr/bin/env python3
"""Read-throughput benchmark of the format library (bench/format_read_bench.cpp): runs
pnb_format_bench, prints Google Benchmark's report, then a table of each read path's rate (median
of the repetitions, run interleaved, with min-max and the coefficient of variation: the spread),
the like-with-like ratios (a copying read against memcpy from the same mapping; a verifying
in-place read against a bare XXH3 pass over the same mapping), and the format goal: uncompressed
read + verify >= 50% of memcpy. Writes OUT/format_read.json (every repetition and the machine
description) and OUT/figures.json (each path's median GB/s and the ratios: pnb-sweep's figures).

The experiment sweep/experiments/format-read.toml runs this; scripts/bench builds and runs that.
  format_read.py --build BUILD --out OUT [--repetitions N] [pnb_format_bench arguments]
Every run regenerates its two 256 MiB test files under BUILD/bench/data/ (a few seconds) and
reads them once, so runs start from the same page-cache state (PNB_BENCH_REUSE_DATA=1 skips
that). The machine is shared and noisy: compare the ratios.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--repetitions", type=int, default=int(os.environ.get("PNB_BENCH_REPETITIONS", "7")))
    # Any other argument goes to pnb_format_bench (e.g. --benchmark_filter='Memcpy|Mmap').
    a, extra = ap.parse_known_args()
    os.makedirs(a.out, exist_ok=True)
    json_path = os.path.join(a.out, "format_read.json")
    # Random interleaving: the repetitions of all benchmarks run in a shuffled order, so the two
    # sides of a like-with-like pair see the same noise from other tenants of the machine.
    r = subprocess.run([os.path.join(a.build, "bench", "pnb_format_bench"),
                        "--benchmark_repetitions=%d" % a.repetitions,
                        "--benchmark_enable_random_interleaving=true", "--benchmark_display_aggregates_only=true",
                        "--benchmark_out=" + json_path, "--benchmark_out_format=json"] + extra)
    if r.returncode != 0:
        sys.exit("format_read: pnb_format_bench failed (exit %d)" % r.returncode)
    doc = json.load(open(json_path))
    rates = {}
    for r in doc["benchmarks"]:
        name = r["run_name"].split("/")[0]
        if r.get("error_occurred"):
            rates[name] = None
        elif r.get("run_type") == "iteration" and rates.get(name, []) is not None:
            rates.setdefault(name, []).append(r["bytes_per_second"])

    labels = [
        ("MemcpyFromMapping", "memcpy from the mapping (pair 1 baseline)"),
        ("LoadIntoOpenOnce", "loadInto, open once (hash + copy)"),
        ("HashFromMapping", "XXH3 over the mapping (pair 2 baseline)"),
        ("MmapVerifyOpenOnce", "load() in place, open once (verify)"),
        ("Memcpy", "memcpy heap to heap (old baseline)"),
        ("MmapVerify", "open + mmap + verify each time"),
        ("MmapLoadInto", "open + mmap + loadInto each time"),
        ("ZstdLoadInto", "zstd file: decompress into caller memory"),
        ("Stream", "streamChunks, read(2) + verify"),
    ]
    ctx = doc.get("context", {})
    print()
    print(f"{ctx.get('num_cpus', '?')} CPUs at {ctx.get('mhz_per_cpu', '?')} MHz; checksums on; "
          f"GB = 10^9 bytes (Google Benchmark's 'G/s' above is GiB/s)")
    print(f"{'read path':<44} {'median GB/s':>11} {'min-max':>13} {'CV':>6}")
    med = {}
    for key, label in labels:
        if key not in rates:
            continue
        xs = rates[key]
        if xs is None:
            print(f"{label:<44} {'error':>11}")
            continue
        med[key] = statistics.median(xs)
        cv = statistics.pstdev(xs) / statistics.mean(xs) if len(xs) > 1 else 0.0
        print(f"{label:<44} {med[key] / 1e9:11.2f} {min(xs) / 1e9:6.2f}-{max(xs) / 1e9:<6.2f} "
              f"{cv:6.1%}")


    def ratio(a, b, text):
        if a in med and b in med:
            ra = [x / med[b] for x in rates[a]]
            print(f"{text}: {med[a] / med[b]:.2f} (per repetition {min(ra):.2f}-{max(ra):.2f})")


    print()
    print("like with like (same mapping, opened once, pre-faulted; median rate ratio):")
    ratio("LoadIntoOpenOnce", "MemcpyFromMapping", "  copying read / memcpy           ")
    ratio("MmapVerifyOpenOnce", "HashFromMapping", "  verifying in-place read / XXH3  ")
    if "MmapVerify" in med and "Memcpy" in med:
        r = med["MmapVerify"] / med["Memcpy"]
        print(f"goal: uncompressed read + verify >= 50% of memcpy: {r:.0%}, "
              f"{'met' if r >= 0.5 else 'NOT met'} (open + verify against heap memcpy, as stated)")

    figures = {"%s GB/s" % k: v / 1e9 for k, v in med.items()}
    for a_, b_ in (("LoadIntoOpenOnce", "MemcpyFromMapping"), ("MmapVerifyOpenOnce", "HashFromMapping"),
                   ("MmapVerify", "Memcpy")):
        if a_ in med and b_ in med:
            figures["%s / %s" % (a_, b_)] = med[a_] / med[b_]
    with open(os.path.join(a.out, "figures.json.tmp"), "w") as f:
        json.dump(figures, f, indent=1)
    os.replace(os.path.join(a.out, "figures.json.tmp"), os.path.join(a.out, "figures.json"))
    print("bench: JSON in format_read.json, figures in figures.json (the output directory)")


if __name__ == "__main__":
    main()
