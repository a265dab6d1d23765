#!/usr/bin/env python3
"""A partial file of exact rows (`formfactors --rows A..B --partial X.sir`) as `i,j,F_ij,error`
lines for `scripts/estimate_check.py`, every pair the rows hold, also those whose value is 0
(`formfactors --out F.ijv` leaves out zero entries and their estimates). Values before the
capping of rows above 1 (`cap_rows`), which needs the whole job. Prints the file's counts.

Layout: core/src/api/exact_rows.rs (version 1). Usage: scripts/exact_rows_ijv.py X.sir [OUT.ijv]
"""
import struct
import sys


def read(path):
    b = open(path, "rb").read()
    if b[:8] != b"SCNINFOR":
        sys.exit(f"{path}: not a file of exact rows")
    o = 12
    _scene, tol, _cap, n, r0, r1 = struct.unpack_from("<QdQQQQ", b, o)
    o += 48 + 1
    integrated, over, points = struct.unpack_from("<QQQ", b, o)
    o += 24
    areas = struct.unpack_from(f"<{n}d", b, o + 8 * n)
    o += 24 * n + 8
    counts = struct.unpack_from(f"<{r1 - r0}Q", b, o)
    o += 8 * (r1 - r0)
    rows = []
    for i, c in zip(range(r0, r1), counts):
        row = [struct.unpack_from("<Idd", b, o + 20 * k) for k in range(c)]
        o += 20 * c
        rows.append((i, row))
    return dict(tol=tol, rows=(r0, r1), integrated=integrated, over=over, points=points,
                areas=areas, pairs=rows)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    d = read(sys.argv[1])
    pairs = sum(len(r) for _, r in d["pairs"])
    print(f"{sys.argv[1]}: rows {d['rows'][0]}..{d['rows'][1]}, tolerance {d['tol']:g}, "
          f"{d['integrated']} pairs integrated, {d['over']} over the tolerance, "
          f"{d['points']} points, {pairs} pairs stored")
    if len(sys.argv) > 2:
        a = d["areas"]
        with open(sys.argv[2], "w") as f:
            for i, row in d["pairs"]:
                for j, flux, err in row:
                    f.write(f"{i},{j},{flux / a[i]!r},{err / a[i]!r}\n")
                    f.write(f"{j},{i},{flux / a[j]!r},{err / a[j]!r}\n")


if __name__ == "__main__":
    main()
