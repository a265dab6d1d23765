#!/usr/bin/env python3
"""Entries of two sparse form-factor files (`formfactors --out F.ijv`: i,j,F,error per line)
where |F_a - F_b| exceeds err_a + err_b: where at least one run's error estimate is wrong.

The estimates bound the integration's error, not the rounding of the sums that make an entry:
a difference within ROUNDING * max(|F_a|, |F_b|) (a few thousand units in the last place) is
counted apart as rounding, not as a miss.

Usage: scripts/estimate_check.py A.ijv B.ijv [N]   (prints the N worst, default 10)
"""
import sys

ROUNDING = 1e-12


def read(path):
    entries = {}
    with open(path) as f:
        for line in f:
            parts = line.strip().split(",")
            try:
                i, j, value, err = int(parts[0]), int(parts[1]), float(parts[2]), float(parts[3])
            except (ValueError, IndexError):
                continue  # a header or a blank line
            entries[(i, j)] = (value, err)
    return entries


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    a, b = read(sys.argv[1]), read(sys.argv[2])
    shown = int(sys.argv[3]) if len(sys.argv) > 3 else 10
    bad = []
    rounding = 0
    for key in sorted(set(a) | set(b)):
        fa, ea = a.get(key, (0.0, 0.0))
        fb, eb = b.get(key, (0.0, 0.0))
        if abs(fa - fb) <= ea + eb:
            continue
        if abs(fa - fb) <= ROUNDING * max(abs(fa), abs(fb)):
            rounding += 1
        else:
            bad.append((abs(fa - fb) / max(ea + eb, 1e-300), key, fa, ea, fb, eb))
    bad.sort(reverse=True)
    pairs = {tuple(sorted(x[1])) for x in bad}
    print(f"entries {len(a)} / {len(b)}; outside the sum of the two estimates: "
          f"{len(bad)} entries, {len(pairs)} pairs (and {rounding} entries apart by rounding only)")
    for ratio, (i, j), fa, ea, fb, eb in bad[:shown]:
        print(f"  ({i},{j}) {ratio:.3g}x: {fa:.6e} ±{ea:.2e} vs {fb:.6e} ±{eb:.2e}")


if __name__ == "__main__":
    main()
