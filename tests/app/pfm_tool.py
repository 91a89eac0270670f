"""Reads PFM files without svetlo, for tests/app/results_test.sh.

  pfm_tool.py crop-equal FULL PART X0 X1 Y0 Y1   exit 0 when PART holds FULL's window bit for bit
  pfm_tool.py pixel FILE X Y                     prints the pixel's r g b (row 0 is the top)
  pfm_tool.py rmse2 A B                          prints mean (a - b)² over pixels and channels
  pfm_tool.py values FILE CHANNEL                prints the distinct values of a channel (0-2)
  pfm_tool.py channel-sum FILE                   exit 0 when every pixel's b is r + g
  pfm_tool.py agree A B TOLERANCE [complement]   prints the fraction of pixels whose r channels
                                                 differ by at most TOLERANCE (A's against 1 - B's)
"""
import struct
import sys


def read(path):
    with open(path, "rb") as f:
        data = f.read()
    fields, pos = [], 0
    while len(fields) < 4:  # PF, width, height, scale, separated by whitespace
        while data[pos : pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos : pos + 1].isspace():
            pos += 1
        fields.append(data[start:pos].decode())
    pos += 1
    assert fields[0] == "PF" and float(fields[3]) < 0, "little-endian RGB PFM expected"
    w, h = int(fields[1]), int(fields[2])
    values = struct.unpack("<%df" % (w * h * 3), data[pos : pos + w * h * 12])
    rows = [values[(h - 1 - j) * w * 3 : (h - j) * w * 3] for j in range(h)]  # top row first
    return w, h, rows


def main():
    cmd = sys.argv[1]
    if cmd == "crop-equal":
        fw, fh, full = read(sys.argv[2])
        pw, ph, part = read(sys.argv[3])
        x0, x1, y0, y1 = map(int, sys.argv[4:8])
        if (pw, ph) != (x1 - x0, y1 - y0):
            print("size %dx%d, window %dx%d" % (pw, ph, x1 - x0, y1 - y0))
            return 1
        for j in range(ph):
            if part[j] != full[y0 + j][3 * x0 : 3 * x1]:
                print("row %d differs" % j)
                return 1
        return 0
    if cmd == "pixel":
        w, h, rows = read(sys.argv[2])
        x, y = int(sys.argv[3]), int(sys.argv[4])
        print("%.9g %.9g %.9g" % tuple(rows[y][3 * x : 3 * x + 3]))
        return 0
    if cmd == "rmse2":
        _, _, a = read(sys.argv[2])
        _, _, b = read(sys.argv[3])
        diffs = [(p - q) ** 2 for ra, rb in zip(a, b) for p, q in zip(ra, rb)]
        print("%.9g" % (sum(diffs) / len(diffs)))
        return 0
    if cmd == "values":
        _, _, rows = read(sys.argv[2])
        c = int(sys.argv[3])
        print(" ".join("%.9g" % v for v in sorted({row[k] for row in rows for k in range(c, len(row), 3)})))
        return 0
    if cmd == "channel-sum":
        _, _, rows = read(sys.argv[2])
        for row in rows:
            for k in range(0, len(row), 3):
                if row[k + 2] != row[k] + row[k + 1]:
                    print("b %g is not r %g + g %g" % (row[k + 2], row[k], row[k + 1]))
                    return 1
        return 0
    if cmd == "agree":
        _, _, a = read(sys.argv[2])
        _, _, b = read(sys.argv[3])
        tol = float(sys.argv[4])
        flip = len(sys.argv) > 5 and sys.argv[5] == "complement"
        pairs = [(ra[k], 1 - rb[k] if flip else rb[k]) for ra, rb in zip(a, b) for k in range(0, len(ra), 3)]
        print("%.6f" % (sum(abs(p - q) <= tol for p, q in pairs) / len(pairs)))
        return 0
    if cmd == "worst-relative":  # the largest |a - b| / max(|b|, floor) of two images
        _, _, a = read(sys.argv[2])
        _, _, b = read(sys.argv[3])
        floor = float(sys.argv[4])
        print("%.3g" % max(abs(p - q) / max(abs(q), floor) for ra, rb in zip(a, b)
                           for p, q in zip(ra, rb)))
        return 0
    return 2


if __name__ == "__main__":
    sys.exit(main())
