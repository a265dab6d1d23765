#!/usr/bin/env python3
"""Side-by-side timing of sceneinfo and the Embree harness (embree_lines), alternating
runs A B A B ... in one run. Every run is one process; its own figures (and its
whole-process wall time) go to a JSONL log, one object per run. summarize.py reads it.

    python3 bench.py --sceneinfo PATH/TO/sceneinfo --reps 3 --out results/run.jsonl

Before each repetition it waits until the 1-minute load average is below --max-load;
before each scene block it waits until the other processes use < 10% of the CPUs over
one second (/proc/stat), so nothing else runs beside the timed jobs. Each run also logs
`others_share`: the share of all CPUs that OTHER processes used while it ran (all CPUs'
busy time from /proc/stat minus the run's own rusage); a run above 5% is logged with
"disturbed": true and run again (up to 3 more times). Before every run it waits until
the CPUs are < 10% busy over half a second.

Like with like (session 21): after the old plan, each scene block also runs the harness'
`filtertally` mode (Embree's all hits fed into a tally of sceneinfo's shape) on 1 and 2
threads and one `sceneinfo bench --split` (sceneinfo's casting with its full tally and
alone, the same lines, interleaved in the process); `--no-split` leaves them out, and a
sceneinfo or harness binary without them runs the old plan only.
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))

SCENES = ["cube30", "cornell10", "room512"]
NCPU = os.cpu_count() or 1
DISTURBED = 0.05  # others used > 5% of all CPUs during a run: log it as disturbed, run it again

# lines per run of the harness, by mode (about >= 2 s a run on 2 threads)
EMBREE_LINES = {"closest": 20_000_000, "packet8": 20_000_000, "allhits": 10_000_000, "filter": 10_000_000,
                "filtertally": 10_000_000}
SCENEINFO_LINES = 10_000_000
FIXED_LINES = 1_000_000  # a short job: t(N) - t(FIXED) leaves out the fixed cost (load, BVH, report)
# `sceneinfo bench --split`: jobs of L and 2L lines, each configuration with its tally and cast alone
SPLIT_LINES = 5_000_000


def loadavg():
    with open("/proc/loadavg") as f:
        return float(f.read().split()[0])


def stat_sample():
    """(total, idle) jiffies of all CPUs."""
    with open("/proc/stat") as f:
        v = [int(x) for x in f.readline().split()[1:]]
    return sum(v[:8]), v[3] + v[4]


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def cpu_busy(seconds=1.0):
    sample = stat_sample
    t0, i0 = sample()
    time.sleep(seconds)
    t1, i1 = sample()
    return 1.0 - (i1 - i0) / max(1, t1 - t0)


def wait_quiet_load(max_load, log):
    while True:
        la = loadavg()
        if la < max_load:
            log(f"load {la:.2f} < {max_load}: go")
            return la
        log(f"load {la:.2f} >= {max_load}: waiting")
        time.sleep(15)


def wait_idle(log, limit=0.10, seconds=1.0):
    while True:
        b = cpu_busy(seconds)
        if b < limit:
            return b
        log(f"cpu busy {b:.2f} before block: waiting")
        time.sleep(5)


EMBREE = os.path.join(HERE, "embree_lines")


def run_embree(scene, mode, threads, lines, prim="tri"):
    cmd = [EMBREE, os.path.join(HERE, "scenes", scene + ".obj"),
           "--lines", str(lines), "--threads", str(threads), "--mode", mode, "--prim", prim]
    t0 = time.monotonic()
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    wall = time.monotonic() - t0
    kv = dict(tok.split("=", 1) for tok in out.split())
    rec = {"tool": "embree", "mode": mode, "prim": prim, "threads": threads, "scene": scene,
           "lines": int(kv["lines"]), "cast_s": float(kv["cast_s"]), "build_s": float(kv["build_s"]),
           "load_s": float(kv["load_s"]), "cpu_s": float(kv["cpu_s"]),
           "lines_per_s": float(kv["lines_per_s"]), "process_wall_s": wall}
    for k in ("hits_per_line", "hit_fraction"):
        if k in kv:
            rec[k] = float(kv[k])
    for k in ("isc", "isc_stderr", "merge_s", "tally_mb", "segments"):  # filtertally
        if k in kv:
            rec[k] = float(kv[k])
    rec["repeats"] = int(kv["repeats"])
    rec["capped"] = int(kv["capped"])
    return rec


def run_sceneinfo(exe, scene, method, threads, lines):
    cmd = [exe, "measure", os.path.join(HERE, "scenes", scene + ".obj"), "--lines", str(lines),
           "--method", method, "--threads", str(threads), "--json"]
    t0 = time.monotonic()
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    wall = time.monotonic() - t0
    d = json.loads(out)
    return {"tool": "sceneinfo", "mode": method, "threads": threads, "scene": scene,
            "requested": lines, "lines": d["lines"], "samples": d["samples"],
            "hits_per_line": d["samples"] / d["lines"], "seconds": d["seconds"],
            "lines_per_s": d["lines_per_second"], "process_wall_s": wall}


def run_split(exe, scene, threads, lines):
    """`sceneinfo bench --split` on one scene: global lines and bundles on 1 and `threads`
    threads, each with its full tally and cast alone (the same lines, hits counted instead
    of tallied), interleaved in the process; marginal rates of jobs of L and 2L lines."""
    cmd = [exe, "bench", "--split", "--scene", os.path.join(HERE, "scenes", scene + ".obj"),
           "--lines", str(lines), "--threads", str(threads), "--reps", "1", "--json"]
    t0 = time.monotonic()
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    wall = time.monotonic() - t0
    d = json.loads(out)
    rows = {}
    for r in d["split"].values():
        key = f"{r['method']}_{r['threads']}t"
        rows[key] = {"full": r["full_lines_per_second"], "alone": r["alone_lines_per_second"],
                     "hits_per_line": r["hits_per_line_alone"], "same_hits": r["same_hits"],
                     "full_cpu": r.get("full_lines_per_cpu_second"),
                     "alone_cpu": r.get("alone_lines_per_cpu_second")}
    main_row = rows.get(f"bundle_{threads}t", {})
    return {"tool": "split", "mode": "split", "threads": threads, "scene": scene, "lines": lines,
            "rows": rows, "lines_per_s": main_row.get("full", 0.0), "process_wall_s": wall}


def main():
    global EMBREE
    ap = argparse.ArgumentParser()
    ap.add_argument("--sceneinfo", required=True)
    ap.add_argument("--embree", default=None, help="the harness binary (default: embree_lines beside this script)")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--first-rep", type=int, default=0, help="number of the first repetition (to append to a log)")
    ap.add_argument("--out", default=os.path.join("results", "run.jsonl"))
    ap.add_argument("--max-load", type=float, default=0.5)
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--scale", type=float, default=1.0, help="multiply every line count (smoke tests)")
    ap.add_argument("--no-wait", action="store_true", help="skip the quiet checks (smoke tests)")
    ap.add_argument("--no-split", action="store_true",
                    help="leave out the like-with-like runs (Embree filtertally, sceneinfo bench --split)")
    args = ap.parse_args()
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    exe = args.sceneinfo
    if args.embree:
        EMBREE = args.embree
    scenes = args.scenes.split(",")
    s = args.scale

    def log(msg):
        print(time.strftime("%H:%M:%S"), msg, file=sys.stderr, flush=True)

    # The like-with-like runs need `sceneinfo bench --split` (session 21) and the harness'
    # `filtertally` mode: an older binary runs the old plan only
    split = not args.no_split
    if split and "--split" not in subprocess.run([exe, "bench", "--help"], capture_output=True, text=True).stdout:
        log(f"{exe} has no `bench --split`: the like-with-like runs are left out")
        split = False
    if split and "filtertally" not in subprocess.run([EMBREE], capture_output=True, text=True).stderr:
        log(f"{EMBREE} has no `--mode filtertally`: the like-with-like runs are left out")
        split = False

    E = lambda scene, mode, t: ("E", lambda: run_embree(scene, mode, t, int(EMBREE_LINES[mode] * s)))
    S = lambda scene, m, t, n=None: ("S", lambda: run_sceneinfo(
        exe, scene, m, t, int(SCENEINFO_LINES * s) if n is None else n))
    with open(args.out, "a") as out:
        for rep in range(args.first_rep, args.first_rep + args.reps):
            if not args.no_wait:
                wait_quiet_load(args.max_load, log)
            for scene in scenes:
                busy = cpu_busy() if args.no_wait else wait_idle(log)
                log(f"rep {rep} scene {scene} (cpu busy {busy:.2f}, load {loadavg():.2f})")
                # A B A B ...: the harness and sceneinfo alternate
                plan = [
                    E(scene, "closest", 1), S(scene, "global", 1),
                    E(scene, "allhits", 1), S(scene, "bundle", 1),
                    E(scene, "filter", 1), S(scene, "global", 1, FIXED_LINES),
                    E(scene, "packet8", 1), S(scene, "bundle", 1, FIXED_LINES),
                    E(scene, "closest", 2), S(scene, "global", 2),
                    E(scene, "allhits", 2), S(scene, "bundle", 2),
                    E(scene, "filter", 2), S(scene, "global", 2, FIXED_LINES),
                    S(scene, "bundle", 2, FIXED_LINES),
                ]
                if split:
                    # Like with like: Embree's all hits fed into a tally of sceneinfo's
                    # shape, and sceneinfo's casting with and without its tally
                    plan += [
                        E(scene, "filtertally", 1),
                        ("S", lambda: run_split(exe, scene, 2, int(SPLIT_LINES * s))),
                        E(scene, "filtertally", 2),
                    ]
                for i, (_, job) in enumerate(plan):
                    for attempt in range(4):
                        if not args.no_wait:
                            wait_idle(log, seconds=0.5)
                        la = loadavg()
                        (t0, i0), c0, w0 = stat_sample(), children_cpu(), time.monotonic()
                        rec = job()
                        (t1, i1), c1, w1 = stat_sample(), children_cpu(), time.monotonic()
                        hz = os.sysconf("SC_CLK_TCK")
                        busy_all = (t1 - t0 - (i1 - i0)) / hz  # CPU seconds used by everything
                        others = max(0.0, busy_all - (c1 - c0))  # ... minus the timed process
                        share = others / max(1e-9, (w1 - w0) * NCPU)
                        disturbed = share > DISTURBED and not args.no_wait
                        rec.update({"rep": rep, "order": i, "attempt": attempt, "load_before": la,
                                    "time": time.time(), "run_cpu_s": c1 - c0, "others_cpu_s": others,
                                    "others_share": share, "disturbed": disturbed})
                        out.write(json.dumps(rec) + "\n")
                        out.flush()
                        rate = rec["lines_per_s"] / 1e6
                        log(f"  {rec['tool']:9} {rec['mode']:8} {rec['threads']}t lines={rec['lines']:>9} "
                            f"{rate:7.3f} M/s wall {rec['process_wall_s']:.2f}s others {share:.3f}"
                            + (" DISTURBED: again" if disturbed else ""))
                        if not disturbed:
                            break
    log("done")


if __name__ == "__main__":
    main()
