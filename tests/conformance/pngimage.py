"""A small RGB image type for the conformance criteria: read and write 8-bit PNG with zlib only.

pnb-play's --screenshot writes 8-bit RGB or RGBA PNGs (player/src/image_write); this reader takes
any non-interlaced 8-bit greyscale, grey+alpha, RGB, RGBA or palette PNG and keeps RGB. Stdlib
only: the tests run under whatever python3 is on PATH (a pyenv one may lack numpy).
"""

import struct
import zlib

_CHANNELS = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}


class Image:
    """width x height RGB, 8 bits a channel, rows top to bottom (px[(y * w + x) * 3 + c])."""

    def __init__(self, width, height, px=None):
        self.w = width
        self.h = height
        self.px = px if px is not None else bytearray(width * height * 3)

    def get(self, x, y):
        i = (y * self.w + x) * 3
        return self.px[i], self.px[i + 1], self.px[i + 2]

    def put(self, x, y, rgb):
        i = (y * self.w + x) * 3
        self.px[i:i + 3] = bytes(rgb)

    def pixels(self):
        """Yields (x, y, r, g, b) for every pixel."""
        px, w = self.px, self.w
        for y in range(self.h):
            row = y * w * 3
            for x in range(w):
                i = row + x * 3
                yield x, y, px[i], px[i + 1], px[i + 2]

    def crop(self, x0, y0, x1, y1):
        out = Image(x1 - x0, y1 - y0)
        for y in range(y0, y1):
            out.px[(y - y0) * out.w * 3:(y - y0 + 1) * out.w * 3] = \
                self.px[(y * self.w + x0) * 3:(y * self.w + x1) * 3]
        return out


def _paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def read_png(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG file")
    pos, idat, palette = 8, [], None
    width = height = depth = ctype = interlace = None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        tag = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if tag == b"IHDR":
            width, height, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif tag == b"PLTE":
            palette = body
        elif tag == b"IDAT":
            idat.append(body)
        elif tag == b"IEND":
            break
    if width is None or depth != 8 or interlace != 0 or ctype not in _CHANNELS:
        raise ValueError(f"{path}: only non-interlaced 8-bit PNGs are read here "
                         f"(depth {depth}, colour type {ctype}, interlace {interlace})")
    n = _CHANNELS[ctype]
    raw = zlib.decompress(b"".join(idat))
    stride = width * n
    img = Image(width, height)
    prev = bytearray(stride)
    for y in range(height):
        ft = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if ft == 1:
            for i in range(n, stride):
                line[i] = (line[i] + line[i - n]) & 255
        elif ft == 2:
            for i in range(stride):
                line[i] = (line[i] + prev[i]) & 255
        elif ft == 3:
            for i in range(stride):
                left = line[i - n] if i >= n else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 255
        elif ft == 4:
            for i in range(stride):
                left = line[i - n] if i >= n else 0
                ul = prev[i - n] if i >= n else 0
                line[i] = (line[i] + _paeth(left, prev[i], ul)) & 255
        elif ft != 0:
            raise ValueError(f"{path}: bad PNG filter {ft} in row {y}")
        o = y * width * 3
        if ctype == 2:
            img.px[o:o + width * 3] = line
        elif ctype == 6:
            for x in range(width):
                img.px[o + x * 3:o + x * 3 + 3] = line[x * 4:x * 4 + 3]
        elif ctype == 3:
            for x in range(width):
                k = line[x] * 3
                img.px[o + x * 3:o + x * 3 + 3] = palette[k:k + 3]
        else:  # grey, grey + alpha
            for x in range(width):
                v = line[x * n]
                img.px[o + x * 3:o + x * 3 + 3] = bytes((v, v, v))
        prev = line
    return img


def write_png(path, img):
    def chunk(tag, body):
        return (struct.pack(">I", len(body)) + tag + body
                + struct.pack(">I", zlib.crc32(tag + body) & 0xFFFFFFFF))

    rows = bytearray()
    for y in range(img.h):
        rows.append(0)
        rows += img.px[y * img.w * 3:(y + 1) * img.w * 3]
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n"
                + chunk(b"IHDR", struct.pack(">IIBBBBB", img.w, img.h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(bytes(rows), 6)) + chunk(b"IEND", b""))
