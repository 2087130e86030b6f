#!/usr/bin/env python3
"""Writes the brush images of styles/brushes/ (RGBA PNG, black ink, alpha = coverage).
Each brush is 128 x 32 (aspect 4, the length of one repetition along a stroke over its width)
and tiles along x: every pattern is periodic over the image width, so seams do not show.
Standard library only; deterministic (fixed seeds). Usage: scripts/make_brushes.py [OUT_DIR]"""
import math, random, struct, sys, zlib, os

W, H = 128, 32

def png(path, alpha_rows):
    raw = b"".join(b"\x00" + b"".join(struct.pack("BBBB", 0, 0, 0, a) for a in row) for row in alpha_rows)
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xffffffff)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 6, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))

def periodic_noise(rng, octaves):
    """Sum of sines with integer periods over W in x: tiles along the stroke."""
    terms = [(rng.randint(1, 3 * 2 ** o), rng.uniform(0.5, 3.0) * 2 ** o, rng.uniform(0, 6.283), 0.5 ** o)
             for o in range(octaves) for _ in range(3)]
    return lambda x, y: sum(a * math.sin(2 * math.pi * k * x / W + fy * y / H + ph) for k, fy, ph, a in terms)

def clamp(v):
    return max(0, min(255, int(round(v))))

def charcoal(rng):
    n = periodic_noise(rng, 4)
    edge = periodic_noise(rng, 2)
    grain = [[rng.random() for _ in range(W)] for _ in range(H)]
    rows = []
    for y in range(H):
        row = []
        for x in range(W):
            v = (y + 0.5) / H * 2 - 1                      # -1 .. 1 across the stroke
            half = 0.78 + 0.12 * edge(x, 0) / 2            # ragged edges
            body = max(0.0, 1 - (abs(v) / half) ** 4)
            tex = 0.82 + 0.08 * n(x, y) / 2 + 0.6 * (grain[y][x] - 0.5)   # paper grain
            row.append(clamp(255 * body * max(0.0, min(1.0, tex))))
        rows.append(row)
    return rows

def ink(rng):
    edge = periodic_noise(rng, 2)
    streak = [rng.uniform(0.8, 1.0) for _ in range(H)]   # bristle streaks along the stroke
    rows = []
    for y in range(H):
        row = []
        for x in range(W):
            v = (y + 0.5) / H * 2 - 1
            half = 0.88 + 0.06 * edge(x, y * 0.2) / 2
            d = abs(v) / half
            body = 1.0 if d < 0.85 else max(0.0, 1 - (d - 0.85) / 0.15)
            row.append(clamp(255 * body * streak[y]))
        rows.append(row)
    return rows

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "styles", "brushes")
os.makedirs(out, exist_ok=True)
png(os.path.join(out, "charcoal.png"), charcoal(random.Random(11)))
png(os.path.join(out, "ink.png"), ink(random.Random(5)))
