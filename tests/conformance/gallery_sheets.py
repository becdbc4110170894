#!/usr/bin/env python3
"""Side-by-side sheets for scripts/gallery: ours | the sample viewer's screenshot, with the model's
name, the criterion's verdict and the model's attribution, one PNG per model and an index.html.

Usage: gallery_sheets.py RESULTS.json MODELS_DIR OUT_DIR
RESULTS.json is what khronos_conformance.py --json writes. Needs Pillow (Debian: python3-pil) for
the screenshots (JPEG, GIF); without it the page shows the two images side by side instead.
"""

import html
import json
import os
import re
import sys

try:
    from PIL import Image, ImageDraw
except ImportError:  # the page still works, with the images side by side
    Image = None

H = 300  # height of each half of a sheet


def attribution(model_dir):
    """The model's licence (LICENSE.md) and credit lines (README's licence/legal section)."""
    licence = ""
    path = os.path.join(model_dir, "LICENSE.md")
    if os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            text = f.read()
        m = re.search(r"directly associated.*?\n\s*\*\s*\[([^\]]+)\][^\n]*?SPDX license identifier: \"([^\"]+)\"",
                      text, re.S)
        if m:
            licence = f"{m.group(1)} ({m.group(2)})"
    credit = []
    path = os.path.join(model_dir, "README.md")
    if os.path.exists(path):
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
        take = False
        for line in lines:
            if line.startswith("#"):
                take = bool(re.match(r"#+\s*(License|Legal)", line, re.I))
                continue
            if take:
                line = re.sub(r"!\[[^\]]*\]\([^)]*\)", "", line)          # badges
                line = re.sub(r"\[([^\]]*)\]\(([^)]*)\)", r"\1 <\2>", line)  # links: text <url>
                line = re.sub(r"<(?!http)[^>]*>", "", line).strip()        # html tags
                if line and not line.startswith("#"):
                    credit.append(line)
    return licence, credit


def screenshot(model_dir):
    d = os.path.join(model_dir, "screenshot")
    if not os.path.isdir(d):
        return None
    files = sorted(f for f in os.listdir(d) if f.lower().endswith((".png", ".jpg", ".jpeg", ".gif")))
    # Prefer a file that shows a correct render over the README's failure examples.
    files.sort(key=lambda f: ("fail" in f.lower(), f))
    return os.path.join(d, files[0]) if files else None


def fit(img, h):
    img = img.convert("RGB")
    return img.resize((max(1, round(img.width * h / img.height)), h))


def make_sheet(result, shot, out_png, licence):
    ours = [Image.open(p) for p in result["renders"][:2]]
    halves = [fit(o, H) for o in ours] or [Image.new("RGB", (H, H), (60, 0, 0))]
    theirs = fit(Image.open(shot), H) if shot else Image.new("RGB", (H, H), (40, 40, 40))
    gap = 8
    width = sum(h.width for h in halves) + gap * len(halves) + theirs.width
    sheet = Image.new("RGB", (max(width, 480), H + 56), (32, 32, 32))
    draw = ImageDraw.Draw(sheet)
    verdict = "PASS" if result["passed"] else "FAIL"
    colour = (60, 200, 60) if result["passed"] else (230, 60, 60)
    draw.rectangle((0, 0, sheet.width, 22), fill=(16, 16, 16))
    draw.text((6, 5), f"{result['model']}", fill=(255, 255, 255))
    draw.text((sheet.width - 40, 5), verdict, fill=colour)
    x = 0
    for h in halves:
        sheet.paste(h, (x, 22))
        x += h.width + gap
    sheet.paste(theirs, (x, 22))
    draw.text((4, H + 26), "Penumbra (pnb-play, llvmpipe)", fill=(200, 200, 200))
    draw.text((x + 4, H + 26), "Khronos sample viewer: " + (os.path.basename(shot) if shot else "none"),
              fill=(200, 200, 200))
    draw.text((4, H + 41), licence[:110], fill=(150, 150, 150))
    sheet.save(out_png)


def main():
    results_path, models_dir, out_dir = sys.argv[1:4]
    with open(results_path) as f:
        results = json.load(f)
    os.makedirs(out_dir, exist_ok=True)
    rows, sections = [], []
    for r in results:
        name = r["model"]
        mdir = os.path.join(models_dir, name)
        licence, credit = attribution(mdir)
        shot = screenshot(mdir)
        verdict = "PASS" if r["passed"] else "FAIL"
        sheet = f"{name}.png"
        if Image is not None:
            make_sheet(r, shot, os.path.join(out_dir, sheet), licence)
            pictures = f'<img src="{html.escape(sheet)}" alt="{html.escape(name)}: ours | sample viewer">'
        else:
            imgs = [os.path.relpath(p, out_dir) for p in r["renders"][:2]]
            if shot:
                imgs.append(os.path.relpath(shot, out_dir))
            pictures = " ".join(f'<img src="{html.escape(p)}" height="{H}">' for p in imgs)
        fail_example = shot and "fail" in os.path.basename(shot).lower()
        checks = "".join(f'<li class="{"ok" if c["ok"] else "bad"}">{"ok" if c["ok"] else "FAIL"}: '
                         f'{html.escape(c["what"])}</li>' for c in r["checks"])
        credit_html = "<br>".join(html.escape(c) for c in credit)
        rows.append(f'<tr><td><a href="#{html.escape(name)}">{html.escape(name)}</a></td>'
                    f'<td>{html.escape(r["criterion"])}</td><td class="{verdict.lower()}">{verdict}</td></tr>')
        sections.append(
            f'<section id="{html.escape(name)}"><h2>{html.escape(name)} '
            f'<span class="{verdict.lower()}">{verdict}</span></h2>'
            f'<p>{pictures}</p>'
            f'<p>Left: Penumbra (pnb-convert, pnb-play --headless on llvmpipe). Right: the Khronos '
            f'sample viewer\'s screenshot <code>{html.escape(os.path.basename(shot) if shot else "none")}</code> '
            f'from the model\'s folder'
            + (" &mdash; <b>this file is the README's example of a failed render</b>, the only "
               "screenshot in the folder" if fail_example else "")
            + f'.</p><p><b>Criterion:</b> {html.escape(r["criterion"])}</p><ul>{checks}</ul>'
            f'<p class="credit"><b>Model:</b> {html.escape(name)} from the Khronos glTF sample '
            f'assets (KhronosGroup/glTF-Sample-Assets). <b>Licence:</b> {html.escape(licence or "see LICENSE.md")}.'
            f'<br>{credit_html}</p></section>')
    passed = sum(1 for r in results if r["passed"])
    page = f"""<!doctype html><html><head><meta charset="utf-8"><title>Penumbra: Khronos sample models</title>
<style>body{{font-family:sans-serif;background:#222;color:#ddd;margin:2em}} img{{max-width:100%}}
td,th{{border-bottom:1px solid #444;padding:3px 8px;text-align:left;vertical-align:top}}
.pass{{color:#5c5}} .fail{{color:#e55}} li.bad{{color:#e88}} .credit{{color:#aaa;font-size:90%}}
a{{color:#8bf}} section{{border-top:1px solid #555;margin-top:2em}}</style></head><body>
<h1>Penumbra on the Khronos glTF sample models</h1>
<p>{passed} of {len(results)} models pass their criterion (tests/conformance/khronos_conformance.py,
docs/PLAYER.md "Conformance on the Khronos sample models"). Each sheet: our render(s) | the sample
viewer's screenshot. The models and screenshots belong to their authors; each one's licence and
credit is given with it below.</p>
<table><tr><th>model</th><th>criterion</th><th>today</th></tr>{''.join(rows)}</table>
{''.join(sections)}</body></html>
"""
    with open(os.path.join(out_dir, "index.html"), "w", encoding="utf-8") as f:
        f.write(page)
    print(f"{passed} of {len(results)} pass; sheets and index in {out_dir}/index.html"
          + ("" if Image is not None else " (no Pillow: images side by side, no PNG sheets)"))


if __name__ == "__main__":
    main()
