#!/usr/bin/env python3
"""Load-time comparison runner of scripts/bench-load (issue 13): every figure from a fresh process.

Each measurement is one run of bench/load/pnb_load_probe (one load per process, one JSON line):
  pnb       the player's loadScene() on the .pnb, to GPU-ready
  assimp    ReadFile(Triangulate | JoinIdenticalVertices | GenSmoothNormals) + stb_image decode of
            every texture + GL upload (buffers, vertex arrays, textures with glGenerateMipmap) +
            one simple lit program per material feature set linked, to GPU-ready
  tinygltf  LoadBinaryFromFile / LoadASCIIFromFile with its stb_image decoding + the same upload
  floor     mmap + memcpy of the very files the loader read into freshly allocated memory
N runs of every (configuration, cache state) pair, all pairs of a round in a shuffled order
(fixed seed); page cache warm, and cold: before a cold run the probe evicts every file that
loader reads (fdatasync + posix_fadvise POSIX_FADV_DONTNEED; the probe binary, its shared
libraries and Mesa's on-disk shader cache stay warm).

Scenes: the 1 M-triangle load test (pnb-make-scene load-test; peers read zlib-PNG and JPEG
re-encodes, and an OBJ export with the PNGs), a real model set (Debian's assimp test models:
every glTF2/OBJ one that pnb-convert and the peers all load; the others are listed as skipped,
with the reason), and the user's own files given on the command line.

Output in --out: results.md (tables), results.csv (one row per configuration and cache state),
samples.jsonl (every probe line), load.png (bars: medians with min-max whiskers; each bar's floor
as a black line). --tiny: one run, a small load test and two models, for the ctest that keeps
this script from rotting.
"""
import argparse
import csv
import json
import os
import platform
import random
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

MODELS_DIR = Path("/usr/share/assimp/models")
# --tiny: two small models that every loader reads (one glTF with a texture, one OBJ).
TINY_MODELS = ["glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", "OBJ/spider.obj"]
GOAL_Q_MS = 30.0
GOAL_FLOOR_RATIO = 2.0

INCLUDED = (
    "What each figure includes: **GPU-ready** = from the loader's first call to glFinish "
    "returning, with geometry in GL buffers + vertex arrays, every texture in a GL texture with a "
    "full mip chain, the programs linked; the EGL context is created before it and timed apart. "
    "**pnb**: the player's loadScene (map, verify XXH3 checksums, decode + validate, upload "
    "straight from the mapping with the container's own mips, the scene's programs linked "
    "as pnb-play makes them: from its program binary cache, filled by an untimed run; the peers "
    "compile theirs, with Mesa's shader cache warm for everyone). **assimp**: Importer::ReadFile with Triangulate | JoinIdenticalVertices | "
    "GenSmoothNormals, stb_image decode of every texture a material names (RGBA8), one buffer + "
    "vertex array per mesh, glTextureStorage2D + glGenerateTextureMipmap per texture, one simple "
    "lit program per distinct material feature set (normals, UV, base-colour map, normal map, "
    "alpha mask). **tinygltf**: LoadBinaryFromFile/LoadASCIIFromFile with its stb_image decoding "
    "(RGBA8), each glTF buffer uploaded once as a GL buffer, one vertex array per primitive, "
    "textures and programs as for assimp. **floor**: mmap + memcpy of the same files the loader "
    "read into never-touched memory (the time to have the bytes, nothing else). **process** = "
    "spawn to exit as the runner sees it (includes dynamic linking, the EGL context and "
    "teardown). Warm = files in the page cache (read back, untimed, right before each warm run); **cold = every file that loader reads evicted "
    "with posix_fadvise(POSIX_FADV_DONTNEED) right before the run** (binary, shared libraries "
    "and Mesa's shader cache stay warm).")


def log(msg):
    print(f"bench-load: {msg}", file=sys.stderr, flush=True)


class Runner:
    def __init__(self, args):
        self.bin = Path(args.bin).resolve()
        self.out = Path(args.out).resolve()
        self.probe = self.bin / "bench" / "load" / "pnb_load_probe"
        self.inputs_tool = self.bin / "bench" / "load" / "pnb_load_inputs"
        self.make_scene = self.bin / "assets_src" / "pnb-make-scene"
        self.convert = self.bin / "converter" / "pnb-convert"
        # pnb's programs come from the program binary cache, as in pnb-play; a directory of the
        # benchmark's own, filled by the untimed warm-up run of each configuration.
        self.env = dict(os.environ, EGL_LOG_LEVEL="fatal",
                        PNB_PROGRAM_CACHE_DIR=str(self.out / "program-cache"))
        # Renamed to samples.jsonl when every run is in (finish_samples).
        self.samples = open(self.out / "samples.jsonl.tmp", "w")

    def finish_samples(self):
        self.samples.close()
        os.replace(self.out / "samples.jsonl.tmp", self.out / "samples.jsonl")

    def run_probe(self, argv, cache="warm", files=None):
        """One fresh probe process; returns its JSON line plus the runner's own timings."""
        evicted = None
        if cache == "warm" and files:
            # Rounds are shuffled: a cold run of this file (or of another loader reading it) may
            # just have evicted it. Read it back, untimed, so that "warm" means warm.
            for path in files:
                with open(path, "rb") as f:
                    while f.read(1 << 22):
                        pass
        if cache == "cold":
            ev = subprocess.run([str(self.probe), "--evict", *files], capture_output=True,
                                text=True, env=self.env, check=True)
            evicted = json.loads(ev.stdout)
        env = dict(self.env)
        spawn = time.monotonic_ns()
        env["PNB_PROBE_SPAWN_NS"] = str(spawn)
        p = subprocess.run([str(self.probe), *argv], capture_output=True, text=True, env=env)
        outer_ms = (time.monotonic_ns() - spawn) / 1e6
        lines = [l for l in p.stdout.splitlines() if l.startswith("{")]
        if not lines:
            return {"ok": False, "error": (p.stderr.strip() or f"exit code {p.returncode}")[-400:]}
        d = json.loads(lines[-1])
        d["outer_ms"] = outer_ms
        if "inner_ms" in d:
            d["start_exit_ms"] = outer_ms - d["inner_ms"]  # process start + exit, as seen outside
        if evicted is not None:
            d["evict"] = evicted
        return d

    def tool(self, argv, what):
        p = subprocess.run([str(a) for a in argv], capture_output=True, text=True, env=self.env)
        if p.returncode != 0:
            return (p.stderr.strip() or p.stdout.strip() or f"exit code {p.returncode}") \
                .splitlines()[-1][:300]
        return None


def replace_atomically(path, write):
    """write(temporary path), then rename over `path`: a reader never sees half a file."""
    tmp = path.with_name(path.name + ".tmp")
    write(tmp)
    os.replace(tmp, path)


def newer(out, *inputs):
    return out.exists() and all(out.stat().st_mtime >= Path(i).stat().st_mtime for i in inputs)


def make_load_test(r, tiny):
    """The load-test scene and its sources; returns (configs, note)."""
    d = r.out / "load-test"
    d.mkdir(parents=True, exist_ok=True)
    glb = d / "load-test.generated.glb"
    args = ["load-test", glb]
    if tiny:
        args += ["--triangles", "20000", "--texture-size", "64"]
    stamp = d / "generated-with.txt"
    if not (newer(glb, r.make_scene) and stamp.exists() and stamp.read_text() == str(args)):
        log("generating load-test" + (" (tiny)" if tiny else ""))
        if err := r.tool([r.make_scene, *args], "pnb-make-scene"):
            sys.exit(f"bench-load: pnb-make-scene failed: {err}")
        stamp.write_text(str(args))
    png, jpg, obj = d / "load-test.glb", d / "load-test.jpeg.glb", d / "obj" / "load-test.obj"
    steps = [
        (png, [r.inputs_tool, "--reencode-glb", glb, png, "png"], [glb, r.inputs_tool]),
        (jpg, [r.inputs_tool, "--reencode-glb", glb, jpg, "jpeg"], [glb, r.inputs_tool]),
        (obj, [r.inputs_tool, "--export-obj", png, obj], [png, r.inputs_tool]),
        (d / "load-test.pnb", [r.convert, png, "-o", d / "load-test.pnb", "-q", "--no-sidecar"],
         [png, r.convert]),
        (d / "load-test.q.pnb", [r.convert, png, "-o", d / "load-test.q.pnb", "-q", "--no-sidecar",
                                 "--quantize", "--compress-textures"], [png, r.convert]),
    ]
    for out, argv, deps in steps:
        if not newer(out, *deps):
            log(f"making {out.name}")
            if out == obj:  # OBJ + MTL + PNG files: made in a fresh directory, then renamed
                tmp = d / "obj.tmp"
                shutil.rmtree(tmp, ignore_errors=True)
                tmp.mkdir()
                argv = argv[:-1] + [tmp / obj.name]
            if err := r.tool(argv, out.name):
                sys.exit(f"bench-load: making {out} failed: {err}")
            if out == obj:
                shutil.rmtree(obj.parent, ignore_errors=True)
                os.replace(tmp, obj.parent)
    s = "load-test"
    return [
        dict(scene=s, label="pnb load-test.q.pnb (--quantize --compress-textures)", loader="pnb",
             file=d / "load-test.q.pnb", goal_q=True),
        dict(scene=s, label="pnb load-test.pnb (converter defaults)", loader="pnb",
             file=d / "load-test.pnb"),
        dict(scene=s, label="assimp load-test.obj (+ MTL, zlib PNGs)", loader="assimp", file=obj),
        dict(scene=s, label="assimp load-test.glb (zlib PNGs)", loader="assimp", file=png),
        dict(scene=s, label="assimp load-test.jpeg.glb (JPEG q90)", loader="assimp", file=jpg),
        dict(scene=s, label="tinygltf load-test.glb (zlib PNGs)", loader="tinygltf", file=png),
        dict(scene=s, label="tinygltf load-test.jpeg.glb (JPEG q90)", loader="tinygltf", file=jpg),
    ]


def source_configs(r, scene, src, pnb, name):
    """pnb + the peers for one source file (converted to `pnb`), or the reason it is skipped."""
    if not newer(pnb, src, r.convert):
        if err := r.tool([r.convert, src, "-o", pnb, "-q", "--no-sidecar"], "pnb-convert"):
            return None, f"pnb-convert: {err}"
    loaders = ["pnb", "assimp"]
    if src.suffix.lower() in (".gltf", ".glb"):
        loaders.append("tinygltf")
    return [dict(scene=scene, label=f"{l} {name}", loader=l, file=pnb if l == "pnb" else src,
                 model=name) for l in loaders], None


def loads_everywhere(r, configs):
    """None if every loader loads it (each once, untimed), else why not."""
    for c in configs:
        d = r.run_probe(["--loader", c["loader"], str(c["file"])])
        if not d.get("ok"):
            return f"{c['loader']}: {d.get('error', '?')}"
        if d.get("triangles", 0) == 0:
            return f"{c['loader']}: loads no triangles"
    return None


def make_model_set(r, tiny):
    candidates = sorted(p.relative_to(MODELS_DIR).as_posix() for p in MODELS_DIR.glob("glTF2/**/*")
                        if p.suffix.lower() in (".gltf", ".glb"))
    candidates += sorted(p.relative_to(MODELS_DIR).as_posix() for p in MODELS_DIR.glob("OBJ/*.obj"))
    if tiny:
        candidates = [c for c in TINY_MODELS if (MODELS_DIR / c).exists()]
    pnb_dir = r.out / "models"
    pnb_dir.mkdir(parents=True, exist_ok=True)
    configs, skipped = [], []
    for rel in candidates:
        # Unique .pnb names: the set has several BoxTextured.gltf in different folders.
        pnb = pnb_dir / (rel.replace("/", "__") + ".pnb")
        cs, why = source_configs(r, "models", MODELS_DIR / rel, pnb, rel)
        if cs is not None:
            why = loads_everywhere(r, cs)
        if why is None:
            configs += cs
        else:
            skipped.append((rel, why.replace("\n", " ")[:200]))
    return configs, skipped


def make_user_files(r, files):
    configs, skipped = [], []
    pnb_dir = r.out / "user"
    pnb_dir.mkdir(parents=True, exist_ok=True)
    for f in files:
        src = Path(f).resolve()
        if not src.exists():
            skipped.append((f, "no such file"))
            continue
        cs, why = source_configs(r, "user:" + src.name, src, pnb_dir / (src.name + ".pnb"),
                                 src.name)
        if cs is None:
            skipped.append((f, why))
            continue
        configs += cs
    return configs, skipped


def quantiles(xs):
    xs = sorted(xs)
    if len(xs) == 1:
        return xs[0], xs[0]
    q = statistics.quantiles(xs, n=4, method="inclusive")
    return q[0], q[2]


def summarise(samples, key):
    xs = [s[key] for s in samples if key in s]
    if not xs:
        return None
    q1, q3 = quantiles(xs)
    return dict(median=statistics.median(xs), min=min(xs), max=max(xs), q1=q1, q3=q3, n=len(xs))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", required=True, help="the release build directory")
    ap.add_argument("--out", required=True, help="output directory")
    ap.add_argument("--runs", type=int, default=7, help="fresh-process runs of each figure")
    ap.add_argument("--tiny", action="store_true", help="one run, small scene, two models")
    ap.add_argument("--no-load-test", action="store_true")
    ap.add_argument("--no-models", action="store_true")
    ap.add_argument("--seed", type=int, default=13)
    ap.add_argument("files", nargs="*", help="your own scenes (.gltf/.glb/.obj/...)")
    args = ap.parse_args()
    if args.tiny:
        args.runs = 1
    if args.runs < 1:
        sys.exit("bench-load: --runs must be at least 1")
    Path(args.out).mkdir(parents=True, exist_ok=True)
    r = Runner(args)
    for tool in (r.probe, r.inputs_tool, r.make_scene, r.convert):
        if not tool.exists():
            sys.exit(f"bench-load: {tool} is missing (build the release preset first)")

    configs, skipped = [], []
    if not args.no_load_test:
        configs += make_load_test(r, args.tiny)
    if not args.no_models:
        log("selecting the model set (each candidate converted and loaded once by every loader)")
        c, s = make_model_set(r, args.tiny)
        configs += c
        skipped += s
    if args.files:
        c, s = make_user_files(r, args.files)
        configs += c
        skipped += s

    # Warm-up: each configuration once, untimed (page cache, Mesa's shader cache); it also
    # records which files the loader reads, which gives the floor's file set and what to evict.
    log(f"warm-up: {len(configs)} configurations")
    kept = []
    for c in configs:
        d = r.run_probe(["--loader", c["loader"], str(c["file"])])
        if not d.get("ok"):
            skipped.append((c["label"], d.get("error", "?")))
            continue
        c["files"] = tuple(sorted(f["path"] for f in d["files"]))
        c["bytes"] = sum(f["bytes"] for f in d["files"])
        for k in ("triangles", "textures", "mip_levels", "programs"):
            c[k] = d.get(k, 0)
        kept.append(c)
    configs = kept
    floors = {}
    for c in configs:
        key = (c["scene"], c["files"])
        if key not in floors:
            n = len(c["files"])
            what = Path(c["file"]).name + (f" + {n - 1} files it names" if n > 1 else "")
            floors[key] = dict(scene=c["scene"], label=f"floor {what}", loader="floor",
                               files=c["files"], bytes=c["bytes"], model=c.get("model"))
        c["floor"] = floors[key]
    everything = configs + list(floors.values())

    rng = random.Random(args.seed)
    caches = ("warm", "cold")
    results = {(id(c), cache): [] for c in everything for cache in caches}
    total = len(everything) * len(caches) * args.runs
    log(f"{total} fresh-process runs: {len(everything)} configurations x warm/cold x {args.runs}")
    done = 0
    started = time.monotonic()
    for run in range(args.runs):
        tasks = [(c, cache) for c in everything for cache in caches]
        rng.shuffle(tasks)
        for c, cache in tasks:
            argv = ["--loader", c["loader"]] + (list(c["files"]) if c["loader"] == "floor"
                                                else [str(c["file"])])
            d = r.run_probe(argv, cache, c["files"])
            d.update(run=run, cache=cache, label=c["label"], scene=c["scene"])
            r.samples.write(json.dumps(d) + "\n")
            if not d.get("ok"):
                sys.exit(f"bench-load: {c['label']} ({cache}) failed: {d.get('error')}")
            results[(id(c), cache)].append(d)
            done += 1
        log(f"round {run + 1}/{args.runs} done ({done}/{total} runs, "
            f"{time.monotonic() - started:.0f} s)")
    r.finish_samples()

    rows = []
    for c in everything:
        for cache in caches:
            ss = results[(id(c), cache)]
            row = dict(scene=c["scene"], model=c.get("model") or "", label=c["label"],
                       loader=c["loader"], cache=cache, runs=len(ss), input_bytes=c["bytes"],
                       files=len(c["files"]))
            for k in ("triangles", "textures", "mip_levels", "programs"):
                row[k] = c.get(k, 0)
            for key in ("gpu_ready_ms", "outer_ms", "start_exit_ms", "exec_to_main_ms",
                        "context_ms", "teardown_ms"):
                st = summarise(ss, key)
                if st:
                    for k, v in st.items():
                        if k != "n":
                            row[f"{key}_{k}"] = round(v, 3)
            phases = {}
            for s in ss:
                for k, v in s.get("phases", {}).items():
                    phases.setdefault(k, []).append(v)
            row["phases"] = " ".join(f"{k}={statistics.median(v):.2f}" for k, v in phases.items())
            if cache == "cold":
                row["resident_after_evict_bytes_max"] = max(
                    s.get("evict", {}).get("resident_bytes_after", 0) for s in ss)
            if c["loader"] != "floor":
                fl = statistics.median(x["gpu_ready_ms"] for x in results[(id(c["floor"]), cache)])
                row["floor_ms"] = round(fl, 3)
                row["x_floor"] = round(row["gpu_ready_ms_median"] / fl, 2) if fl > 0 else None
            rows.append(row)

    write_outputs(r.out, args, rows, skipped, configs)


def fmt_range(row, key):
    return (f"{row[key + '_median']:.1f} ({row[key + '_min']:.1f}–{row[key + '_max']:.1f}; "
            f"IQR {row[key + '_q1']:.1f}–{row[key + '_q3']:.1f})")


def machine():
    cpu = "unknown"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{cpu}, {os.cpu_count()} cores, {platform.system()} {platform.release()}"


def write_outputs(out, args, rows, skipped, configs):
    fields = []
    for row in rows:
        for k in row:
            if k not in fields:
                fields.append(k)
    def write_csv(path):
        with open(path, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=fields)
            w.writeheader()
            w.writerows(rows)
    replace_atomically(out / "results.csv", write_csv)

    gl, upload_pages = "unknown", set()
    for line in open(out / "samples.jsonl"):
        d = json.loads(line)
        if "gl" in d and gl == "unknown":
            gl = f"{d['gl']['renderer']}, {d['gl']['version']}"
        pages = d.get("upload_pages", "")
        if pages.startswith("4 KiB pages ("):  # "4 KiB pages (why)"
            upload_pages.add("4 KiB pages: " + pages[len("4 KiB pages ("):].rstrip(")"))
        elif "in 2 MiB pages" in pages:  # "N MiB in 2 MiB pages"; small scenes use no heap
            upload_pages.add("2 MiB pages")
    md = []
    p = md.append
    p("# scripts/bench-load")
    p("")
    p(f"Measured {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} on {machine()}; GL: {gl}.")
    p(f"Command: `scripts/bench-load{' --tiny' if args.tiny else ''} --runs {args.runs}"
      f"{' ' + ' '.join(args.files) if args.files else ''}`. Every figure is a fresh process; "
      f"{args.runs} runs of each (configuration, cache) pair, interleaved in a shuffled order. "
      "Cells: median (min–max; IQR q1–q3), ms.")
    if upload_pages:
        p(f"pnb's upload heap on this machine (docs/PLAYER.md, Upload memory): "
          f"{'; '.join(sorted(upload_pages))}.")
    p("")
    p(INCLUDED)
    p("")
    by_scene = {}
    for row in rows:
        by_scene.setdefault(row["scene"], []).append(row)
    for scene, rs in by_scene.items():
        if scene == "models":
            continue
        p(f"## {scene}")
        p("")
        p("| loader and input | MiB read | cache | **GPU-ready** | × floor | floor | phases (median) "
          "| process (spawn to exit) | start + exit | of which exec→main | EGL context |")
        p("|---|--:|---|--:|--:|--:|---|--:|--:|--:|--:|")
        for row in rs:
            if row["loader"] == "floor":
                continue
            p(f"| {row['label']} | {row['input_bytes'] / 2**20:.1f} | {row['cache']} | "
              f"**{fmt_range(row, 'gpu_ready_ms')}** | {row['x_floor']:.2f} | "
              f"{row['floor_ms']:.1f} | {row['phases']} | {row['outer_ms_median']:.0f} | "
              f"{row['start_exit_ms_median']:.0f} | {row.get('exec_to_main_ms_median', 0):.0f} | "
              f"{row.get('context_ms_median', 0):.0f} |")
        p("")
        p("Floors (mmap + copy of the same files):")
        p("")
        for row in rs:
            if row["loader"] == "floor":
                p(f"- {row['label']} ({row['input_bytes'] / 2**20:.1f} MiB, {row['cache']}): "
                  f"{fmt_range(row, 'gpu_ready_ms')}")
        p("")
    models = [r for r in rows if r["scene"] == "models" and r["loader"] != "floor"]
    if models:
        names = sorted({r["model"] for r in models})
        p(f"## Model set: {len(names)} assimp test models (Debian assimp-testmodels)")
        p("")
        p("GPU-ready medians, ms (× its floor); a dash: that loader does not read the format.")
        p("")
        p("| model | cache | pnb | assimp | tinygltf |")
        p("|---|---|--:|--:|--:|")
        for name in names:
            for cache in ("warm", "cold"):
                cells = []
                for loader in ("pnb", "assimp", "tinygltf"):
                    m = [r for r in models if r["model"] == name and r["cache"] == cache
                         and r["loader"] == loader]
                    cells.append(f"{m[0]['gpu_ready_ms_median']:.1f} ({m[0]['x_floor']:.1f}×)"
                                 if m else "–")
                p(f"| {name} | {cache} | " + " | ".join(cells) + " |")
        p("")
        for subset in ("glTF2", "OBJ"):
            for cache in ("warm", "cold"):
                sums = {}
                for loader in ("pnb", "assimp", "tinygltf"):
                    m = [r for r in models if r["cache"] == cache and r["loader"] == loader
                         and r["model"].startswith(subset + "/")]
                    if m:
                        sums[loader] = (sum(r["gpu_ready_ms_median"] for r in m), len(m))
                if sums:
                    p(f"Sum of medians, {subset} models, {cache}: " + "; ".join(
                        f"{k} {v:.0f} ms over {n}" for k, (v, n) in sums.items()) + ".")
        p("")
    if skipped:
        p("## Skipped")
        p("")
        for what, why in skipped:
            p(f"- `{what}`: {why}")
        p("")
    p("## Goals (pnb GPU-ready, fresh process)")
    p("")
    goals = []
    for row in rows:
        if row["loader"] != "pnb":
            continue
        cfg = next((c for c in configs if c["label"] == row["label"]), {})
        ok = row["x_floor"] is not None and row["x_floor"] <= GOAL_FLOOR_RATIO
        goals.append((row, "≤ 2× floor", ok))
        if cfg.get("goal_q") and not args.tiny:
            goals.append((row, f"≤ {GOAL_Q_MS:.0f} ms", row["gpu_ready_ms_median"] <= GOAL_Q_MS))
    for row, goal, ok in goals:
        if row["scene"] == "models":
            continue
        p(f"- {row['label']}, {row['cache']}: {goal}: **{'met' if ok else 'MISSED'}** "
          f"({row['gpu_ready_ms_median']:.1f} ms, {row['x_floor']:.2f}× its floor of "
          f"{row['floor_ms']:.1f} ms)")
    for cache in ("warm", "cold"):
        m = [(row, ok) for row, goal, ok in goals if row["scene"] == "models"
             and row["cache"] == cache]
        if m:
            ratios = sorted(row["x_floor"] for row, ok in m)
            p(f"- model set, {cache}: ≤ 2× floor met for **{sum(ok for _, ok in m)} of {len(m)}** "
              f"models (× floor: median {statistics.median(ratios):.1f}, "
              f"{ratios[0]:.1f}–{ratios[-1]:.1f}; a small model's floor is a fraction of a "
              "millisecond, its load mostly program compilation)")
    p("")
    p("The machine is shared and noisy: compare ratios within one run, not absolute times "
      "across runs.")
    text = "\n".join(md) + "\n"
    replace_atomically(out / "results.md", lambda p: p.write_text(text))
    print(text)
    try:
        plot(out, rows)
    except ImportError:
        log("matplotlib is missing: no load.png (python3-matplotlib, scripts/setup installs it)")
    log(f"results in {out}/results.md, results.csv, samples.jsonl, load.png")


def plot(out, rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    groups = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        rs = [r for r in rows if r["scene"] == scene and r["loader"] != "floor"]
        if scene == "models":  # per subset and loader: the sum over the models (and floors)
            agg = []
            for subset in ("glTF2", "OBJ"):
                for loader in ("pnb", "assimp", "tinygltf"):
                    for cache in ("warm", "cold"):
                        m = [r for r in rs if r["loader"] == loader and r["cache"] == cache
                             and r["model"].startswith(subset + "/")]
                        if not m:
                            continue
                        agg.append(dict(
                            label=f"{loader} (sum over {len(m)} {subset} models)", cache=cache,
                            gpu_ready_ms_median=sum(r["gpu_ready_ms_median"] for r in m),
                            gpu_ready_ms_min=sum(r["gpu_ready_ms_min"] for r in m),
                            gpu_ready_ms_max=sum(r["gpu_ready_ms_max"] for r in m),
                            floor_ms=sum(r["floor_ms"] for r in m)))
            rs = agg
        if rs:
            groups.append((scene, rs))
    fig, axes = plt.subplots(len(groups), 1, figsize=(11, 3.2 + 0.0 * len(groups)),
                             squeeze=False) if len(groups) == 1 else \
        plt.subplots(len(groups), 1, figsize=(11, 3.6 * len(groups)), squeeze=False)
    for ax, (scene, rs) in zip(axes[:, 0], groups):
        labels = list(dict.fromkeys(r["label"] for r in rs))
        for i, label in enumerate(labels):
            for j, cache in enumerate(("warm", "cold")):
                m = [r for r in rs if r["label"] == label and r["cache"] == cache]
                if not m:
                    continue
                r = m[0]
                x = i + (j - 0.5) * 0.38
                med = r["gpu_ready_ms_median"]
                ax.bar(x, med, width=0.36, color="tab:blue" if cache == "warm" else "tab:orange",
                       yerr=[[med - r["gpu_ready_ms_min"]], [r["gpu_ready_ms_max"] - med]],
                       capsize=2, label=cache if i == 0 else None)
                ax.hlines(r["floor_ms"], x - 0.18, x + 0.18, colors="black", linewidth=2,
                          label="floor (mmap + copy of the same files)" if i == 0 and j == 0
                          else None)
        ax.set_xticks(range(len(labels)))
        ax.set_xticklabels([l.replace(" (", "\n(") for l in labels], fontsize=7)
        ax.set_yscale("log")
        ax.set_ylabel("GPU-ready, ms (log)")
        ax.set_title(f"{scene}: median of fresh processes, whiskers min–max", fontsize=9)
        ax.legend(fontsize=7)
    fig.tight_layout()
    replace_atomically(out / "load.png", lambda p: fig.savefig(p, dpi=110, format="png"))


if __name__ == "__main__":
    main()
