//! `sceneinfo bench`: whole-job throughput on the scenes, measured side by side in
//! one run so that ratios stay meaningful on a busy machine.
//!
//! For each Monte Carlo scene: global lines per second with full count accumulation on one
//! thread and on `--threads`, the same job with every query answered by the naive loop
//! over all patches (the baseline the BVH's gain is measured against), the peak resident
//! memory of the process while the job ran (Linux `VmHWM`, reset through
//! `/proc/self/clear_refs` before each scene), and the memory of the pair counts. Then the
//! exact form factors' times, and the per-line cost against the number of patches.
//!
//! Two clocks (see `rate`): rates on one thread are per second of the workers' CPU time,
//! which a loaded machine does not dilute; the multi-threaded rate is per second of wall
//! time, the only clock that shows thread scaling (and only on an idle machine). Both are
//! marginal rates of jobs of `L` and `2L` lines, so per-job costs (allocating and merging
//! tallies) do not count. The load average is printed with the results.

use std::fmt::Write as _;
use std::io::Write;
use std::time::Instant;

use anyhow::{Context, Result};
use sceneinfo::geom::DVec3;
use sceneinfo::scene::{Scene2, Scene3, Subdivision};
use sceneinfo::tally::{LineMethod, LineTally, LineTracer};
use sceneinfo::trace::estimate_2d::Tracer2;
use sceneinfo::trace::estimate_3d::Tracer3;
use sceneinfo_report::JsonObject;

use crate::args::BenchArgs;

/// Seed of every benchmark job.
const SEED: u64 = 9;

/// A benchmark scene: its name and how to build it (built only when it runs).
type Named<S> = (&'static str, fn() -> sceneinfo::Result<S>);

/// One Monte Carlo benchmark scene.
struct McRow {
    name: &'static str,
    patches: usize,
    /// Samples (crossings) per line.
    hits_per_line: f64,
    /// Naive baseline, 1 thread, lines per CPU second.
    naive: f64,
    /// BVH, 1 thread, lines per CPU second.
    one: f64,
    /// BVH, 1 thread, lines per wall second.
    one_wall: f64,
    /// BVH, `threads` threads, lines per wall second.
    many: f64,
    peak_mb: Option<f64>,
    count_bytes: usize,
    pairs: u64,
}

/// Global lines and bundles of parallel lines on one scene, in the same run.
struct BundleRow {
    name: &'static str,
    /// Global lines: 1 thread, lines per CPU second of the whole job; the figure of merit
    /// of `I_S^c`.
    global: f64,
    global_merit: Merit,
    /// Bundles: 1 thread, lines per CPU second of the whole job and (marginal) per wall
    /// second; `threads`, per wall second (marginal); the figure of merit of `I_S^c`.
    bundle: f64,
    bundle_wall: f64,
    bundle_many: f64,
    bundle_merit: Merit,
}

/// How much a job's `I_S^c` is worth per unit of work: the job's standard error and CPU
/// seconds, and the efficiency `1 / (stderr² · CPU seconds)` (the inverse of the variance
/// a CPU second buys: larger is better, and it does not depend on the job's length).
#[derive(Clone, Copy)]
struct Merit {
    lines: u64,
    stderr: f64,
    cpu_seconds: f64,
}

impl Merit {
    fn of(tally: &LineTally, job: &crate::lines::JobTimes) -> Self {
        Self {
            lines: tally.lines(),
            stderr: tally.continuous().stderr,
            cpu_seconds: job.worker_cpu.unwrap_or(job.wall),
        }
    }

    /// The standard error of a job of one line, `stderr · √lines`: the ratio of two
    /// methods' is the ratio of their standard errors at equal lines.
    fn stderr_per_line(&self) -> f64 {
        self.stderr * (self.lines as f64).sqrt()
    }

    /// Lines per CPU second of the whole job.
    fn rate(&self) -> f64 {
        self.lines as f64 / self.cpu_seconds
    }

    fn efficiency(&self) -> f64 {
        1.0 / (self.stderr * self.stderr * self.cpu_seconds)
    }
}

/// One exact form-factor computation.
struct ExactRow {
    name: &'static str,
    patches: usize,
    seconds: f64,
}

/// One point of the cost-per-line curve.
struct CurvePoint {
    mesh: String,
    patches: usize,
    ns_per_line: f64,
    /// Of it, sampling the line and finding its hits (`Tracer3::global_line_hits`), without
    /// the tally.
    query_ns_per_line: f64,
    hits_per_line: f64,
}

pub fn run(args: &BenchArgs, threads: usize) -> Result<()> {
    let budget = if args.full { 3.0 } else { 0.25 };
    let start = Instant::now();
    let load_before = load_average();
    let mut mc = Vec::new();
    let mut bundles = Vec::new();
    let quiet = args.json;
    let note = |s: &str| {
        if !quiet {
            eprintln!("bench: {s}");
        }
    };
    let wanted = |name: &str| args.only.as_ref().is_none_or(|o| name.contains(o.as_str()));

    // Monte Carlo scenes: flatland, then 3D
    let flat: [Named<Scene2>; 2] = [
        ("triangle (30)", || Scene2::regular_polygon(3, 10)),
        ("64-squares-a", || Scene2::catalogue("64-squares-a", 10)),
    ];
    for (name, make) in flat.into_iter().filter(|(n, _)| wanted(n)) {
        note(name);
        let scene = make()?;
        reset_peak();
        let tracer = Tracer2::new(&scene)?;
        let naive = Tracer2::new(&scene)?.naive_baseline();
        let (row, global_merit) = bench_scene(name, &tracer, &naive, budget, threads);
        note(&format!("{name}: bundles"));
        bundles.push(bench_bundles(name, &tracer, global_merit, budget, threads));
        mc.push(row);
    }
    let solid: [Named<Scene3>; 5] = [
        ("cube 600", || Scene3::cube(10)),
        ("cube 5400", || Scene3::cube(30)),
        ("cornell (grid 10)", || Scene3::preset("cornell", 10)),
        ("room, 512 cubes", || Scene3::preset("cubes-512-random", 1)),
        ("cube 99846", || Scene3::cube(129)),
    ];
    for (name, make) in solid.into_iter().filter(|(n, _)| wanted(n)) {
        note(name);
        let scene = make()?;
        reset_peak();
        let tracer = Tracer3::new(&scene)?;
        let naive = Tracer3::new(&scene)?.naive_baseline();
        let (row, global_merit) = bench_scene(name, &tracer, &naive, budget, threads);
        note(&format!("{name}: bundles"));
        bundles.push(bench_bundles(name, &tracer, global_merit, budget, threads));
        mc.push(row);
    }

    // Exact form factors
    let mut exact = Vec::new();
    if wanted("exact") {
        note("exact form factors");
        let scene = Scene2::catalogue("16-squares-4", 52)?;
        let scene = sceneinfo::Scene::Flat(scene);
        let t = Instant::now();
        let ff = scene.exact_form_factors()?;
        exact.push(ExactRow {
            name: "flatland 16-squares-4",
            patches: ff.n_patches(),
            seconds: t.elapsed().as_secs_f64(),
        });
        let cube = sceneinfo::Scene::Solid(Scene3::cube(10)?);
        let t = Instant::now();
        let ff = cube.exact_form_factors()?;
        exact.push(ExactRow {
            name: "3D cube",
            patches: ff.n_patches(),
            seconds: t.elapsed().as_secs_f64(),
        });
    }

    // Cost per line against the number of patches
    let mut curve = Vec::new();
    if wanted("curve") {
        let grids: &[u32] = if args.full {
            &[4, 13, 41, 129, 408]
        } else {
            &[4, 13, 41, 129]
        };
        for &k in grids {
            note(&format!("curve: cube grid {k}"));
            curve.push(curve_point(
                format!("cube grid {k}"),
                &Scene3::cube(k)?,
                budget,
            )?);
        }
        let levels: &[u32] = if args.full { &[1, 3, 5, 7] } else { &[1, 3, 5] };
        for &l in levels {
            note(&format!("curve: triangulated cube level {l}"));
            let scene = triangulated_cube(l)?;
            curve.push(curve_point(format!("cube triangles {l}"), &scene, budget)?);
        }
    }

    // The memory check
    let memory = match args.memory_lines {
        Some(lines) => {
            note(&format!(
                "memory check: {lines} lines on the 99,846-patch cube"
            ));
            Some(memory_check(lines, threads)?)
        }
        None => None,
    };

    let total = start.elapsed().as_secs_f64();
    let load = [load_before, load_average()];
    let report = Report {
        mc: &mc,
        bundles: &bundles,
        exact: &exact,
        curve: &curve,
        memory: memory.as_ref(),
        threads,
        load,
        total,
    };
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", json(&report)?)?;
    } else {
        write!(out, "{}", table(&report, budget))?;
    }
    out.flush()?;
    Ok(())
}

/// Everything `bench` measured, for printing.
struct Report<'a> {
    mc: &'a [McRow],
    bundles: &'a [BundleRow],
    exact: &'a [ExactRow],
    curve: &'a [CurvePoint],
    memory: Option<&'a MemoryCheck>,
    threads: usize,
    /// The 1-minute load average before and after.
    load: [Option<f64>; 2],
    total: f64,
}

/// The memory check: one long job on a 10⁵-patch scene.
struct MemoryCheck {
    patches: usize,
    lines: u64,
    threads: usize,
    seconds: f64,
    peak_mb: Option<f64>,
    count_bytes: usize,
    pairs: u64,
}

/// Casts `lines` global lines on the 99,846-patch cube (sparse counts) and finishes the
/// estimate, as `measure` would, recording the peak resident memory of the whole job.
fn memory_check(lines: u64, threads: usize) -> Result<MemoryCheck> {
    let scene = Scene3::cube(129)?;
    reset_peak();
    let t = Instant::now();
    let tracer = Tracer3::new(&scene)?;
    let tally = crate::lines::run(&tracer, LineMethod::Global, SEED, lines, threads);
    let (count_bytes, pairs) = tally.count_memory();
    let estimate = tally.finish(&tracer)?;
    let seconds = t.elapsed().as_secs_f64();
    let peak_mb = peak_bytes().map(|b| b as f64 / 1e6);
    drop(estimate);
    Ok(MemoryCheck {
        patches: tracer.n_patches(),
        lines,
        threads,
        seconds,
        peak_mb,
        count_bytes,
        pairs,
    })
}

/// The 1-minute load average (Linux `/proc/loadavg`).
fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// The unit cube with each face cut into triangles (`Subdivision::Triangles(level)`:
/// `2 · 4^level` per face), the faces of [`Scene3::cube`] — a mesh the BVH holds patch by
/// patch (no grid sheets), for the cost curve.
fn triangulated_cube(level: u32) -> Result<Scene3> {
    let cube = Scene3::cube(1)?;
    let mut b = Scene3::builder();
    for f in 0..cube.faces().len() {
        let v: Vec<DVec3> = cube.face_vertices(f).to_vec();
        b.polygon(&v, Subdivision::Triangles(level))?;
    }
    Ok(b.build()?)
}

/// Rates of a tracer on some threads: lines per second of wall time and per second of
/// the workers' CPU time.
struct Rate {
    /// Lines per second of wall time.
    wall: f64,
    /// Lines per second of the workers' CPU time, summed over the workers; `None` where
    /// the CPU time cannot be read (not Linux).
    cpu: Option<f64>,
}

impl Rate {
    /// The CPU rate, or the wall rate where there is none.
    fn cpu_or_wall(&self) -> f64 {
        self.cpu.unwrap_or(self.wall)
    }
}

/// Rates of `tracer` casting lines of `method` on `threads` threads, and the tally and
/// times of the last job.
///
/// Jobs of `L` and `2L` lines give the marginal rates `L / (t(2L) − t(L))`, with `L` grown
/// (×2) until a job of `L` lines takes half of `budget`: the difference then leaves out
/// what a job pays once (allocating and merging the tallies — 233 MB a thread for the
/// 5400-patch cube's dense counts — and starting threads), so it is the rate of a long
/// job, and it is large beside the noise of those costs. (A difference that is not
/// positive — noise larger than a job — falls back to the rate of the `2L` job.)
fn rate<T: LineTracer + Sync>(
    tracer: &T,
    method: LineMethod,
    budget: f64,
    threads: usize,
) -> (Rate, LineTally, crate::lines::JobTimes) {
    let timed = |lines: u64| {
        crate::lines::run_chunks_timed(
            tracer,
            method,
            SEED,
            lines,
            0..sceneinfo::LineSession::chunk_count(lines),
            threads,
        )
    };
    let marginal = |lines: u64, t1: f64, t2: f64| {
        if t2 > t1 {
            lines as f64 / (t2 - t1)
        } else {
            2.0 * lines as f64 / t2.max(1e-9)
        }
    };
    let mut lines = 4096u64;
    loop {
        let (_, job1) = timed(lines);
        if job1.wall >= budget / 2.0 || lines >= 1 << 40 {
            let (tally, job2) = timed(2 * lines);
            let wall = marginal(lines, job1.wall, job2.wall);
            let cpu = job1
                .worker_cpu
                .zip(job2.worker_cpu)
                .map(|(c1, c2)| marginal(lines, c1, c2));
            return (Rate { wall, cpu }, tally, job2);
        }
        lines *= 2;
    }
}

fn bench_scene<T: LineTracer + Sync>(
    name: &'static str,
    tracer: &T,
    naive: &T,
    budget: f64,
    threads: usize,
) -> (McRow, Merit) {
    let (naive_rate, _, _) = rate(naive, LineMethod::Global, budget, 1);
    let (one, one_tally, one_job) = rate(tracer, LineMethod::Global, budget, 1);
    let (many, tally, _) = rate(tracer, LineMethod::Global, budget, threads);
    let (count_bytes, pairs) = tally.count_memory();
    let samples = tally.continuous().samples;
    let row = McRow {
        name,
        patches: tracer.n_patches(),
        hits_per_line: samples as f64 / tally.lines().max(1) as f64,
        naive: naive_rate.cpu_or_wall(),
        one: one.cpu_or_wall(),
        one_wall: one.wall,
        many: many.wall,
        peak_mb: peak_bytes().map(|b| b as f64 / 1e6),
        count_bytes,
        pairs,
    };
    (row, Merit::of(&one_tally, &one_job))
}

/// Bundles of parallel lines on the scene of `tracer`, beside its global lines' figure of
/// merit from the same run.
fn bench_bundles<T: LineTracer + Sync>(
    name: &'static str,
    tracer: &T,
    global_merit: Merit,
    budget: f64,
    threads: usize,
) -> BundleRow {
    let (one, tally, job) = rate(tracer, LineMethod::Bundle, budget, 1);
    // The 1-thread rates of this table are whole-job rates (lines per CPU second of the
    // 2L-line job), like the efficiency: for these scenes a job's fixed costs are small,
    // and unlike the marginal rates they stay sane under heavy load.
    let (many, _, _) = rate(tracer, LineMethod::Bundle, budget, threads);
    BundleRow {
        name,
        global: global_merit.rate(),
        global_merit,
        bundle: Merit::of(&tally, &job).rate(),
        bundle_wall: one.wall,
        bundle_many: many.wall,
        bundle_merit: Merit::of(&tally, &job),
    }
}

fn curve_point(mesh: String, scene: &Scene3, budget: f64) -> Result<CurvePoint> {
    let tracer = Tracer3::new(scene)?;
    let (r, tally, _) = rate(&tracer, LineMethod::Global, budget, 1);
    Ok(CurvePoint {
        mesh,
        patches: tracer.n_patches(),
        ns_per_line: 1e9 / r.cpu_or_wall(),
        query_ns_per_line: query_ns_per_line(scene, budget)?,
        hits_per_line: tally.continuous().samples as f64 / tally.lines().max(1) as f64,
    })
}

/// CPU (else wall) nanoseconds per line of sampling a global line of `scene` and finding
/// all its hits with the BVH, without tallying them: the query's share of a curve point's
/// cost, the rest being the tally's. Lines as in the tracer's jobs (seed [`SEED`], chunk
/// 0's stream); jobs of `L` and `2L` lines, `L` grown until a job takes half of `budget`,
/// as in `rate`.
fn query_ns_per_line(scene: &Scene3, budget: f64) -> Result<f64> {
    let tracer = Tracer3::new(scene)?;
    let timed = |lines: u64| {
        let (cpu, wall) = (crate::lines::thread_cpu_seconds(), Instant::now());
        std::hint::black_box(tracer.global_line_hits(SEED, 0, lines));
        let cpu = cpu.zip(crate::lines::thread_cpu_seconds());
        cpu.map_or(wall.elapsed().as_secs_f64(), |(a, b)| b - a)
    };
    let mut lines = 4096u64;
    loop {
        let t1 = timed(lines);
        if t1 >= budget / 2.0 || lines >= 1 << 40 {
            let t2 = timed(2 * lines);
            let dt = if t2 > t1 { t2 - t1 } else { t2 / 2.0 };
            return Ok(dt / lines as f64 * 1e9);
        }
        lines *= 2;
    }
}

/// Resets the kernel's peak-RSS mark of this process (Linux; ignored elsewhere).
fn reset_peak() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// Peak resident memory of this process since the last [`reset_peak`], in bytes (Linux
/// `VmHWM`, the `ru_maxrss` of getrusage without its never-reset maximum).
fn peak_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// `x` with one decimal, or `n/a`.
fn or_na(x: Option<f64>) -> String {
    x.map_or("n/a".to_string(), |x| format!("{x:.1}"))
}

fn table(r: &Report, budget: f64) -> String {
    let mut s = String::new();
    let threads = r.threads;
    let _ = writeln!(
        s,
        "Load average (1 min) {} before, {} after, on {} cores",
        or_na(r.load[0]),
        or_na(r.load[1]),
        crate::config::cores()
    );
    if !r.mc.is_empty() {
        let _ = writeln!(
            s,
            "\nGlobal lines with full count accumulation, M lines/s ({budget} s per \
             measurement). 1t: per CPU second of the worker (load does not dilute it); \
             {threads}t: per wall second (shows scaling only on an idle machine)"
        );
        let _ = writeln!(
            s,
            "{:<20} {:>7} {:>6} {:>9} {:>8} {:>9} {:>8} {:>9} {:>6} {:>8} {:>9} {:>7}",
            "scene",
            "patches",
            "hits",
            "naive 1t",
            "BVH 1t",
            "1t wall",
            format!("BVH {threads}t"),
            "BVH/naive",
            "Nt/1t",
            "peak MB",
            "counts MB",
            "B/pair"
        );
    }
    for m in r.mc {
        let per_pair = if m.pairs > 0 && m.patches > sceneinfo::tally::LineTally::DENSE_COUNT_LIMIT
        {
            format!("{:.1}", m.count_bytes as f64 / m.pairs as f64)
        } else {
            "dense".to_string()
        };
        let _ = writeln!(
            s,
            "{:<20} {:>7} {:>6.2} {:>9.4} {:>8.3} {:>9.3} {:>8.3} {:>9.1} {:>6.2} {:>8} {:>9.1} {:>7}",
            m.name,
            m.patches,
            m.hits_per_line,
            m.naive / 1e6,
            m.one / 1e6,
            m.one_wall / 1e6,
            m.many / 1e6,
            m.one / m.naive,
            m.many / m.one_wall,
            m.peak_mb.map_or("n/a".to_string(), |m| format!("{m:.0}")),
            m.count_bytes as f64 / 1e6,
            per_pair
        );
    }
    if !r.bundles.is_empty() {
        let _ = writeln!(
            s,
            "\nGlobal lines vs bundles of parallel lines, M lines/s (1t: per CPU \
             second of a whole job; 1t wall and {threads}t: marginal, per wall second) and \
             the efficiency of I_S^c, 1/(stderr^2 * CPU s), of the same 1-thread jobs (their \
             stderr from one job: ±10-20 %)"
        );
        let _ = writeln!(
            s,
            "{:<20} {:>9} {:>9} {:>9} {:>9} {:>8} {:>11} {:>11} {:>11} {:>7}",
            "scene",
            "global 1t",
            "bundle 1t",
            "1t wall",
            format!("bundle {threads}t"),
            "speed",
            "eff global",
            "eff bundle",
            "σ b/g",
            "eff b/g"
        );
    }
    for b in r.bundles {
        let (g, u) = (&b.global_merit, &b.bundle_merit);
        let _ = writeln!(
            s,
            "{:<20} {:>9.3} {:>9.3} {:>9.3} {:>9.3} {:>8.2} {:>11.3e} {:>11.3e} {:>11.3} {:>7.1}",
            b.name,
            b.global / 1e6,
            b.bundle / 1e6,
            b.bundle_wall / 1e6,
            b.bundle_many / 1e6,
            b.bundle / b.global,
            g.efficiency(),
            u.efficiency(),
            u.stderr_per_line() / g.stderr_per_line(),
            u.efficiency() / g.efficiency()
        );
    }
    if !r.exact.is_empty() {
        let _ = writeln!(s, "\nExact form factors (wall time)");
    }
    for e in r.exact {
        let _ = writeln!(
            s,
            "{:<24} {:>6} patches {:>8.3} s",
            e.name, e.patches, e.seconds
        );
    }
    if !r.curve.is_empty() {
        let _ = writeln!(
            s,
            "\nCost per global line against patches (1 thread, full tally, CPU time)\n\
             {:<20} {:>8} {:>9} {:>9} {:>6} {:>12}",
            "mesh", "patches", "ns/line", "query ns", "hits", "ns/log2(n)"
        );
    }
    for p in r.curve {
        let _ = writeln!(
            s,
            "{:<20} {:>8} {:>9.0} {:>9.0} {:>6.2} {:>12.1}",
            p.mesh,
            p.patches,
            p.ns_per_line,
            p.query_ns_per_line,
            p.hits_per_line,
            p.ns_per_line / (p.patches as f64).log2()
        );
    }
    if let Some(m) = r.memory {
        let _ = writeln!(
            s,
            "\nMemory check: {} lines on {} patches, {} threads: {:.1} s, {:.2} M lines/s \
             (wall), peak {} MB, counts {:.1} MB for {} non-zero pairs ({} B/pair)",
            m.lines,
            m.patches,
            m.threads,
            m.seconds,
            m.lines as f64 / m.seconds / 1e6,
            m.peak_mb.map_or("n/a".to_string(), |m| format!("{m:.0}")),
            m.count_bytes as f64 / 1e6,
            m.pairs,
            if m.pairs > 0 {
                format!("{:.1}", m.count_bytes as f64 / m.pairs as f64)
            } else {
                "n/a".to_string()
            }
        );
    }
    let _ = writeln!(s, "\ntotal {:.1} s", r.total);
    s
}

fn json(r: &Report) -> Result<String> {
    let mut s = String::new();
    let mut o = JsonObject::new(&mut s).context("json")?;
    o.integer("threads", r.threads as u64)?;
    if let Some(l) = r.load[0] {
        o.number("load_average_before", l)?;
    }
    if let Some(l) = r.load[1] {
        o.number("load_average_after", l)?;
    }
    o.object("monte_carlo", |o| {
        for m in r.mc {
            o.object(m.name, |o| {
                o.integer("patches", m.patches as u64)?;
                o.number("hits_per_line", m.hits_per_line)?;
                o.number("naive_lines_per_cpu_second", m.naive)?;
                o.number("lines_per_cpu_second_1_thread", m.one)?;
                o.number("lines_per_second_1_thread", m.one_wall)?;
                o.number("lines_per_second", m.many)?;
                o.number("speedup_over_naive", m.one / m.naive)?;
                o.number("thread_scaling", m.many / m.one_wall)?;
                if let Some(p) = m.peak_mb {
                    o.number("peak_mb", p)?;
                }
                o.integer("count_bytes", m.count_bytes as u64)?;
                o.integer("nonzero_pairs", m.pairs)
            })?;
        }
        Ok(())
    })?;
    o.object("bundles", |o| {
        for b in r.bundles {
            o.object(b.name, |o| {
                o.number("global_lines_per_cpu_second_1_thread", b.global)?;
                o.number("bundle_lines_per_cpu_second_1_thread", b.bundle)?;
                o.number("bundle_lines_per_second_1_thread", b.bundle_wall)?;
                o.number("bundle_lines_per_second", b.bundle_many)?;
                for (key, m) in [("global", &b.global_merit), ("bundle", &b.bundle_merit)] {
                    o.object(key, |o| {
                        o.integer("lines", m.lines)?;
                        o.number("i_s_continuous_stderr", m.stderr)?;
                        o.number("cpu_seconds", m.cpu_seconds)?;
                        o.number("efficiency", m.efficiency())
                    })?;
                }
                Ok(())
            })?;
        }
        Ok(())
    })?;
    o.object("exact", |o| {
        for e in r.exact {
            o.object(e.name, |o| {
                o.integer("patches", e.patches as u64)?;
                o.number("seconds", e.seconds)
            })?;
        }
        Ok(())
    })?;
    o.object("cost_per_line", |o| {
        for p in r.curve {
            o.object(&p.mesh, |o| {
                o.integer("patches", p.patches as u64)?;
                o.number("ns_per_line", p.ns_per_line)?;
                o.number("query_ns_per_line", p.query_ns_per_line)?;
                o.number("hits_per_line", p.hits_per_line)
            })?;
        }
        Ok(())
    })?;
    if let Some(m) = r.memory {
        o.object("memory_check", |o| {
            o.integer("patches", m.patches as u64)?;
            o.integer("lines", m.lines)?;
            o.integer("threads", m.threads as u64)?;
            o.number("seconds", m.seconds)?;
            if let Some(p) = m.peak_mb {
                o.number("peak_mb", p)?;
            }
            o.integer("count_bytes", m.count_bytes as u64)?;
            o.integer("nonzero_pairs", m.pairs)
        })?;
    }
    o.number("seconds", r.total)?;
    o.finish()?;
    Ok(s)
}
