"""ꟻLIP computed a second way, for tests/app/results_test.sh: straight from the papers' 2D
kernels (Andersson et al., HPG 2020; HDR-ꟻLIP, EG 2021), in numpy, with none of svetlo's
code (its filters are separable passes in float). Prints the mean.

  flip_reference.py ldr REFERENCE.png TEST.png
  flip_reference.py hdr REFERENCE.pfm TEST.pfm
"""
import struct
import sys
import zlib

import numpy as np

PPD = 0.7 * 3840 / 0.7 * np.pi / 180


def read_png(path):
    """8-bit RGB, non-interlaced PNG (as svetlo writes it) -> values in [0, 1], H x W x 3."""
    data = open(path, "rb").read()
    pos, idat, w, h = 8, b"", 0, 0
    while pos < len(data):
        n = struct.unpack(">I", data[pos : pos + 4])[0]
        kind, body = data[pos + 4 : pos + 8], data[pos + 8 : pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, color = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and color == 2, "8-bit RGB expected"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(h, 1 + 3 * w)
    out = np.zeros((h, 3 * w), np.int32)
    for j in range(h):
        f, line = raw[j, 0], raw[j, 1:].astype(np.int32)
        prev = out[j - 1] if j > 0 else np.zeros(3 * w, np.int32)
        row = np.zeros(3 * w, np.int32)
        for i in range(3 * w):
            a = row[i - 3] if i >= 3 else 0
            b = prev[i]
            c = prev[i - 3] if i >= 3 else 0
            if f == 0:
                p = 0
            elif f == 1:
                p = a
            elif f == 2:
                p = b
            elif f == 3:
                p = (a + b) // 2
            else:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            row[i] = (line[i] + p) & 255
        out[j] = row
    return out.reshape(h, w, 3) / 255.0


def read_pfm(path):
    data = open(path, "rb").read()
    parts = data.split(maxsplit=4)
    w, h = int(parts[1]), int(parts[2])
    values = np.frombuffer(data[len(data) - w * h * 12 :], "<f4").reshape(h, w, 3)
    return values[::-1].astype(np.float64)


def srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


M = np.array([[10135552 / 24577794, 8788810 / 24577794, 4435075 / 24577794],
              [2613072 / 12288897, 8788810 / 12288897, 887015 / 12288897],
              [1425312 / 73733382, 8788810 / 73733382, 70074185 / 73733382]])
WHITE = np.array([0.950428545, 1.0, 1.088900371])


def ycxcz(rgb):
    n = rgb @ M.T / WHITE
    return np.stack([116 * n[..., 1] - 16, 500 * (n[..., 0] - n[..., 1]),
                     200 * (n[..., 1] - n[..., 2])], -1)


def ycxcz_to_rgb(o):
    y = (o[..., 0] + 16) / 116
    xyz = np.stack([y + o[..., 1] / 500, y, y - o[..., 2] / 200], -1) * WHITE
    return xyz @ np.linalg.inv(M).T


def hunt_lab(rgb):
    t = rgb @ M.T / WHITE
    d = 6 / 29
    f = np.where(t > d ** 3, np.cbrt(t), t / (3 * d * d) + 4 / 29)
    L = 116 * f[..., 1] - 16
    return np.stack([L, 0.01 * L * 500 * (f[..., 0] - f[..., 1]),
                     0.01 * L * 200 * (f[..., 1] - f[..., 2])], -1)


def hyab(a, b):
    d = a - b
    return np.abs(d[..., 0]) + np.hypot(d[..., 1], d[..., 2])


def filter2d(plane, kernel):
    """Correlation with edge pixels repeated, the whole 2D kernel at once."""
    r = kernel.shape[0] // 2
    padded = np.pad(plane, r, mode="edge")
    h, w = plane.shape
    out = np.zeros_like(plane)
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            out += kernel[dy + r, dx + r] * padded[r + dy : r + dy + h, r + dx : r + dx + w]
    return out


def csf(a1, b1, a2, b2):
    r = int(np.ceil(3 * np.sqrt(0.04 / (2 * np.pi ** 2)) * PPD))
    x, y = np.meshgrid(range(-r, r + 1), range(-r, r + 1))
    z = (x / PPD) ** 2 + (y / PPD) ** 2
    s = a1 * np.sqrt(np.pi / b1) * np.exp(-np.pi ** 2 * z / b1)
    if a2:
        s += a2 * np.sqrt(np.pi / b2) * np.exp(-np.pi ** 2 * z / b2)
    return s / s.sum()


def feature_kernel(kind):
    sd = 0.5 * 0.082 * PPD
    r = int(np.ceil(3 * sd))
    x, y = np.meshgrid(range(-r, r + 1), range(-r, r + 1))
    g = np.exp(-(x ** 2 + y ** 2) / (2 * sd * sd))
    k = -x * g if kind == "edge" else (x ** 2 / (sd * sd) - 1) * g
    return np.where(k < 0, k / -k[k < 0].sum(), np.where(k > 0, k / k[k > 0].sum(), 0.0))


def ldr_flip(ref, test):
    """Per-pixel LDR-ꟻLIP of two linear RGB images in [0, 1]."""
    kernels = [csf(1, 0.0047, 0, 0), csf(1, 0.0053, 0, 0), csf(34.1, 0.04, 13.5, 0.025)]
    labs, ys = [], []
    for img in (ref, test):
        o = ycxcz(np.clip(img, 0, 1))
        filtered = np.stack([filter2d(o[..., c], kernels[c]) for c in range(3)], -1)
        labs.append(hunt_lab(np.clip(ycxcz_to_rgb(filtered), 0, 1)))
        ys.append((o[..., 0] + 16) / 116)
    cmax = hyab(hunt_lab(np.array([0.0, 1, 0])), hunt_lab(np.array([0.0, 0, 1]))) ** 0.7
    c = hyab(labs[0], labs[1]) ** 0.7
    color = np.where(c < 0.4 * cmax, 0.95 / (0.4 * cmax) * c,
                     0.95 + (c - 0.4 * cmax) / (cmax - 0.4 * cmax) * 0.05)
    mags = []
    for kind in ("edge", "point"):
        k = feature_kernel(kind)
        mags.append([np.hypot(filter2d(y, k), filter2d(y, k.T)) for y in ys])
    f = np.maximum(np.abs(mags[0][0] - mags[0][1]), np.abs(mags[1][0] - mags[1][1]))
    return color ** (1 - (f / np.sqrt(2)) ** 0.5)


def aces(x):
    k = [0.6 * 0.6 * 2.51, 0.6 * 0.03, 0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14]
    return np.clip((k[0] * x * x + k[1] * x + k[2]) / (k[3] * x * x + k[4] * x + k[5]), 0, 1)


def hdr_flip(ref, test):
    k = [0.6 * 0.6 * 2.51, 0.6 * 0.03, 0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14]
    t = 0.85
    c0 = (k[1] - k[4] * t) / (k[0] - k[3] * t)
    c1 = (k[2] - k[5] * t) / (k[0] - k[3] * t)
    x = -0.5 * c0 + np.sqrt(0.25 * c0 * c0 - c1)
    lum = np.maximum(ref, 0) @ np.array([0.2126, 0.7152, 0.0722])
    flat = np.sort(lum.ravel())
    median = max(flat[flat.size // 2], np.finfo(np.float32).eps)
    start, stop = np.log2(x / lum.max()), np.log2(x / median)
    n = max(2, int(np.ceil(stop - start)))
    errors = [ldr_flip(aces(2 ** e * np.maximum(ref, 0)), aces(2 ** e * np.maximum(test, 0)))
              for e in np.linspace(start, stop, n)]
    return np.max(errors, axis=0)


def main():
    mode, a, b = sys.argv[1:4]
    if mode == "ldr":
        ref, test = srgb_to_linear(read_png(a)), srgb_to_linear(read_png(b))
        print("%.9f" % ldr_flip(ref, test).mean())
    else:
        print("%.9f" % hdr_flip(read_pfm(a), read_pfm(b)).mean())


main()
