#!/usr/bin/env python3
"""Compares the C example's JSON with `sceneinfo measure --json` (and, when given, the
CLI's `--matrix` CSV with the example's form_factor_matrix), bit for bit.

    compare_cli.py C.json CLI.json [F.csv]

Every number of the CLI's report (but its timings) must be in the C output with the same
bits; so must its booleans and warnings. Exit status 1 on the first difference.
"""
import json
import struct
import sys

# Timings; the method's name (the C output has its SiMethod code); the loader's warnings,
# which the CLI filters for visibility jobs (the C example prints them all on stderr); the
# solver's name (the job chose it)
IGNORED = {"seconds", "lines_per_second", "form_factors", "load_warnings", "solver"}


def bits(x):
    return struct.pack("<d", float(x))


def same(a, b):
    """Equal numbers have equal bits (so 0.0 and -0.0 differ, as they should here)."""
    return struct.pack("<d", float(a)) == struct.pack("<d", float(b))


def compare(c, cli, path, counts):
    for key, want in cli.items():
        if not path and key in IGNORED:
            continue
        where = path + key
        if isinstance(want, dict):
            compare(c.get(key, {}), want, where + ".", counts)
        elif isinstance(want, bool):
            # The verdicts (row_stochastic, ...) are the caller's to draw; background is there
            if key in c and c[key] is not want:
                sys.exit(f"{where}: C {c[key]!r} != CLI {want!r}")
            counts[0] += key in c
        elif want is None:
            # Undefined (some patch without a line): C leaves the key out or prints null
            if c.get(key) is not None:
                sys.exit(f"{where}: C {c[key]!r}, CLI null")
        elif isinstance(want, (int, float, list)):
            if key not in c:
                sys.exit(f"{where}: missing from the C output")
            if key == "warnings":
                # The report's are the channel's; the façade's Measurement adds the
                # few-observations warning of I_S^c's standard error
                ok = all(w in c[key] for w in want)
            elif isinstance(want, list):
                ok = len(c[key]) == len(want) and all(
                    same(g, w) if isinstance(w, (int, float)) else g == w
                    for g, w in zip(c[key], want))
            else:
                ok = same(c[key], want)
            if not ok:
                sys.exit(f"{where}: C {c[key]!r} != CLI {want!r}")
            counts[0] += len(want) if isinstance(want, list) else 1


def main():
    c = json.load(open(sys.argv[1]))
    cli = json.load(open(sys.argv[2]))
    counts = [0]
    compare(c, cli, "", counts)
    entries = 0
    if len(sys.argv) > 3:
        rows = [line.split(",") for line in open(sys.argv[3]).read().splitlines()]
        matrix = c.get("form_factor_matrix")
        if matrix is None or len(matrix) != len(rows):
            sys.exit("form_factor_matrix: missing or of another size than the CLI's CSV")
        for i, (got, want) in enumerate(zip(matrix, rows)):
            if len(got) != len(want) or not all(same(g, w) for g, w in zip(got, want)):
                sys.exit(f"form factors, row {i}: C and CLI differ")
            entries += len(want)
    print(f"    bit-identical: {counts[0]} values of the report" +
          (f" and {entries} form factors" if entries else ""))


main()
