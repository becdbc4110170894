"""Image measurements the conformance criteria are written in (stdlib only, see pngimage.py).

Everything locates features by colour and connected regions, never by fixed pixel coordinates,
so a criterion holds under any framing that shows the model whole.
"""

import colorsys
import math


def lum(r, g, b):
    """Luma of 8-bit sRGB values, 0..1 (a ranking, not a photometric figure)."""
    return (0.2126 * r + 0.7152 * g + 0.0722 * b) / 255.0


def hue_class(r, g, b, min_sat=0.45, min_val=0.18):
    """'red', 'orange', 'yellow', 'green', 'cyan', 'blue', 'magenta', or None when the pixel is
    too grey or too dark to have a reliable hue. Lighting changes value, not hue."""
    h, s, v = colorsys.rgb_to_hsv(r / 255.0, g / 255.0, b / 255.0)
    if s < min_sat or v < min_val:
        return None
    deg = h * 360.0
    if deg < 15 or deg >= 335:
        return "red"
    if deg < 40:
        return "orange"
    if deg < 70:
        return "yellow"
    if deg < 160:
        return "green"
    if deg < 200:
        return "cyan"
    if deg < 260:
        return "blue"
    return "magenta"


class Mask:
    """A boolean image (bytearray of 0/1), with region helpers."""

    def __init__(self, w, h, bits=None):
        self.w, self.h = w, h
        self.bits = bits if bits is not None else bytearray(w * h)

    @staticmethod
    def where(img, pred):
        m = Mask(img.w, img.h)
        px = img.px
        for i in range(img.w * img.h):
            if pred(px[3 * i], px[3 * i + 1], px[3 * i + 2]):
                m.bits[i] = 1
        return m

    def count(self):
        return sum(self.bits)

    def bbox(self):
        xs = [i % self.w for i in range(len(self.bits)) if self.bits[i]]
        ys = [i // self.w for i in range(len(self.bits)) if self.bits[i]]
        if not xs:
            return None
        return min(xs), min(ys), max(xs) + 1, max(ys) + 1

    def dilate(self, steps=1):
        """Grown by `steps` pixels (4-neighbourhood): joins parts a shading edge split."""
        bits, w, h = self.bits, self.w, self.h
        for _ in range(steps):
            out = bytearray(bits)
            for i in range(w * h):
                if bits[i]:
                    x = i % w
                    if x > 0: out[i - 1] = 1
                    if x < w - 1: out[i + 1] = 1
                    if i >= w: out[i - w] = 1
                    if i < w * (h - 1): out[i + w] = 1
            bits = out
        return Mask(w, h, bits)

    def components(self, min_size=1):
        """Connected regions (4-neighbourhood), largest first, as Region objects."""
        seen = bytearray(self.bits)  # 1 = unvisited foreground
        w, h = self.w, self.h
        out = []
        for start in range(w * h):
            if not seen[start]:
                continue
            seen[start] = 0
            stack, pixels = [start], []
            while stack:
                i = stack.pop()
                pixels.append(i)
                x, y = i % w, i // w
                for j, ok in ((i - 1, x > 0), (i + 1, x < w - 1), (i - w, y > 0), (i + w, y < h - 1)):
                    if ok and seen[j]:
                        seen[j] = 0
                        stack.append(j)
            if len(pixels) >= min_size:
                out.append(Region(pixels, w))
        out.sort(key=lambda r: -r.size)
        return out


class Region:
    def __init__(self, pixels, w):
        self.pixels = pixels
        self.w = w
        self.size = len(pixels)
        xs = [i % w for i in pixels]
        ys = [i // w for i in pixels]
        self.cx = sum(xs) / self.size
        self.cy = sum(ys) / self.size
        self.x0, self.x1, self.y0, self.y1 = min(xs), max(xs) + 1, min(ys), max(ys) + 1

    @property
    def width(self):
        return self.x1 - self.x0

    @property
    def height(self):
        return self.y1 - self.y0

    def fill(self):
        """Fraction of its bounding box the region covers (a disc: pi/4)."""
        return self.size / float(self.width * self.height)

    def axis(self):
        """Unit principal axis (dx, dy) of the pixels and the spread along it and across it."""
        sxx = syy = sxy = 0.0
        for i in self.pixels:
            dx, dy = i % self.w - self.cx, i // self.w - self.cy
            sxx += dx * dx
            syy += dy * dy
            sxy += dx * dy
        sxx, syy, sxy = sxx / self.size, syy / self.size, sxy / self.size
        angle = 0.5 * math.atan2(2 * sxy, sxx - syy)
        ax, ay = math.cos(angle), math.sin(angle)
        tr, det = sxx + syy, sxx * syy - sxy * sxy
        disc = math.sqrt(max(tr * tr / 4 - det, 0))
        return (ax, ay), math.sqrt(tr / 2 + disc), math.sqrt(max(tr / 2 - disc, 0))

    def pointing(self):
        """For an arrow-shaped region: the unit direction from its tail to its head. The head holds
        more pixels than the shaft, so the pixels' distribution along the axis is skewed away from
        the head (its third moment is negative in the head's direction)."""
        (ax, ay), _, _ = self.axis()
        m3 = 0.0
        for i in self.pixels:
            t = (i % self.w - self.cx) * ax + (i // self.w - self.cy) * ay
            m3 += t * t * t
        return (-ax, -ay) if m3 > 0 else (ax, ay)


def mean_colour(img, pixels):
    n = max(len(pixels), 1)
    px = img.px
    return tuple(sum(px[3 * i + c] for i in pixels) / n for c in range(3))


def lum_stats(img, pixels):
    px = img.px
    vals = [lum(px[3 * i], px[3 * i + 1], px[3 * i + 2]) for i in pixels]
    n = max(len(vals), 1)
    mean = sum(vals) / n
    return mean, math.sqrt(sum((v - mean) ** 2 for v in vals) / n)


def lit_side(img, region, inner=None):
    """Where the light comes from within a region: the offset of its centroid weighted by luma
    above the darkest pixel's from its plain centroid, in units of the region's radius:
    (dx, dy, magnitude). inner: only the disc of that fraction of the region's half-size around
    its box centre (the bump of a test cell, without the flat frame around it)."""
    px, w = img.px, region.w
    pixels = region.pixels
    if inner:
        bx, by = (region.x0 + region.x1 - 1) / 2, (region.y0 + region.y1 - 1) / 2
        rad = inner * min(region.width, region.height) / 2
        pixels = [i for i in pixels if (i % w - bx) ** 2 + (i // w - by) ** 2 <= rad * rad]
    if not pixels:
        return 0.0, 0.0, 0.0
    ls = [lum(px[3 * i], px[3 * i + 1], px[3 * i + 2]) for i in pixels]
    lo = min(ls)
    sw = sx = sy = cx = cy = 0.0
    for i, l in zip(pixels, ls):
        x, y = i % w, i // w
        cx += x
        cy += y
        sw += l - lo
        sx += (l - lo) * x
        sy += (l - lo) * y
    if sw <= 0:
        return 0.0, 0.0, 0.0
    n = len(pixels)
    r = max(math.sqrt(n / math.pi), 1.0)
    dx, dy = (sx / sw - cx / n) / r, (sy / sw - cy / n) / r
    return dx, dy, math.hypot(dx, dy)


def angle_between(a, b):
    la, lb = math.hypot(*a), math.hypot(*b)
    if la == 0 or lb == 0:
        return 180.0
    c = max(-1.0, min(1.0, (a[0] * b[0] + a[1] * b[1]) / (la * lb)))
    return math.degrees(math.acos(c))


def border_background(img):
    """Mean colour and luma spread of the image's outermost rows and columns."""
    idx = [x for x in range(img.w)] + [(img.h - 1) * img.w + x for x in range(img.w)]
    idx += [y * img.w for y in range(img.h)] + [y * img.w + img.w - 1 for y in range(img.h)]
    mean, spread = lum_stats(img, idx)
    return mean_colour(img, idx), mean, spread


def resample_lum(img, box, n):
    """n x n mean-luma grid over box (x0, y0, x1, y1): tiles compared independently of size."""
    x0, y0, x1, y1 = box
    out = []
    for gy in range(n):
        for gx in range(n):
            ax, bx = x0 + (x1 - x0) * gx // n, x0 + (x1 - x0) * (gx + 1) // n
            ay, by = y0 + (y1 - y0) * gy // n, y0 + (y1 - y0) * (gy + 1) // n
            vals = [lum(*img.get(x, y)) for y in range(ay, max(by, ay + 1))
                    for x in range(ax, max(bx, ax + 1))]
            out.append(sum(vals) / len(vals))
    return out


def correlation(a, b):
    n = len(a)
    ma, mb = sum(a) / n, sum(b) / n
    va = sum((x - ma) ** 2 for x in a)
    vb = sum((y - mb) ** 2 for y in b)
    if va <= 1e-12 or vb <= 1e-12:
        return 0.0
    return sum((x - ma) * (y - mb) for x, y in zip(a, b)) / math.sqrt(va * vb)
