#!/usr/bin/env python3
"""Summarise the runs of scripts/bench-osgshadow (standard library only).

    summarize.py OUT_DIR

Reads OUT_DIR/run.json (settings, techniques, exact command lines, the list of runs; written by
the script), OUT_DIR/scene/camera.json (glb2obj.py) and every run's frame_clock output, and writes
OUT_DIR/summary.json, OUT_DIR/table.md and OUT_DIR/screenshots/<technique>.png (from the PPMs of
round 1). Prints the table.

Per run: frame k's time is swap(k+1) - swap(k) (frame_clock: glFinish before every swap); the
first `warmup` intervals are dropped (shader compilation, first uploads, OSG's near/far and the
shadow cameras settling), the rest are the run's samples. Per technique: ms = median over its
runs of the per-run medians; ratio = median over rounds of (technique run median / median of the
no-shadow run it was paired with, back to back), so slow phases of the shared machine that hit
both runs of a pair cancel. The same for the process CPU time per frame (all threads, llvmpipe's
included): less sensitive to other tenants than wall time, since time spent waiting for a core
is not counted.
Also checks, from the last frame's GL calls, the camera (eye, forward, up, fovy, aspect, near,
far), the light, the window size and the shadow passes (depth clears per viewport size) against
what was asked for, and fails (exit 1) when the camera or light disagrees.
"""
import json
import math
import os
import statistics
import struct
import sys
import zlib


def median(xs):
    return statistics.median(xs) if xs else None


def pct(xs, p):
    s = sorted(xs)
    if not s:
        return None
    k = (len(s) - 1) * p
    lo, hi = math.floor(k), math.ceil(k)
    return s[lo] + (s[hi] - s[lo]) * (k - lo)


def parse_clock(path):
    info = {'swaps': [], 'cpu': [], 'clears': []}
    for line in open(path):
        key, _, rest = line.rstrip('\n').partition(' ')
        if key == 'swap':
            fields = rest.split()
            info['swaps'].append(int(fields[1]))
            if len(fields) > 2:
                info['cpu'].append(int(fields[2]))
        elif key in ('renderer', 'version'):
            info[key] = rest
        elif key == 'window':
            info['window'] = [int(v) for v in rest.split()]
        elif key == 'clears':
            info['clears'] = rest.split()
        elif key in ('main_projection', 'main_modelview', 'light0_position', 'light0_modelview'):
            info[key] = [float(v) for v in rest.split()] if rest.strip() else None
        elif key == 'loaded':
            info['loaded'] = int(rest)
    return info


def ppm_to_png(src, dst):
    data = open(src, 'rb').read()
    header = data.split(b'\n', 3)
    w, h = map(int, header[1].split())
    raw = header[3]
    rows = b''.join(b'\x00' + raw[y * w * 3:(y + 1) * w * 3] for y in range(h))

    def chunk(tag, body):
        return (struct.pack('>I', len(body)) + tag + body
                + struct.pack('>I', zlib.crc32(tag + body) & 0xffffffff))
    with open(dst, 'wb') as f:
        f.write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0))
                + chunk(b'IDAT', zlib.compress(rows, 6)) + chunk(b'IEND', b''))


def col(m, r, c):  # column-major 4x4
    return m[c * 4 + r]


def camera_from_gl(proj, mv):
    """eye/forward/up (world) and fovy/aspect/near/far from OpenGL column-major matrices."""
    rv = [[col(mv, r, c) for c in range(3)] for r in range(3)]
    t = [col(mv, r, 3) for r in range(3)]
    eye = [-sum(rv[r][c] * t[r] for r in range(3)) for c in range(3)]
    forward = [-rv[2][c] for c in range(3)]
    up = [rv[1][c] for c in range(3)]
    p00, p11, p22, p32 = col(proj, 0, 0), col(proj, 1, 1), col(proj, 2, 2), col(proj, 2, 3)
    return {
        'eye': eye, 'forward': forward, 'up': up,
        'yfov_deg': math.degrees(2 * math.atan(1 / p11)),
        'aspect': p11 / p00,
        'near': p32 / (p22 - 1), 'far': p32 / (p22 + 1),
    }


def light_from_gl(pos, lmv, view):
    """GL_LIGHT0 position as passed under model-view lmv, expressed in the frame of `view`."""
    def apply(m, v):
        return [sum(col(m, r, c) * v[c] for c in range(4)) for r in range(4)]
    eye = apply(lmv, pos)
    # world = view^-1 * eye (view is rigid: [R t] -> [R^T, -R^T t])
    rv = [[col(view, r, c) for c in range(3)] for r in range(3)]
    t = [col(view, r, 3) for r in range(3)]
    v3 = [eye[i] - t[i] * eye[3] for i in range(3)]
    w = [sum(rv[r][c] * v3[r] for r in range(3)) for c in range(3)]
    return w + [eye[3]]


def mat3_t_apply(R, v):  # R^T v
    return [sum(R[r][c] * v[r] for r in range(3)) for c in range(3)]


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def dist(a, b):
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))


def r(v, nd=4):
    if isinstance(v, list):
        return [round(x, nd) for x in v]
    return None if v is None else round(v, nd)


def main():
    out = sys.argv[1]
    run = json.load(open(os.path.join(out, 'run.json')))
    cam = json.load(open(os.path.join(out, 'scene', 'camera.json')))
    warmup = run['settings']['warmup']
    techniques = run['techniques']
    base = techniques[0]
    R = cam['R_world_to_obj']
    problems = []

    per_tech = {t: {'runs': []} for t in techniques}
    pairs = {}  # (round, shadow technique) -> {technique: run median}
    checks = {}
    for entry in run['runs']:
        info = parse_clock(os.path.join(out, entry['clock']))
        sw = info['swaps']
        intervals = [(b - a) / 1e6 for a, b in zip(sw, sw[1:])]
        samples = intervals[warmup:]
        cpu = info['cpu']
        cpu_samples = [(b - a) / 1e6 for a, b in zip(cpu, cpu[1:])][warmup:]
        if len(samples) < 5:
            sys.exit(f'summarize: {entry["clock"]}: only {len(samples)} frames after warm-up')
        rec = {
            'round': entry['round'],
            'median_ms': median(samples),
            'mean_ms': statistics.fmean(samples),
            'p10_ms': pct(samples, 0.1), 'p90_ms': pct(samples, 0.9),
            'cpu_median_ms': median(cpu_samples),
            'frames': len(samples),
            'startup_ms': (sw[0] - info['loaded']) / 1e6 if 'loaded' in info else None,
            'process_wall_s': entry.get('wall_s'),
            'samples_ms': [round(x, 3) for x in samples],
        }
        if entry.get('kind') == 'crosscheck':
            per_tech[entry['technique']].setdefault('crosscheck_runs', []).append(
                {'frames_total': entry['frames'], 'wall_s': entry['wall_s'],
                 'shim_mean_ms': rec['mean_ms'], 'shim_median_ms': rec['median_ms']})
            continue
        rec['paired_with'] = entry.get('pair')
        per_tech[entry['technique']]['runs'].append(rec)
        if entry.get('pair'):
            pairs.setdefault((entry['round'], entry['pair']), {})[entry['technique']] = (
                rec['median_ms'], rec['cpu_median_ms'])

        t = entry['technique']
        if t not in checks:
            gl_cam = camera_from_gl(info['main_projection'], info['main_modelview'])
            light_obj = light_from_gl(info['light0_position'], info['light0_modelview'],
                                      info['main_modelview'])
            depth_passes = {}
            for c in info['clears']:
                size, _, flags = c.partition(':')
                if 'D' in flags:
                    depth_passes[size] = depth_passes.get(size, 0) + 1
            win = run['settings']['window']
            main_size = f'{win[0]}x{win[1]}'
            shadow_passes = {k: v for k, v in depth_passes.items() if k != main_size}
            checks[t] = {
                'renderer': info.get('renderer'), 'gl_version': info.get('version'),
                'window': info.get('window'),
                'depth_clears_by_viewport': depth_passes,
                'shadow_map_passes': shadow_passes,
                'camera_obj': {k: r(v, 6) for k, v in gl_cam.items()},
                'camera_world': {
                    'eye': r(mat3_t_apply(R, gl_cam['eye']), 6),
                    'forward': r(mat3_t_apply(R, gl_cam['forward']), 6),
                    'up': r(mat3_t_apply(R, gl_cam['up']), 6),
                },
                'light_obj_position': r(light_obj, 6),
                'light_world_direction_to_light': r(unit(mat3_t_apply(R, light_obj[:3])), 6),
            }
            want = cam['camera']['obj']
            c = checks[t]
            err = max(dist(gl_cam['eye'], want['eye']), dist(gl_cam['forward'], want['forward']),
                      dist(gl_cam['up'], want['up']))
            if err > 1e-3:
                problems.append(f'{t}: camera differs from the requested one by {err:.4g}')
            if abs(gl_cam['yfov_deg'] - cam['camera']['yfov_deg']) > 1e-3:
                problems.append(f'{t}: fovy {gl_cam["yfov_deg"]} != {cam["camera"]["yfov_deg"]}')
            if abs(gl_cam['aspect'] - win[0] / win[1]) > 1e-3:
                problems.append(f'{t}: aspect {gl_cam["aspect"]} != {win[0] / win[1]}')
            want_light = cam['sun']['osg_light_position']
            if dist(unit(light_obj[:3]), want_light[:3]) > 1e-4 or light_obj[3] != 0:
                problems.append(f'{t}: light {light_obj} != {want_light}')
            if c['window'] != win:
                problems.append(f'{t}: window {c["window"]} != {win}')
            expect = run['expected_shadow_passes'].get(t)
            if expect is not None and shadow_passes.get(expect[0], 0) != expect[1]:
                problems.append(f'{t}: expected {expect[1]} depth passes at {expect[0]}, '
                                f'saw {shadow_passes}')

    results = {}
    for t in techniques:
        runs = per_tech[t]['runs']
        pooled = [x for rr in runs for x in rr['samples_ms']]
        if t == base:
            ratios = [1.0] * len(runs)
            cpu_ratios = [1.0] * len(runs) if runs and runs[0]['cpu_median_ms'] else []
        else:
            keys = [k for k in sorted(pairs) if k[1] == t and t in pairs[k] and base in pairs[k]]
            ratios = [pairs[k][t][0] / pairs[k][base][0] for k in keys]
            cpu_ratios = [pairs[k][t][1] / pairs[k][base][1] for k in keys
                          if pairs[k][t][1] and pairs[k][base][1]]
        res = {
            'label': run['labels'][t],
            'command': run['commands'][t],
            'median_ms': r(median([rr['median_ms'] for rr in runs]), 3),
            'per_run_median_ms': [r(rr['median_ms'], 3) for rr in runs],
            'pooled_median_ms': r(median(pooled), 3),
            'pooled_mean_ms': r(statistics.fmean(pooled), 3),
            'pooled_p10_ms': r(pct(pooled, 0.1), 3), 'pooled_p90_ms': r(pct(pooled, 0.9), 3),
            'ratio_to_' + base: r(median(ratios), 3),
            'ratio_per_round': [r(x, 3) for x in ratios],
            'ratio_range': [r(min(ratios), 3), r(max(ratios), 3)] if ratios else None,
            'cpu_median_ms': r(median([rr['cpu_median_ms'] for rr in runs
                                       if rr['cpu_median_ms'] is not None]), 3),
            'cpu_ratio_to_' + base: r(median(cpu_ratios), 3),
            'cpu_ratio_per_round': [r(x, 3) for x in cpu_ratios],
            'frames_per_run': runs[0]['frames'] if runs else None,
            'startup_ms_median': r(median([rr['startup_ms'] for rr in runs if rr['startup_ms']]), 1),
            'checks': checks.get(t),
            'runs': runs,
        }
        cc = per_tech[t].get('crosscheck_runs')
        if cc and len(cc) == 2:
            a, b = sorted(cc, key=lambda x: x['frames_total'])
            res['crosscheck'] = {
                'what': 'whole-process wall time of a run of N frames and one of 2N frames, back '
                        'to back: (wall(2N) - wall(N)) / N, independent of the shim clock',
                'frames': [a['frames_total'], b['frames_total']],
                'wall_s': [round(a['wall_s'], 3), round(b['wall_s'], 3)],
                'wall_ms_per_frame': r((b['wall_s'] - a['wall_s']) * 1000
                                       / (b['frames_total'] - a['frames_total']), 3),
                'shim_mean_ms_of_the_2N_run': r(b['shim_mean_ms'], 3),
            }
        shot = os.path.join(out, 'runs', f'{t}.ppm')
        png = os.path.join(out, 'screenshots', f'{t}.png')
        if os.path.exists(shot):
            os.makedirs(os.path.join(out, 'screenshots'), exist_ok=True)
            ppm_to_png(shot, png)
            os.remove(shot)
        if os.path.exists(png):
            res['screenshot'] = os.path.relpath(png, run['repo_root'])
        results[t] = res

    summary = {
        'what': 'OpenSceneGraph osgShadow frame time (stock osgshadow example) under Xvfb + '
                'Mesa llvmpipe; see bench/osgshadow/NOTES.md',
        'machine': run['machine'],
        'settings': run['settings'],
        'scene': {k: cam[k] for k in ('source', 'frame', 'R_world_to_obj', 'obj_read_option',
                                      'triangles', 'bounds_obj')},
        'camera': cam['camera'],
        'camera_note': 'world = the glTF scene frame (Y up); obj = R_world_to_obj * world, the '
                       'frame osgshadow renders in. near/far: OSG computes them every frame '
                       '(COMPUTE_NEAR_FAR_USING_BOUNDING_VOLUMES); checks.camera_obj gives the '
                       'values of the last frame.',
        'sun': cam['sun'],
        'environment': run['environment'],
        'results': results,
        'problems': problems,
    }
    with open(os.path.join(out, 'summary.json'), 'w') as f:
        json.dump(summary, f, indent=1)
        f.write('\n')

    lines = ['| technique | median ms/frame | ratio to ' + base + ' (range over rounds) '
             '| p10–p90 ms | CPU ms/frame (ratio) | shadow passes | wall-clock cross-check ms |',
             '|---|---|---|---|---|---|---|']
    for t in techniques:
        x = results[t]
        rng = x['ratio_range']
        passes = ', '.join(f'{v}×{k}' for k, v in (x['checks'] or {}).get('shadow_map_passes', {}).items()) or '—'
        cc = x.get('crosscheck', {}).get('wall_ms_per_frame')
        lines.append(f'| {x["label"]} | {x["median_ms"]:.1f} | {x["ratio_to_" + base]:.2f} '
                     f'({rng[0]:.2f}–{rng[1]:.2f}) | {x["pooled_p10_ms"]:.1f}–{x["pooled_p90_ms"]:.1f} '
                     f'| {x["cpu_median_ms"]:.1f} ({x["cpu_ratio_to_" + base]:.2f}) | {passes} | {"—" if cc is None else f"{cc:.1f}"} |')
    table = '\n'.join(lines) + '\n'
    with open(os.path.join(out, 'table.md'), 'w') as f:
        f.write(table)
    print(table)
    for p in problems:
        print('PROBLEM:', p, file=sys.stderr)
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
