#!/usr/bin/env python3
"""Conformance on the Khronos glTF sample models (issue 38): convert -> play headless -> judge the
IMAGE by the model's own criterion (its README in ../shared/khronos/<Model>/), not the exit code.

Usage:
  khronos_conformance.py --convert PNB_CONVERT --play PNB_PLAY --models DIR --out DIR
                         [--json FILE] [MODEL...]       (no MODEL: every model in the registry)
  khronos_conformance.py --list                         (the registry: model, criterion)
  khronos_conformance.py --models DIR --check-registry  (every model in DIR has a criterion)

Exit status: 0 every named model passes, 1 one fails, 2 usage error or a model with no criterion,
77 (CTest's SKIP_RETURN_CODE) when DIR or a named model's folder does not exist: the message says
where it looked. Renders, the camera paths and the tools' output are kept under --out/<Model>/.

Views: the harness does not use pnb-convert's default camera (its framing is being changed): each
render looks at the bounds read from the glTF file (gltfview.py), or through the model's own
camera where the criterion is about it. Sizes are 256..512 px to keep llvmpipe fast.
"""

import argparse
import json
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import gltfview  # noqa: E402
import imagecheck as ic  # noqa: E402
from pngimage import read_png  # noqa: E402

SKIP = 77
REGISTRY = {}


def model(name, criterion, variant=None):
    """Registers a criterion: fn(ctx) calls ctx.check(ok, message) for each part."""
    def wrap(fn):
        REGISTRY[name] = dict(name=name, criterion=criterion, variant=variant, fn=fn)
        return fn
    return wrap


class Failed(Exception):
    """A step the criterion needs did not happen (conversion refused, player failed)."""


class Ctx:
    def __init__(self, name, models_dir, out_dir, convert, play, variant=None):
        self.name = name
        self.dir = os.path.join(models_dir, name)
        self.out = os.path.join(out_dir, name)
        os.makedirs(self.out, exist_ok=True)
        self.convert_exe, self.play_exe = convert, play
        self.src = find_source(self.dir, variant)
        self.pnb = os.path.join(self.out, name + ".pnb")
        self.results = []
        self.images = {}
        self.renders = []
        self.convert_rc = None
        self.convert_text = ""
        self.summary = {}

    def check(self, ok, message):
        self.results.append((bool(ok), message))
        return bool(ok)

    # --- the tools ------------------------------------------------------------------------
    def convert(self):
        if self.convert_rc is not None:
            return self.convert_rc
        summary = os.path.join(self.out, "summary.json")
        if os.path.exists(summary):
            os.remove(summary)
        cmd = [self.convert_exe, self.src, "-o", self.pnb, "--summary-json", summary]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
        self.convert_rc = r.returncode
        self.convert_text = r.stdout + r.stderr
        with open(os.path.join(self.out, "convert.txt"), "w") as f:
            f.write("$ " + " ".join(cmd) + "\n" + self.convert_text + f"exit {r.returncode}\n")
        if os.path.exists(summary):
            with open(summary) as f:
                self.summary = json.load(f)
        return self.convert_rc

    def require_converted(self):
        rc = self.convert()
        if rc != 0:
            last = [l for l in self.convert_text.splitlines() if l.strip()][-1:] or ["(no output)"]
            raise Failed(f"pnb-convert exit {rc}: {last[0].strip()}")

    def render(self, label, direction=(0, 0, 1), camera=None, size=(384, 288), settings=(),
               background=False, mask=False):
        """Renders frame 0 and returns the image. The view is a still camera path fitted to the
        file's bounds along -direction, or the container's camera `camera`. background=False
        adds ibl.background=false (a uniform background to tell the model from; the lighting
        keeps any environment); mask=True renders debug.view=normal: black where no surface is."""
        key = (label, mask)
        if key in self.images:
            return self.images[key]
        self.require_converted()
        w, h = size
        args = [self.play_exe, self.pnb, "--headless", "--frame", "0", "--size", f"{w}x{h}"]
        if camera is not None:
            args += ["--camera", str(camera)]
        else:
            path = os.path.join(self.out, f"{label}.path.json")
            with open(path, "w") as f:
                json.dump(gltfview.camera_path(self.src, direction=direction, aspect=w / h), f)
            args += ["--path", path]
        sets = list(settings)
        if not background or mask:
            sets.append("ibl.background=false")
        if mask:
            sets.append("debug.view=normal")
        for s in sets:
            args += ["--set", s]
        png = os.path.join(self.out, f"{label}{'.mask' if mask else ''}.png")
        if os.path.exists(png):
            os.remove(png)
        args += ["--screenshot", png]
        env = dict(os.environ, EGL_LOG_LEVEL="fatal")
        r = subprocess.run(args, capture_output=True, text=True, timeout=300, env=env)
        with open(os.path.join(self.out, f"{label}{'.mask' if mask else ''}.play.txt"), "w") as f:
            f.write("$ " + " ".join(args) + "\n" + r.stdout + r.stderr + f"exit {r.returncode}\n")
        if r.returncode != 0 or not os.path.exists(png):
            err = [l for l in (r.stderr or r.stdout).splitlines() if l.strip()][-1:] or ["?"]
            raise Failed(f"pnb-play exit {r.returncode} ({label}): {err[0].strip()}")
        img = read_png(png)
        self.images[key] = img
        if not mask:
            self.renders.append(png)
        return img

    def mask(self, label, **view):
        """Where a surface is, from the normal debug view of the same view."""
        img = self.render(label, mask=True, **view)
        return ic.Mask.where(img, lambda r, g, b: r > 6 or g > 6 or b > 6)

    def summary_mentions(self, *words):
        text = self.convert_text.lower()
        return all(w.lower() in text for w in words)


def find_source(model_dir, variant=None):
    order = [variant] if variant else ["glTF-Binary", "glTF", "glTF-KTX-BasisU", "glTF-Embedded"]
    for v in order:
        d = os.path.join(model_dir, v)
        if os.path.isdir(d):
            for f in sorted(os.listdir(d)):
                if f.endswith((".glb", ".gltf")):
                    return os.path.join(d, f)
    raise Failed(f"no .glb/.gltf in {model_dir} ({', '.join(order)})")


# --- shared criteria -----------------------------------------------------------------------------

def colour_pixels(img, mask, name, **kw):
    px = img.px
    out = []
    for i in range(img.w * img.h):
        if mask is None or mask.bits[i]:
            if ic.hue_class(px[3 * i], px[3 * i + 1], px[3 * i + 2], **kw) == name:
                out.append(i)
    return out


def colour_mask(img, names, **kw):
    names = (names,) if isinstance(names, str) else names
    return ic.Mask.where(img, lambda r, g, b: ic.hue_class(r, g, b, **kw) in names)


def converts_and_plays(ctx, min_coverage=0.01, **view):
    """The conversion succeeds, the player renders, and the model covers some of the frame."""
    m = ctx.mask("view", **view)
    frac = m.count() / float(m.w * m.h)
    ctx.check(frac >= min_coverage, f"model covers {100 * frac:.1f} % of the frame (>= {100 * min_coverage:.0f} %)")
    ctx.render("view", **view)
    return m


def summary_names(ctx, feature, patterns):
    """The summary's "not rendered" list (--summary-json not_rendered) names the feature exactly
    once, with what the player draws instead; and pnb-convert prints it."""
    lines = ctx.summary.get("not_rendered", [])
    hit = [l for l in lines if any(re.match(p, l, re.I) for p in patterns)]
    ctx.check(len(hit) == 1 and ": " in hit[0] and hit[0] in ctx.convert_text,
              f"the summary names {feature} once with its fallback (what the player does not "
              f"draw): {hit if hit else lines}")


def summary_plays(ctx, feature, pattern):
    """pnb-convert's summary counts the feature among what the deform pass plays (issue 42), and
    its "not rendered" list no longer names skins, animations or morph targets."""
    dropped = [l for l in ctx.summary.get("not_rendered", [])
               if re.match(r"(skins|animations|morph)", l, re.I)]
    line = next((l for l in ctx.convert_text.splitlines() if "played by the deform pass" in l), "")
    ctx.check(bool(re.search(pattern, line)) and not dropped,
              f"the summary plays {feature}: {line.strip() or 'no deform line'}"
              f"{'; not rendered: ' + str(dropped) if dropped else ''}")


def no_red_marks(ctx, img, mask, what, limit=0.002):
    red = colour_pixels(img, mask, "red", min_sat=0.5, min_val=0.12)  # also a red X in shade
    area = max(mask.count(), 1)
    ctx.check(len(red) <= limit * area,
              f"{what}: red failure marks cover {100 * len(red) / area:.2f} % of the model "
              f"(<= {100 * limit:.1f} %)")
    return red


def lit_directions(ctx, img, regions, what, max_spread=60.0, min_offset=0.05, inner=None):
    """Every region lit from the same side: the direction of its luminance-weighted centroid's
    offset within max_spread degrees of the regions' mean direction."""
    dirs = []
    for r in regions:
        dx, dy, mag = ic.lit_side(img, r, inner)
        if mag >= min_offset:
            dirs.append((dx, dy, r))
    if not ctx.check(len(dirs) >= 2, f"{what}: {len(dirs)} regions with a measurable lit side (>= 2)"):
        return
    mx = sum(d[0] / (d[0] ** 2 + d[1] ** 2) ** 0.5 for d in dirs)
    my = sum(d[1] / (d[0] ** 2 + d[1] ** 2) ** 0.5 for d in dirs)
    worst = max(dirs, key=lambda d: ic.angle_between((d[0], d[1]), (mx, my)))
    angle = ic.angle_between((worst[0], worst[1]), (mx, my))
    off = sum(1 for d in dirs if ic.angle_between((d[0], d[1]), (mx, my)) > max_spread)
    ctx.check(off == 0, f"{what}: {off} of {len(dirs)} lit from another side (worst "
              f"{angle:.0f} deg from the mean direction at ({worst[2].cx:.0f}, {worst[2].cy:.0f}); "
              f"<= {max_spread:.0f} deg)")


# --- the models ----------------------------------------------------------------------------------

@model("TextureTransformTest",
       "KHR_texture_transform: in the rotation, scale and all-three tiles the arrow points at the "
       "green marker (not yellow: not applied, not red: wrong way); the offset tiles show their "
       "check, not the yellow 'not applied' image")
def _texture_transform(ctx):
    view = dict(size=(512, 384))
    img = ctx.render("front", **view)
    model_mask = ctx.mask("front", **view)
    bb = model_mask.bbox()
    mid = (bb[1] + bb[3]) / 2
    # Arrows: dark regions in the lower half that do not touch the image's border.
    dark = ic.Mask.where(img, lambda r, g, b: ic.lum(r, g, b) < 0.12)
    for i in range(img.w * img.h):
        if not model_mask.bits[i]:
            dark.bits[i] = 0
    arrows = [a for a in dark.components(min_size=40) if a.cy > mid and a.axis()[1] > 3 * a.axis()[2]]
    markers = []
    for colour in ("green", "yellow", "red"):
        cm = colour_mask(img, colour, min_sat=0.5, min_val=0.3)
        markers += [(colour, r) for r in cm.components(min_size=6) if r.cy > mid]
    if not ctx.check(len(arrows) == 3, f"{len(arrows)} arrows found in the lower row (3)"):
        return
    for a in sorted(arrows, key=lambda a: a.cx):
        tile = {a.cx < bb[0] + (bb[2] - bb[0]) / 3: "rotation",
                a.cx > bb[0] + 2 * (bb[2] - bb[0]) / 3: "all"}.get(True, "scale")
        d = a.pointing()
        near = [(colour, r) for colour, r in markers
                if abs(r.cx - a.cx) < (bb[2] - bb[0]) / 4]
        best = None
        for colour, r in near:
            ang = ic.angle_between(d, (r.cx - a.cx, r.cy - a.cy))
            if best is None or ang < best[0]:
                best = (ang, colour)
        ctx.check(best and best[1] == "green" and best[0] < 20,
                  f"{tile} tile: the arrow points at the "
                  + (f"{best[1]} marker ({best[0]:.0f} deg off)" if best else "no marker"))
    top = [i for i in range(img.w * img.h) if model_mask.bits[i] and i // img.w < mid]
    yellow = colour_pixels(img, None, "yellow", min_sat=0.5)
    yellow_top = [i for i in yellow if i // img.w < mid]
    ctx.check(len(yellow_top) < 0.05 * len(top),
              f"offset tiles: yellow 'offset not applied' covers {100 * len(yellow_top) / max(len(top), 1):.1f} % of the top row (< 5 %)")


@model("TextureTransformMultiTest",
       "KHR_texture_transform on every input and on TEXCOORD_1: in each row with a visible "
       "check, the UV 0 and UV 1 tiles look like the Sample tile (luma correlation >= 0.6)")
def _texture_transform_multi(ctx):
    view = dict(size=(384, 512))
    img = ctx.render("front", **view)
    m = ctx.mask("front", **view)
    # Tiles: light squares in the right part of the board; labels are the light boxes on the left.
    light = ic.Mask.where(img, lambda r, g, b: ic.lum(r, g, b) > 0.35 and not (b > r + 60))
    bb = m.bbox()
    tiles = [t for t in light.components(min_size=60)
             if t.cx > bb[0] + 0.45 * (bb[2] - bb[0]) and 0.6 < t.width / max(t.height, 1) < 1.6]
    rows = {}
    for t in sorted(tiles, key=lambda t: t.cy):
        key = next((k for k in rows if abs(k - t.cy) < t.height / 2), t.cy)
        rows.setdefault(key, []).append(t)
    compared = 0
    for cy, row in sorted(rows.items()):
        if len(row) != 3:
            continue
        row.sort(key=lambda t: t.cx)
        n = 8
        grids = [ic.resample_lum(img, (t.x0, t.y0, t.x1, t.y1), n) for t in row]
        sample = grids[2]
        mean = sum(sample) / len(sample)
        if max(sample) - min(sample) < 0.25 or mean <= 0:
            continue  # low-contrast row (no visible check in the Sample tile)
        compared += 1
        for label, g in (("UV 0", grids[0]), ("UV 1", grids[1])):
            c = ic.correlation(g, sample)
            ctx.check(c >= 0.6, f"row at y={cy:.0f}: {label} tile vs Sample correlation {c:.2f}")
    ctx.check(compared >= 3, f"{compared} rows with a visible check compared (>= 3)")


@model("TextureSettingsTest",
       "per-texture sampler wrap modes (and doubleSided): no red X or solid red box anywhere, the "
       "Test column green like the Sample pass column")
def _texture_settings(ctx):
    view = dict(size=(384, 384))
    img = ctx.render("front", **view)
    m = ctx.mask("front", **view)
    no_red_marks(ctx, img, m, "wrap and sided tests")
    green = colour_pixels(img, m, "green")
    ctx.check(len(green) > 0.04 * m.count(), f"green checks cover {100 * len(green) / max(m.count(), 1):.1f} % of the model (> 4 %)")


@model("NegativeScaleTest",
       "mirrored nodes (scale -1): no red X in the check blocks, and each mirrored sphere lit like "
       "its unmirrored twin (same brightness within 35 %, lit from the same side)")
def _negative_scale(ctx):
    view = dict(size=(384, 384))
    img = ctx.render("front", **view)
    m = ctx.mask("front", **view)
    no_red_marks(ctx, img, m, "front/back/sample blocks", limit=0.001)
    # Spheres: round regions that are not the blue board and not the light label boxes.
    bb = m.bbox()
    board = ic.Mask.where(img, lambda r, g, b: b > r + 40 and b > g + 10)
    cand = ic.Mask(img.w, img.h)
    for i in range(img.w * img.h):
        cand.bits[i] = 1 if m.bits[i] and not board.bits[i] else 0
    spheres = [r for r in cand.components(min_size=30)
               if 0.65 < r.fill() < 0.9 and 0.75 < r.width / r.height < 1.33
               and r.cy > bb[1] + 0.5 * (bb[3] - bb[1])]
    if not ctx.check(len(spheres) >= 2, f"{len(spheres)} spheres found (the white pair at least)"):
        return
    spheres.sort(key=lambda r: r.cy)
    white = sorted(spheres[:2], key=lambda r: r.cx)
    (l0, _), (l1, _) = ic.lum_stats(img, white[0].pixels), ic.lum_stats(img, white[1].pixels)
    ctx.check(l1 >= 0.65 * l0 and l0 >= 0.65 * l1,
              f"white spheres: scale 1.0 mean luma {l0:.2f}, scale -1.0 {l1:.2f} (within 35 %)")
    a, b = ic.lit_side(img, white[0]), ic.lit_side(img, white[1])
    ang = ic.angle_between(a[:2], b[:2])
    ctx.check(ang < 45, f"white spheres lit from the same side ({ang:.0f} deg apart, < 45)")


def _normal_tangent(ctx):
    view = dict(size=(512, 384))
    img = ctx.render("front", **view)
    m = ctx.mask("front", **view)
    cells = [r for r in m.components(min_size=80) if 0.7 < r.width / r.height < 1.4 and r.fill() > 0.8]
    # Judge the cells with contrast (the metal column is flat without reflections to see).
    judged = [c for c in cells if ic.lum_stats(img, c.pixels)[1] > 0.05]
    ctx.check(len(judged) >= 10, f"{len(judged)} cells with shading found ({len(cells)} cells)")
    lit_directions(ctx, img, judged, "normal-mapped and geometry cells (their bumps)", max_spread=60,
                   inner=0.8)


model("NormalTangentTest",
      "normal maps with tangents generated (none in the file): every cell, geometry or normal "
      "map, lit from the same side (within 60 deg of the mean)")(_normal_tangent)
model("NormalTangentMirrorTest",
      "normal maps with the file's tangents (mirrored UVs): every cell lit from the same side "
      "(within 60 deg of the mean)")(_normal_tangent)


@model("Cameras",
       "camera 1 is orthographic: the tilted square's near and far edges are as wide as each "
       "other (within 3 %) and it spans half the frame (xmag 1); camera 0 (perspective) shows "
       "the far edge narrower")
def _cameras(ctx):
    def widths(m):
        bb = m.bbox()
        def width_at(y):
            xs = [x for x in range(m.w) if m.bits[y * m.w + x]]
            return (max(xs) - min(xs) + 1) if xs else 0
        h = bb[3] - bb[1]
        return width_at(bb[1] + max(1, h // 10)), width_at(bb[3] - 1 - max(1, h // 10)), bb
    ctx.check(ctx.convert() == 0 and ctx.summary.get("counts", {}).get("cameras", 0) >= 2,
              f"both cameras converted ({ctx.summary.get('counts', {}).get('cameras')} in the container)")
    p_top, p_bottom, _ = widths(ctx.mask("camera0", camera=0, size=(256, 256)))
    ctx.render("camera0", camera=0, size=(256, 256))
    ctx.check(p_top < 0.95 * p_bottom, f"camera 0 perspective: far edge {p_top} px, near edge {p_bottom} px")
    m = ctx.mask("camera1", camera=1, size=(256, 256))
    ctx.render("camera1", camera=1, size=(256, 256))
    o_top, o_bottom, bb = widths(m)
    ratio = o_top / max(o_bottom, 1)
    ctx.check(abs(1 - ratio) <= 0.03, f"camera 1 orthographic: far/near edge width {ratio:.3f} (1 +- 0.03)")
    span = (bb[2] - bb[0]) / m.w
    ctx.check(0.42 <= span <= 0.58, f"camera 1: the unit square spans {span:.2f} of the 2-unit-wide view (0.5)")


@model("MorphPrimitivesTest",
       "default morph weights (0.5) applied: seen edge-on, the rest shape rises above the plane "
       "(silhouette height >= 5 % of its width), not a flat plane")
def _morph_primitives(ctx):
    view = dict(direction=(0, 0.02, 1), size=(384, 288))
    m = ctx.mask("edge-on", **view)
    ctx.render("edge-on", **view)
    ctx.render("above", direction=(0, 1, 1.2), size=(384, 288))
    bb = m.bbox()
    if not ctx.check(bb, "something visible edge-on"):
        return
    ratio = (bb[3] - bb[1]) / float(bb[2] - bb[0])
    ctx.check(ratio >= 0.05, f"edge-on silhouette height/width {ratio:.3f} (>= 0.05; flat ~0)")
    red = colour_pixels(ctx.images[("above", False)], None, "red")
    green = colour_pixels(ctx.images[("above", False)], None, "green")
    ctx.check(red and green, f"both primitives drawn (red {len(red)} px, green {len(green)} px)")


@model("SpecGlossVsMetalRough",
       "KHR_materials_pbrSpecularGlossiness: the spec-gloss bottle (right) looks like the "
       "metal-rough one (left): mean luma within 30 %, not near-black gold")
def _spec_gloss(ctx):
    view = dict(size=(384, 384))
    img = ctx.render("front", **view)
    m = ctx.mask("front", **view)
    bb = m.bbox()
    mid = (bb[0] + bb[2]) / 2
    # The bottles' bodies: the lower 70 % of the model (the labels float above).
    y_body = bb[1] + 0.3 * (bb[3] - bb[1])
    left = [i for i in range(img.w * img.h) if m.bits[i] and i // img.w > y_body and i % img.w < mid]
    right = [i for i in range(img.w * img.h) if m.bits[i] and i // img.w > y_body and i % img.w >= mid]
    (ll, _), (lr, _) = ic.lum_stats(img, left), ic.lum_stats(img, right)
    ctx.check(lr >= 0.7 * ll and ll >= 0.7 * lr,
              f"bottles' mean luma: metal-rough {ll:.3f}, spec-gloss {lr:.3f} (within 30 %)")
    cl, cr = ic.mean_colour(img, left), ic.mean_colour(img, right)
    ctx.check(max(abs(a - b) for a, b in zip(cl, cr)) < 40,
              f"mean colours: metal-rough ({cl[0]:.0f}, {cl[1]:.0f}, {cl[2]:.0f}), spec-gloss "
              f"({cr[0]:.0f}, {cr[1]:.0f}, {cr[2]:.0f}) (each channel within 40)")


@model("SimpleInstancing",
       "EXT_mesh_gpu_instancing: 125 instances counted in the summary and drawn (the cubes cover "
       ">= 10 % of the frame fitted to all 125, one cube covers ~0.3 %)")
def _instancing(ctx):
    view = dict(direction=(1, 0.8, 1.3), size=(384, 288))
    ctx.require_converted()
    counted = re.search(r"125\D{0,40}instanc|instanc\D{0,40}125", ctx.convert_text, re.I)
    ctx.check(counted, "the summary counts 125 instances")
    m = ctx.mask("view", **view)
    ctx.render("view", **view)
    frac = m.count() / float(m.w * m.h)
    ctx.check(frac >= 0.10, f"cubes cover {100 * frac:.1f} % of the frame (>= 10 %)")
    blobs = m.components(min_size=4)
    ctx.check(frac >= 0.10 or len(blobs) > 1, f"{len(blobs)} separate cube regions")


@model("UnlitTest",
       "KHR_materials_unlit (required): converts, and each object is one flat colour: its pixels "
       "within 10/255 of their median, and that colour the base colour (#FF7F00, #007FFF) after "
       "the player's display transform (exposure 1, ACES fit, sRGB) within 12/255: no light, "
       "shadow or environment term. The display transform applies to every pixel, unlit ones too "
       "(the sample viewer's screenshot, tone mapping off, shows the raw colours)")
def _unlit(ctx):
    view = dict(size=(384, 288), direction=(0.6, 0.5, 1))  # several faces of each object
    img = ctx.render("front", **view)
    m = ctx.mask("front", **view)
    for name, hue, base in (("orange", ("orange", "red"), (255, 127, 0)),
                            ("blue", ("blue",), (0, 127, 255))):
        expect = tuple(_display(c) for c in base)
        pix = [i for i in range(img.w * img.h) if m.bits[i]
               and ic.hue_class(img.px[3 * i], img.px[3 * i + 1], img.px[3 * i + 2], min_sat=0.3, min_val=0.05) in hue]
        if not ctx.check(len(pix) > 200, f"{name} object found ({len(pix)} px)"):
            continue
        med = [sorted(img.px[3 * i + c] for i in pix)[len(pix) // 2] for c in range(3)]
        off = sum(1 for i in pix if max(abs(img.px[3 * i + c] - med[c]) for c in range(3)) > 10)
        ctx.check(off <= 0.03 * len(pix), f"{name}: {100 * off / len(pix):.1f} % of its pixels differ from its "
                  f"colour ({med[0]}, {med[1]}, {med[2]}) by > 10/255 (<= 3 %: flat)")
        ctx.check(max(abs(med[c] - expect[c]) for c in range(3)) <= 12,
                  f"{name}: colour ({med[0]}, {med[1]}, {med[2]}) vs base colour {expect} (within 12/255)")


def _display(srgb8):
    """An sRGB 8-bit base colour channel through the player's display transform
    (shaders/tonemap.frag: exposure 1, Narkowicz's ACES fit, then the sRGB encoding)."""
    c = srgb8 / 255.0
    x = c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4
    y = min(max((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0), 1.0)
    e = 12.92 * y if y <= 0.0031308 else 1.055 * y ** (1 / 2.4) - 0.055
    return round(e * 255)


def _not_black(ctx, img, m, what, min_luma, max_dark):
    pix = [i for i in range(img.w * img.h) if m.bits[i]]
    mean, _ = ic.lum_stats(img, pix)
    dark = sum(1 for i in pix if ic.lum(img.px[3 * i], img.px[3 * i + 1], img.px[3 * i + 2]) < 0.05)
    ctx.check(mean >= min_luma and dark <= max_dark * len(pix),
              f"{what}: mean luma {mean:.3f} (>= {min_luma}), near-black {100 * dark / max(len(pix), 1):.0f} % "
              f"of its pixels (<= {100 * max_dark:.0f} %)")


def _background(ctx, img, m):
    bg = [i for i in range(img.w * img.h) if not m.bits[i]]
    mean, _ = ic.lum_stats(img, bg)
    ctx.check(mean >= 0.06, f"background mean luma {mean:.3f} (>= 0.06: not a black void)")


@model("DamagedHelmet",
       "the standard PBR model with no lights or environment in the file: the metal lit (mean "
       "luma >= 0.15, <= 35 % near-black) and the background not a black void")
def _damaged_helmet(ctx):
    view = dict(size=(384, 384))
    img = ctx.render("front", background=True, **view)
    m = ctx.mask("front", **view)
    _not_black(ctx, img, m, "helmet", 0.15, 0.35)
    _background(ctx, img, m)


@model("MetalRoughSpheresNoTextures",
       "metal/roughness grid with no environment in the file: the metal spheres (upper half) "
       "not near-black (mean luma >= 0.5 x the non-metals'), background not a black void")
def _metal_rough(ctx):
    view = dict(size=(384, 384))
    img = ctx.render("front", background=True, **view)
    m = ctx.mask("front", **view)
    bb = m.bbox()
    mid = (bb[1] + bb[3]) / 2
    spheres = [r for r in m.components(min_size=20) if r.fill() > 0.6 and 0.7 < r.width / r.height < 1.4]
    metal = [i for r in spheres if r.cy < mid for i in r.pixels]
    plastic = [i for r in spheres if r.cy >= mid for i in r.pixels]
    if not ctx.check(metal and plastic, f"{len(spheres)} spheres found"):
        return
    lm, lp = ic.lum_stats(img, metal)[0], ic.lum_stats(img, plastic)[0]
    ctx.check(lm >= 0.5 * lp, f"metal spheres mean luma {lm:.3f}, non-metal {lp:.3f} (>= 0.5 x)")
    _background(ctx, img, m)


@model("AlphaBlendModeTest",
       "OPAQUE, BLEND, MASK and alphaCutoff: every test shows its green check, no red X")
def _alpha_blend(ctx):
    view = dict(size=(512, 256))
    img = ctx.render("front", **view)
    m = ctx.mask("front", **view)
    no_red_marks(ctx, img, m, "mode labels", limit=0.0005)
    green = colour_mask(img, "green", min_sat=0.5, min_val=0.3)
    checks = [r for r in green.components(min_size=6)]
    ctx.check(len(checks) >= 3, f"{len(checks)} green checks/marks visible (>= 3)")


@model("TextureCoordinateTest",
       "UV origin top-left: the yellow 'Top Left' square upper left, orange 'Top Right' upper "
       "right, blue 'Bottom Left' lower left, green 'Bottom Right' lower right")
def _texcoord(ctx):
    view = dict(size=(384, 384))
    img = ctx.render("front", **view)
    m = ctx.mask("front", **view)
    bb = m.bbox()
    cx, cy = (bb[0] + bb[2]) / 2, (bb[1] + bb[3]) / 2
    for colour, want in (("yellow", (-1, -1)), ("orange", (1, -1)), ("blue", (-1, 1)), ("green", (1, 1))):
        pix = colour_pixels(img, m, colour)
        if not ctx.check(len(pix) > 0.03 * m.count(), f"{colour} square found ({len(pix)} px)"):
            continue
        x = sum(i % img.w for i in pix) / len(pix) - cx
        y = sum(i // img.w for i in pix) / len(pix) - cy
        ctx.check(x * want[0] > 0 and y * want[1] > 0,
                  f"{colour} square at ({x:+.0f}, {y:+.0f}) from the centre (expected "
                  f"{'left' if want[0] < 0 else 'right'}, {'top' if want[1] < 0 else 'bottom'})")


@model("MultiUVTest",
       "TEXCOORD_1 for the emissive texture: the green glTF logo shows, the white 'Multiple UVs "
       "not supported' text does not")
def _multi_uv(ctx):
    view = dict(size=(384, 288))
    img = ctx.render("front", **view)
    m = ctx.mask("front", **view)
    # The logo (uv1.png, emissive) is a yellow-green lighter and greener than the face.
    green = [i for i in range(img.w * img.h) if m.bits[i] and img.px[3 * i + 1] - img.px[3 * i] >= 8
             and img.px[3 * i + 1] - img.px[3 * i + 2] > 60]
    white = [i for i in range(img.w * img.h) if m.bits[i] and min(img.px[3 * i:3 * i + 3]) > 215]
    area = max(m.count(), 1)
    ctx.check(len(green) > 0.03 * area, f"green logo covers {100 * len(green) / area:.1f} % (> 3 %)")
    ctx.check(len(white) < 0.005 * area, f"white 'not supported' text covers {100 * len(white) / area:.2f} % (< 0.5 %)")


@model("VertexColorTest",
       "COLOR_0 multiplies baseColor: the Test row's checks pure red, green and blue like the "
       "Sample pass row, no cyan, magenta or yellow X")
def _vertex_colour(ctx):
    view = dict(size=(384, 384))
    img = ctx.render("front", **view)
    m = ctx.mask("front", **view)
    area = max(m.count(), 1)
    for colour in ("cyan", "magenta", "yellow"):
        pix = colour_pixels(img, m, colour)
        ctx.check(len(pix) < 0.002 * area, f"{colour} X covers {100 * len(pix) / area:.2f} % (< 0.2 %)")
    bb = m.bbox()
    mid = (bb[1] + bb[3]) / 2
    for colour in ("red", "green", "blue"):
        pix = colour_pixels(img, m, colour, min_sat=0.6)
        top = sum(1 for i in pix if i // img.w < mid)
        bottom = len(pix) - top
        ctx.check(top > 0.5 * bottom and bottom > 0,
                  f"{colour} check: {top} px in the Test row, {bottom} in the Sample pass row")


@model("OrientationTest",
       "node rotations (quaternions and matrices): each coloured arrow points at the target of "
       "its colour; the target sits at the arrow's tip, so arrow and target are one region of "
       "that colour (grown by 2 px, the largest holds >= 90 % of its pixels), a turned arrow stands apart")
def _orientation(ctx):
    for label, direction, colours in (("front", (1, 0.8, 1.2), ("red", "green", "blue")),
                                      ("back", (-1, -0.8, -1.2), ("cyan", "magenta", "yellow"))):
        img = ctx.render(label, direction=direction, size=(384, 384))
        for colour in colours:
            regs = colour_mask(img, colour, min_sat=0.65, min_val=0.2).dilate(2).components(min_size=1)
            total = sum(r.size for r in regs)
            regs = [r for r in regs if r.size >= 0.03 * total]  # not edge speckles
            total = sum(r.size for r in regs)
            if not ctx.check(total >= 50, f"{label}: {colour} arrow found ({total} px)"):
                continue
            share = regs[0].size / float(total)
            ctx.check(share >= 0.9, f"{label}: {colour} arrow and target joined: the largest "
                      f"region holds {100 * share:.0f} % of {total} px ({len(regs)} regions; >= 90 %)")


@model("EmissiveStrengthTest",
       "KHR_materials_emissive_strength: the five emissive cubes brighter left to right "
       "(1x..16x), the last clearly brighter than the first")
def _emissive_strength(ctx):
    view = dict(size=(512, 288))
    img = ctx.render("front", **view)
    # The cubes emit [0.1, 0.5, 0.9]: blue above red however bright; the walls are grey.
    cubes = ic.Mask.where(img, lambda r, g, b: b >= 150 and b - r >= 10)
    regs = [r for r in cubes.components(min_size=15) if 0.5 < r.width / r.height < 2]
    regs = sorted(regs[:5], key=lambda r: r.cx)
    if not ctx.check(len(regs) == 5, f"{len(regs)} emissive cubes found (5)"):
        return
    lums = [ic.lum_stats(img, r.pixels)[0] for r in regs]
    ok = all(b >= a - 0.01 for a, b in zip(lums, lums[1:])) and lums[-1] > lums[0] + 0.1
    ctx.check(ok, "mean luma left to right " + ", ".join(f"{v:.2f}" for v in lums))


def _skinned(ctx, features):
    ctx.require_converted()
    for feature, pattern in features:
        summary_plays(ctx, feature, pattern)
    converts_and_plays(ctx, min_coverage=0.02, size=(384, 288),
                       direction=(1, 0.3, 1) if ctx.name == "Fox" else (0, 0, 1))


@model("CesiumMan", "skin and animation played (the pose at a time is checked against the glTF's "
       "own by render.KhronosPose.*): converts, plays its walk (covers >= 2 % of the frame), "
       "and the summary names the skin and the animation")
def _cesium_man(ctx):
    _skinned(ctx, (("the skin", r"skins 1 \(19 joints\)"), ("the animation", r"animations \(1 clips")))


@model("Fox", "skin and 3 animations played (the pose checked by render.KhronosPose.*): "
       "converts, plays its first clip (covers >= 2 % of the frame), and the summary names the "
       "skin and the animations")
def _fox(ctx):
    _skinned(ctx, (("the skin", r"skins 1 \(24 joints\)"), ("the animations", r"animations \(3 clips")))


@model("AnimatedMorphCube", "morph animation played (the pose checked by render.KhronosPose.*): "
       "converts, plays its first frame (weights 0 at t = 0: a cube filling its projected box), "
       "and the summary names the animation")
def _animated_morph_cube(ctx):
    ctx.require_converted()
    summary_plays(ctx, "the morph animation", r"animations \(1 clips.*morphed meshes 1")
    m = converts_and_plays(ctx, min_coverage=0.05, size=(288, 288), direction=(1, 0.8, 1.2))
    bb = m.bbox()
    if bb:
        fill = m.count() / float((bb[2] - bb[0]) * (bb[3] - bb[1]))
        ctx.check(fill > 0.6, f"the cube fills {100 * fill:.0f} % of its bounding box (> 60 %)")


@model("StainedGlassLamp",
       "KHR_texture_basisu (KTX2) textures: either converted and drawn, or refused with an error "
       "that says KTX2 and what to do")
def _stained_glass(ctx):
    rc = ctx.convert()
    if rc == 0:
        converts_and_plays(ctx, min_coverage=0.02, size=(288, 384))
        return
    ctx.check(rc in (2, 3), f"pnb-convert refuses it with exit {rc} (2 or 3, not a crash)")
    ctx.check(re.search(r"ktx2", ctx.convert_text, re.I),
              "the error says KTX2" + ("" if re.search(r"ktx2", ctx.convert_text, re.I)
                                       else f": '{ctx.convert_text.strip().splitlines()[-1]}'"))


# --- driver --------------------------------------------------------------------------------------

def run_model(name, models_dir, out_dir, convert, play):
    entry = REGISTRY[name]
    t0 = time.monotonic()
    ctx = None
    try:
        ctx = Ctx(name, models_dir, out_dir, convert, play, entry["variant"])
        entry["fn"](ctx)
        results = ctx.results
    except Failed as e:
        results = (ctx.results if ctx else []) + [(False, str(e))]
    except subprocess.TimeoutExpired as e:
        results = (ctx.results if ctx else []) + [(False, f"timed out: {e.cmd[0]}")]
    passed = bool(results) and all(ok for ok, _ in results)
    return dict(model=name, criterion=entry["criterion"], passed=passed,
                checks=[dict(ok=ok, what=msg) for ok, msg in results],
                renders=ctx.renders if ctx else [], source=ctx.src if ctx else None,
                seconds=round(time.monotonic() - t0, 2))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--convert")
    ap.add_argument("--play")
    ap.add_argument("--models")
    ap.add_argument("--out", default="out/conformance")
    ap.add_argument("--json")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--check-registry", action="store_true")
    ap.add_argument("names", nargs="*")
    a = ap.parse_args()
    if a.list:
        for name, e in sorted(REGISTRY.items()):
            print(f"{name}\t{e['criterion']}")
        return 0
    if not a.models or not os.path.isdir(a.models):
        print(f"SKIP: no Khronos sample models at '{a.models}' (the folder ../shared/khronos "
              "beside the project root; CMake: -DPNB_KHRONOS_DIR=...)")
        return SKIP
    present = sorted(d for d in os.listdir(a.models) if os.path.isdir(os.path.join(a.models, d)))
    if a.check_registry:
        missing = [d for d in present if d not in REGISTRY]
        gone = [n for n in REGISTRY if n not in present]
        for d in missing:
            print(f"FAIL: {d} (in {a.models}) has no criterion in {__file__}")
        for n in gone:
            print(f"note: {n} has a criterion but is not in {a.models} (its test skips)")
        print(f"{len(present) - len(missing)} of {len(present)} models have a criterion")
        return 2 if missing else 0
    if not a.convert or not a.play:
        ap.error("--convert and --play are needed")
    names = a.names or [n for n in sorted(REGISTRY) if n in present]
    unknown = [n for n in names if n not in REGISTRY]
    if unknown:
        print(f"no criterion for {', '.join(unknown)} (known: {', '.join(sorted(REGISTRY))})")
        return 2
    absent = [n for n in names if n not in present]
    if absent and len(names) == 1:
        print(f"SKIP: {names[0]} is not in {a.models}")
        return SKIP
    results = []
    for n in names:
        if n in absent:
            print(f"SKIP {n}: not in {a.models}")
            continue
        r = run_model(n, a.models, a.out, a.convert, a.play)
        results.append(r)
        print(f"{'PASS' if r['passed'] else 'FAIL'} {n} ({r['seconds']:.1f} s): {r['criterion']}")
        for c in r["checks"]:
            print(f"  {'ok  ' if c['ok'] else 'FAIL'} {c['what']}")
        if r["renders"]:
            print(f"  renders: {', '.join(r['renders'])}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(results, f, indent=1)
    return 0 if all(r["passed"] for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
