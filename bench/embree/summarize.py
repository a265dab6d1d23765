#!/usr/bin/env python3
"""Summarize bench.py's JSONL log: M lines/s (min / median / max over repetitions) per
scene and configuration, hits per line, and the sceneinfo / Embree ratios, taken rep by
rep (the runs of one rep and scene ran back to back) and then their median.

    python3 summarize.py results/run.jsonl

sceneinfo rates:
  reported  its own `lines_per_second` = lines / seconds, where `seconds` runs from the
            start of `measure` to the report: scene load + BVH + matrix + casting +
            tally + entropies etc.
  marginal  (L - L0) / (s(L) - s(L0)) from the L = 1e7 run and the L0 = 1e6 run of the
            same rep, scene, method and threads: the fixed cost cancels, leaving casting
            + tally (the per-line cost).
Embree rates: lines / seconds of the casting loop only (BVH build reported apart).

Like with like (bench.py's `filtertally` and `--split` runs):
  Embree filter+tally  filter's hits of each line fed into a tally of sceneinfo's shape
            (counts, I_S^c terms; embree_lines.cpp, `Tally`), casting loop timed
  split full / alone  `sceneinfo bench --split`: the same lines with the full tally and cast
            alone (hits counted, not tallied), marginal rates of jobs of L and 2L lines
            timed inside one process (no load, BVH or report in either)
  ratios    casting alone against casting alone (sceneinfo alone / Embree filter or closest),
            casting + the same tally against it (sceneinfo full / Embree filter+tally), and
            each side's tally share (1 - with tally / without)
"""
import json
import statistics
import sys
from collections import defaultdict

SCENE_NAMES = {"cube30": "cube 5400", "cornell10": "cornell grid 10 (810)", "room512": "room 512 cubes (3672)"}


DISTURBED = 0.05  # a run during which other processes used more than 5% of all CPUs


def main(path):
    recs = [json.loads(l) for l in open(path) if l.strip()]
    bad = [r for r in recs if r.get("others_share", 0) > DISTURBED]
    runs = defaultdict(dict)  # (scene, rep) -> key -> rec
    for r in recs:
        if r["tool"] == "embree":
            key = ("E", r["mode"], r["threads"])
        elif r["tool"] == "split":
            key = ("X",)
        else:
            big = r["requested"] >= 5_000_000
            key = ("S", r["mode"], r["threads"], "L" if big else "L0")
        d = runs[(r["scene"], r["rep"])]
        # a disturbed run (bench.py ran it again) counts only if no clean attempt exists
        if not r.get("disturbed") or key not in d or d[key].get("disturbed"):
            if not (r.get("disturbed") and key in d and not d[key].get("disturbed")):
                d[key] = r
    scenes = []
    for s, _ in runs:
        if s not in scenes:
            scenes.append(s)
    reps = sorted({rep for _, rep in runs})

    def rate(scene, rep, cfg):
        d = runs[(scene, rep)]
        if cfg[0] == "E":
            r = d.get(cfg)
            return r["lines_per_s"] if r else None
        if cfg[0] == "EC":  # Embree per CPU second of its threads
            r = d.get(("E",) + cfg[1:])
            return r["lines"] / r["cpu_s"] if r and r.get("cpu_s") else None
        if cfg[0] == "X":  # ("X", method, threads, "full" | "alone" | "full_cpu" | "alone_cpu")
            r = d.get(("X",))
            row = r["rows"].get(f"{cfg[1]}_{cfg[2]}t") if r else None
            return row.get(cfg[3]) if row else None
        _, mode, t, kind = cfg
        big, small = d.get(("S", mode, t, "L")), d.get(("S", mode, t, "L0"))
        if big is None:
            return None
        if kind == "reported":
            return big["lines_per_s"]
        if small is None:
            return None
        return (big["lines"] - small["lines"]) / (big["seconds"] - small["seconds"])

    cfgs = [
        ("Embree closest 1t", ("E", "closest", 1)), ("Embree closest 2t", ("E", "closest", 2)),
        ("Embree all-hits 1t", ("E", "allhits", 1)), ("Embree all-hits 2t", ("E", "allhits", 2)),
        ("Embree filter all-hits 1t", ("E", "filter", 1)), ("Embree filter all-hits 2t", ("E", "filter", 2)),
        ("Embree packet8 closest 1t", ("E", "packet8", 1)),
        ("Embree filter+tally 1t", ("E", "filtertally", 1)), ("Embree filter+tally 2t", ("E", "filtertally", 2)),
        ("sceneinfo split global full 1t", ("X", "global", 1, "full")),
        ("sceneinfo split global alone 1t", ("X", "global", 1, "alone")),
        ("sceneinfo split global full 2t", ("X", "global", 2, "full")),
        ("sceneinfo split global alone 2t", ("X", "global", 2, "alone")),
        ("sceneinfo split bundle full 1t", ("X", "bundle", 1, "full")),
        ("sceneinfo split bundle alone 1t", ("X", "bundle", 1, "alone")),
        ("sceneinfo split bundle full 2t", ("X", "bundle", 2, "full")),
        ("sceneinfo split bundle alone 2t", ("X", "bundle", 2, "alone")),
        # one thread per CPU second (robust to other load; about the wall rate when quiet)
        ("Embree filter 1t (cpu)", ("EC", "filter", 1)),
        ("Embree filter+tally 1t (cpu)", ("EC", "filtertally", 1)),
        ("Embree closest 1t (cpu)", ("EC", "closest", 1)),
        ("sceneinfo split global full 1t (cpu)", ("X", "global", 1, "full_cpu")),
        ("sceneinfo split global alone 1t (cpu)", ("X", "global", 1, "alone_cpu")),
        ("sceneinfo split bundle full 1t (cpu)", ("X", "bundle", 1, "full_cpu")),
        ("sceneinfo split bundle alone 1t (cpu)", ("X", "bundle", 1, "alone_cpu")),
        ("sceneinfo global 1t (marginal)", ("S", "global", 1, "marginal")),
        ("sceneinfo global 2t (marginal)", ("S", "global", 2, "marginal")),
        ("sceneinfo global 1t (reported)", ("S", "global", 1, "reported")),
        ("sceneinfo global 2t (reported)", ("S", "global", 2, "reported")),
        ("sceneinfo bundle 1t (marginal)", ("S", "bundle", 1, "marginal")),
        ("sceneinfo bundle 2t (marginal)", ("S", "bundle", 2, "marginal")),
        ("sceneinfo bundle 1t (reported)", ("S", "bundle", 1, "reported")),
        ("sceneinfo bundle 2t (reported)", ("S", "bundle", 2, "reported")),
    ]
    out = []
    out.append(f"log: {path}; repetitions: {len(reps)}; runs: {len(recs)}")
    shares = [r.get("others_share", 0) for r in recs]
    out.append(f"other processes' share of the CPUs during runs: median {statistics.median(shares):.4f}, "
               f"max {max(shares):.4f}; runs above {DISTURBED}: {len(bad)}")
    out.append(f"runs flagged disturbed by bench.py and run again: {sum(1 for r in recs if r.get('disturbed'))}")
    for r in bad:
        out.append(f"  others > {DISTURBED}: rep {r['rep']} {r['scene']} {r['tool']} {r['mode']} {r['threads']}t "
                   f"others {r['others_share']:.3f}")
    loads = [r.get("load_before", 0) for r in recs]
    out.append(f"1-min load before runs: min {min(loads):.2f}, median {statistics.median(loads):.2f}, "
               f"max {max(loads):.2f} (includes this run's own earlier runs)\n")
    out.append("M lines/s: min / median / max over repetitions\n")
    for scene in scenes:
        out.append(f"\n## {SCENE_NAMES.get(scene, scene)}\n")
        out.append(f"{'configuration':38} {'min':>8} {'median':>8} {'max':>8}  n")
        for name, cfg in cfgs:
            v = [x for x in (rate(scene, rep, cfg) for rep in reps) if x is not None]
            if not v:
                continue
            out.append(f"{name:38} {min(v)/1e6:8.3f} {statistics.median(v)/1e6:8.3f} {max(v)/1e6:8.3f}  {len(v)}")
        # hits per line and build times
        hp = defaultdict(list)
        extra = defaultdict(list)
        for rep in reps:
            for key, r in runs[(scene, rep)].items():
                if key[0] == "X":
                    if rep == reps[0]:
                        for k, row in sorted(r["rows"].items()):
                            if k.endswith("_1t"):
                                hp[("X", k.split("_")[0])].append((row["hits_per_line"], 2 * r["lines"]))
                            extra[f"split_same_hits_{k}"].append(float(row["same_hits"]))
                    continue
                # every rep casts the same lines (fixed seed): one 1-thread run per tool/mode
                if ("hits_per_line" in r and rep == reps[0] and key[2] == 1
                        and (key[0] == "E" or key[3] == "L")):
                    hp[(key[0], key[1])].append((r["hits_per_line"], r["lines"]))
                if key[0] == "E":
                    extra["build_s"].append(r["build_s"])
                    extra["load_s"].append(r["load_s"])
                    extra["repeats"].append(r["repeats"])
                    extra["capped"].append(r["capped"])
                    if key[2] == 1:
                        extra[f"cast_s_{key[1]}_1t"].append(r["cast_s"])
                    else:
                        extra[f"cast_s_{key[1]}_2t"].append(r["cast_s"])
                if key[0] == "S" and key[3] == "L":
                    extra[f"s_seconds_{key[1]}_{key[2]}t"].append(r["seconds"])
                    extra[f"s_wall_{key[1]}_{key[2]}t"].append(r["process_wall_s"])
                if key[0] == "S" and key[3] == "L0":
                    extra[f"s_seconds_L0_{key[1]}_{key[2]}t"].append(r["seconds"])
        out.append("\nhits per line (the 1-thread run of the first rep; lines with no hit count 0; "
                   "every rep repeats the same seeded lines):")
        for (tool, mode), v in sorted(hp.items()):
            n = sum(l for _, l in v)
            h = sum(x * l for x, l in v) / n
            who = {"E": "Embree", "S": "sceneinfo", "X": "split"}[tool]
            out.append(f"  {who:9} {mode:11} {h:.5f}  ({n:.3g} lines)")
        out.append(f"Embree BVH build s (median {statistics.median(extra['build_s']):.4f}, "
                   f"max {max(extra['build_s']):.4f}); OBJ load s median {statistics.median(extra['load_s']):.4f}; "
                   f"allhits repeats {sum(extra['repeats'])}, capped {sum(extra['capped'])}")
        for k in sorted(extra):
            if k.startswith("split_same_hits"):
                out.append(f"  {k:28} {'all' if min(extra[k]) == 1 else 'NOT ALL'} reps same hits alone/full")
            elif k.startswith("cast_s") or k.startswith("s_"):
                v = extra[k]
                out.append(f"  {k:28} min {min(v):7.3f}  median {statistics.median(v):7.3f}  max {max(v):7.3f}")
        # ratios per rep
        out.append("\nratios sceneinfo / Embree (per rep, then min / median / max):")
        pairs = [
            ("global marginal 1t / Embree all-hits 1t", ("S", "global", 1, "marginal"), ("E", "allhits", 1)),
            ("global marginal 2t / Embree all-hits 2t", ("S", "global", 2, "marginal"), ("E", "allhits", 2)),
            ("global marginal 1t / Embree filter 1t", ("S", "global", 1, "marginal"), ("E", "filter", 1)),
            ("global marginal 2t / Embree filter 2t", ("S", "global", 2, "marginal"), ("E", "filter", 2)),
            ("global marginal 1t / Embree closest 1t", ("S", "global", 1, "marginal"), ("E", "closest", 1)),
            ("global marginal 2t / Embree closest 2t", ("S", "global", 2, "marginal"), ("E", "closest", 2)),
            ("global reported 1t / Embree all-hits 1t", ("S", "global", 1, "reported"), ("E", "allhits", 1)),
            ("global reported 2t / Embree all-hits 2t", ("S", "global", 2, "reported"), ("E", "allhits", 2)),
            ("global reported 1t / Embree closest 1t", ("S", "global", 1, "reported"), ("E", "closest", 1)),
            ("global reported 2t / Embree closest 2t", ("S", "global", 2, "reported"), ("E", "closest", 2)),
            ("bundle marginal 1t / Embree all-hits 1t", ("S", "bundle", 1, "marginal"), ("E", "allhits", 1)),
            ("bundle marginal 2t / Embree all-hits 2t", ("S", "bundle", 2, "marginal"), ("E", "allhits", 2)),
            ("bundle marginal 1t / Embree closest 1t", ("S", "bundle", 1, "marginal"), ("E", "closest", 1)),
            ("bundle marginal 2t / Embree closest 2t", ("S", "bundle", 2, "marginal"), ("E", "closest", 2)),
            # like with like: casting alone against casting alone ...
            ("split global alone 1t / Embree filter 1t", ("X", "global", 1, "alone"), ("E", "filter", 1)),
            ("split global alone 2t / Embree filter 2t", ("X", "global", 2, "alone"), ("E", "filter", 2)),
            ("split bundle alone 1t / Embree closest 1t", ("X", "bundle", 1, "alone"), ("E", "closest", 1)),
            ("split bundle alone 2t / Embree closest 2t", ("X", "bundle", 2, "alone"), ("E", "closest", 2)),
            ("split bundle alone 2t / Embree filter 2t", ("X", "bundle", 2, "alone"), ("E", "filter", 2)),
            # ... and both with the same tally
            ("split global full 1t / Embree filter+tally 1t", ("X", "global", 1, "full"), ("E", "filtertally", 1)),
            ("split global full 2t / Embree filter+tally 2t", ("X", "global", 2, "full"), ("E", "filtertally", 2)),
            ("split bundle full 1t / Embree filter+tally 1t", ("X", "bundle", 1, "full"), ("E", "filtertally", 1)),
            ("split bundle full 2t / Embree filter+tally 2t", ("X", "bundle", 2, "full"), ("E", "filtertally", 2)),
            # the goals' ratios with sceneinfo timed in process (no fixed cost to subtract)
            ("split global full 2t / Embree filter 2t", ("X", "global", 2, "full"), ("E", "filter", 2)),
            ("split global alone 1t / Embree filter 1t (cpu)", ("X", "global", 1, "alone_cpu"), ("EC", "filter", 1)),
            ("split global full 1t / Embree filter+tally 1t (cpu)", ("X", "global", 1, "full_cpu"),
             ("EC", "filtertally", 1)),
            ("split bundle full 1t / Embree closest 1t (cpu)", ("X", "bundle", 1, "full_cpu"), ("EC", "closest", 1)),
            ("split bundle full 2t / Embree closest 2t", ("X", "bundle", 2, "full"), ("E", "closest", 2)),
        ]
        for name, a, b in pairs:
            v = []
            for rep in reps:
                x, y = rate(scene, rep, a), rate(scene, rep, b)
                if x and y:
                    v.append(x / y)
            if v:
                out.append(f"  {name:52} {min(v):6.3f} {statistics.median(v):6.3f} {max(v):6.3f}  n={len(v)}")
        # each side's tally share: 1 - (rate with the tally) / (rate without), per rep
        out.append("\ntally share of a line's time, 1 - with/without (per rep, then min / median / max):")
        shares = [
            ("Embree filter+tally vs filter 1t", ("E", "filtertally", 1), ("E", "filter", 1)),
            ("Embree filter+tally vs filter 2t", ("E", "filtertally", 2), ("E", "filter", 2)),
            ("sceneinfo global 1t", ("X", "global", 1, "full"), ("X", "global", 1, "alone")),
            ("sceneinfo global 2t", ("X", "global", 2, "full"), ("X", "global", 2, "alone")),
            ("sceneinfo bundle 1t", ("X", "bundle", 1, "full"), ("X", "bundle", 1, "alone")),
            ("sceneinfo bundle 2t", ("X", "bundle", 2, "full"), ("X", "bundle", 2, "alone")),
        ]
        for name, a, b in shares:
            v = []
            for rep in reps:
                x, y = rate(scene, rep, a), rate(scene, rep, b)
                if x and y:
                    v.append(1.0 - x / y)
            if v:
                out.append(f"  {name:46} {min(v):6.3f} {statistics.median(v):6.3f} {max(v):6.3f}  n={len(v)}")
        isc = [(r["isc"], r["isc_stderr"]) for rep in reps for k, r in runs[(scene, rep)].items()
               if k[0] == "E" and "isc" in r]
        if isc:
            out.append(f"Embree filter+tally I_S^c {isc[0][0]:.5f} +- {isc[0][1]:.5f} (its first run; "
                       "sceneinfo measure reports i_s_continuous for comparison)")
    print("\n".join(out))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "results/run.jsonl")
