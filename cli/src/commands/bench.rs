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

mod split;

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
    naive: Spread,
    /// BVH, 1 thread, lines per CPU second.
    one: Spread,
    /// BVH, 1 thread, lines per wall second.
    one_wall: Spread,
    /// BVH, `threads` threads, lines per wall second.
    many: Spread,
    peak_mb: Option<f64>,
    count_bytes: usize,
    pairs: u64,
}

/// Global lines and bundles of parallel lines on one scene, in the same run.
struct BundleRow {
    name: &'static str,
    /// Global lines: 1 thread, lines per CPU second of the whole job; the figure of merit
    /// of `I_S^c` (of the repetition with the median rate).
    global: Spread,
    global_merit: Merit,
    /// Bundles: 1 thread, lines per CPU second of the whole job and (marginal) per wall
    /// second; `threads`, per wall second (marginal); the figure of merit of `I_S^c`.
    bundle: Spread,
    bundle_wall: Spread,
    bundle_many: Spread,
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
    ns_per_line: Spread,
    /// Of it, sampling the line and finding its hits (`Tracer3::global_line_hits`), without
    /// the tally.
    query_ns_per_line: f64,
    hits_per_line: f64,
}

pub fn run(args: &BenchArgs, threads: usize) -> Result<()> {
    let budget = if args.full { 3.0 } else { 0.25 };
    let reps = args.reps.max(1);
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
    if args.split {
        return run_split(args, threads, budget, reps);
    }

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
        let (row, bundle) = bench_scene(name, &tracer, &naive, budget, threads, reps);
        bundles.push(bundle);
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
        let (row, bundle) = bench_scene(name, &tracer, &naive, budget, threads, reps);
        bundles.push(bundle);
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
                reps,
            )?);
        }
        let levels: &[u32] = if args.full { &[1, 3, 5, 7] } else { &[1, 3, 5] };
        for &l in levels {
            note(&format!("curve: triangulated cube level {l}"));
            let scene = triangulated_cube(l)?;
            curve.push(curve_point(
                format!("cube triangles {l}"),
                &scene,
                budget,
                reps,
            )?);
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
    let cores = crate::config::cores();
    let noise = noise(&mc, &bundles, &curve, &[], load, cores);
    let report = Report {
        reps,
        cores,
        noise: &noise,
        mc: &mc,
        bundles: &bundles,
        exact: &exact,
        curve: &curve,
        split: &[],
        memory: memory.as_ref(),
        threads,
        load,
        total,
    };
    print_report(&report, args.json, budget)
}

/// `bench --split`: the cast/tally split ([`split`]) on the `--scene` files, else on the
/// harness' scenes `--only` selects, printed alone.
fn run_split(args: &BenchArgs, threads: usize, budget: f64, reps: usize) -> Result<()> {
    let start = Instant::now();
    let load_before = load_average();
    let note = |s: &str| {
        if !args.json {
            eprintln!("bench: {s}");
        }
    };
    let methods = match args.method {
        Some(m) => vec![m.line_method()],
        None => vec![LineMethod::Global, LineMethod::Bundle],
    };
    let mut rows = Vec::new();
    if args.scene.is_empty() {
        let wanted = |name: &str| args.only.as_ref().is_none_or(|o| name.contains(o.as_str()));
        for (name, make) in split::SCENES.into_iter().filter(|(n, _)| wanted(n)) {
            note(&format!("split: {name}"));
            rows.extend(split::scene_rows(
                name,
                &make()?,
                &methods,
                args.lines,
                budget,
                threads,
                reps,
            )?);
        }
    }
    for path in &args.scene {
        let name = path.display().to_string();
        note(&format!("split: {name}"));
        let scene = split::load(path)?;
        rows.extend(split::scene_rows(
            &name, &scene, &methods, args.lines, budget, threads, reps,
        )?);
    }
    let total = start.elapsed().as_secs_f64();
    let load = [load_before, load_average()];
    let cores = crate::config::cores();
    let noise = noise(&[], &[], &[], &rows, load, cores);
    let report = Report {
        reps,
        cores,
        noise: &noise,
        mc: &[],
        bundles: &[],
        exact: &[],
        curve: &[],
        split: &rows,
        memory: None,
        threads,
        load,
        total,
    };
    print_report(&report, args.json, budget)
}

/// Everything `bench` measured, for printing.
struct Report<'a> {
    /// Repetitions of every measurement.
    reps: usize,
    /// Logical CPUs of the machine.
    cores: usize,
    /// Why the run is noisy (empty: it is not).
    noise: &'a [String],
    mc: &'a [McRow],
    bundles: &'a [BundleRow],
    exact: &'a [ExactRow],
    curve: &'a [CurvePoint],
    /// The cast/tally split (`--split`).
    split: &'a [split::SplitRow],
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

/// Prints `report` to stdout: JSON with `--json`, else the tables.
fn print_report(report: &Report, as_json: bool, budget: f64) -> Result<()> {
    let mut out = std::io::stdout().lock();
    if as_json {
        writeln!(out, "{}", json(report)?)?;
    } else {
        write!(out, "{}", table(report, budget))?;
    }
    out.flush()?;
    Ok(())
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

/// Min, median and max of one figure over the repetitions of a benchmark.
#[derive(Clone, Copy, Debug)]
struct Spread {
    min: f64,
    median: f64,
    max: f64,
}

impl Spread {
    /// The spread of `xs` (the median of an even count is the mean of the middle two);
    /// zeros for no value.
    fn of(xs: &[f64]) -> Self {
        let mut v: Vec<f64> = xs.iter().copied().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return Self {
                min: 0.0,
                median: 0.0,
                max: 0.0,
            };
        }
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let median = if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        };
        Self {
            min: v[0],
            median,
            max: v[n - 1],
        }
    }

    /// `max / min`: 1 for a figure that repeats exactly.
    fn max_over_min(&self) -> f64 {
        if self.min > 0.0 {
            self.max / self.min
        } else {
            f64::INFINITY
        }
    }

    /// `median [min–max]` in millions, for the tables.
    fn millions(&self) -> String {
        format!(
            "{:.3} [{:.3}-{:.3}]",
            self.median / 1e6,
            self.min / 1e6,
            self.max / 1e6
        )
    }
}

/// A spread above this (`max / min` of a rate over the repetitions) flags the run as noisy.
const NOISY_SPREAD: f64 = 1.3;
/// A 1-minute load average above this share of the cores flags the run as noisy.
const NOISY_LOAD_PER_CORE: f64 = 0.25;

/// One configuration a benchmark compares: a tracer, a line method and a thread count.
struct Config<'a> {
    tracer: &'a (dyn LineTracer + Sync),
    method: LineMethod,
    threads: usize,
}

/// One repetition of a configuration: its marginal rates and what its longer job's tally
/// held (the tally itself is dropped: a 5400-patch tally is 58 MB).
struct Sample {
    rate: Rate,
    merit: Merit,
    /// Samples (crossings) per line.
    hits_per_line: f64,
    /// [`LineTally::count_memory`].
    count_memory: (usize, u64),
}

impl Config<'_> {
    fn job(&self, lines: u64) -> (LineTally, crate::lines::JobTimes) {
        crate::lines::run_chunks_timed(
            self.tracer,
            self.method,
            SEED,
            lines,
            0..sceneinfo::LineSession::chunk_count(lines),
            self.threads,
        )
    }

    /// The job length `L` of this configuration: grown (×2, from 256) until a job of `L`
    /// lines takes half of `budget` (wall time), so that `t(2L) − t(L)` is large beside
    /// the noise of what a job pays once.
    fn calibrate(&self, budget: f64) -> u64 {
        let mut lines = 256u64;
        loop {
            let (_, job) = self.job(lines);
            if job.wall >= budget / 2.0 || lines >= 1 << 40 {
                return lines;
            }
            lines *= 2;
        }
    }

    /// Jobs of `L` and `2L` lines: the marginal rates `L / (t(2L) − t(L))` on both clocks,
    /// which leave out what a job pays once (allocating and merging the tallies — 58 MB a
    /// thread for the 5400-patch cube's dense counts — and starting threads). A difference
    /// that is not positive (noise larger than a job) falls back to the rate of the `2L` job.
    fn sample(&self, lines: u64) -> Sample {
        let marginal = |t1: f64, t2: f64| {
            if t2 > t1 {
                lines as f64 / (t2 - t1)
            } else {
                2.0 * lines as f64 / t2.max(1e-9)
            }
        };
        let (_, job1) = self.job(lines);
        let (tally, job2) = self.job(2 * lines);
        let rate = Rate {
            wall: marginal(job1.wall, job2.wall),
            cpu: job1
                .worker_cpu
                .zip(job2.worker_cpu)
                .map(|(c1, c2)| marginal(c1, c2)),
        };
        Sample {
            rate,
            merit: Merit::of(&tally, &job2),
            hits_per_line: tally.continuous().samples as f64 / tally.lines().max(1) as f64,
            count_memory: tally.count_memory(),
        }
    }
}

/// Runs every configuration `reps` times, interleaved (A B C A B C …, after calibrating
/// each one's job length once), so that a drift of the machine's speed touches all of
/// them alike. Returns each configuration's samples in repetition order.
fn interleaved(configs: &[Config<'_>], budget: f64, reps: usize) -> Vec<Vec<Sample>> {
    let lengths: Vec<u64> = configs.iter().map(|c| c.calibrate(budget)).collect();
    let mut samples: Vec<Vec<Sample>> = configs.iter().map(|_| Vec::new()).collect();
    for _ in 0..reps.max(1) {
        for ((c, &l), out) in configs.iter().zip(&lengths).zip(&mut samples) {
            out.push(c.sample(l));
        }
    }
    samples
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

/// The spread of `f` over samples.
fn spread(samples: &[Sample], f: impl Fn(&Sample) -> f64) -> Spread {
    Spread::of(&samples.iter().map(f).collect::<Vec<_>>())
}

/// Global lines (naive baseline, BVH on 1 and `threads` threads) and bundles (1 and
/// `threads` threads) on one scene, the five configurations interleaved `reps` times.
fn bench_scene<T: LineTracer + Sync>(
    name: &'static str,
    tracer: &T,
    naive: &T,
    budget: f64,
    threads: usize,
    reps: usize,
) -> (McRow, BundleRow) {
    let configs = [
        Config {
            tracer: naive,
            method: LineMethod::Global,
            threads: 1,
        },
        Config {
            tracer,
            method: LineMethod::Global,
            threads: 1,
        },
        Config {
            tracer,
            method: LineMethod::Global,
            threads,
        },
        Config {
            tracer,
            method: LineMethod::Bundle,
            threads: 1,
        },
        Config {
            tracer,
            method: LineMethod::Bundle,
            threads,
        },
    ];
    let s = interleaved(&configs, budget, reps);
    let [naive_s, one_s, many_s, b_one_s, b_many_s] = &s[..] else {
        unreachable!("five configurations")
    };
    let ((count_bytes, pairs), hits_per_line) = many_s
        .last()
        .map_or(((0, 0), 0.0), |x| (x.count_memory, x.hits_per_line));
    let row = McRow {
        name,
        patches: tracer.n_patches(),
        hits_per_line,
        naive: spread(naive_s, |x| x.rate.cpu_or_wall()),
        one: spread(one_s, |x| x.rate.cpu_or_wall()),
        one_wall: spread(one_s, |x| x.rate.wall),
        many: spread(many_s, |x| x.rate.wall),
        peak_mb: peak_bytes().map(|b| b as f64 / 1e6),
        count_bytes,
        pairs,
    };
    let merit = |v: &[Sample]| {
        let m: Vec<Merit> = v.iter().map(|x| x.merit).collect();
        // The repetition of median whole-job rate stands for the configuration
        let mut order: Vec<usize> = (0..m.len()).collect();
        order.sort_by(|&a, &b| m[a].rate().total_cmp(&m[b].rate()));
        (
            m[order[order.len() / 2]],
            Spread::of(&m.iter().map(Merit::rate).collect::<Vec<_>>()),
        )
    };
    let (global_merit, global) = merit(one_s);
    let (bundle_merit, bundle) = merit(b_one_s);
    let bundles = BundleRow {
        name,
        global,
        global_merit,
        bundle,
        bundle_wall: spread(b_one_s, |x| x.rate.wall),
        bundle_many: spread(b_many_s, |x| x.rate.wall),
        bundle_merit,
    };
    (row, bundles)
}

fn curve_point(mesh: String, scene: &Scene3, budget: f64, reps: usize) -> Result<CurvePoint> {
    let tracer = Tracer3::new(scene)?;
    let config = Config {
        tracer: &tracer,
        method: LineMethod::Global,
        threads: 1,
    };
    let lines = config.calibrate(budget);
    // The full job and the query alone, alternated
    let (mut full, mut query) = (Vec::new(), Vec::new());
    let mut hits_per_line = 0.0;
    for _ in 0..reps.max(1) {
        let s = config.sample(lines);
        full.push(1e9 / s.rate.cpu_or_wall());
        hits_per_line = s.hits_per_line;
        query.push(query_ns_per_line(scene, budget)?);
    }
    Ok(CurvePoint {
        mesh,
        patches: tracer.n_patches(),
        ns_per_line: Spread::of(&full),
        query_ns_per_line: Spread::of(&query).median,
        hits_per_line,
    })
}

/// CPU (else wall) nanoseconds per line of sampling a global line of `scene` and finding
/// all its hits with the BVH, without tallying them: the query's share of a curve point's
/// cost, the rest being the tally's. Lines as in the tracer's jobs (seed [`SEED`], chunk
/// 0's stream); jobs of `L` and `2L` lines, `L` grown until a job takes half of `budget`,
/// as in [`Config::calibrate`].
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

/// Why a run's figures are not to be trusted: a 1-minute load average above
/// [`NOISY_LOAD_PER_CORE`] of the cores before or after, or a rate whose `max / min` over
/// the repetitions exceeds [`NOISY_SPREAD`] (one line each; empty for a quiet run).
fn noise(
    mc: &[McRow],
    bundles: &[BundleRow],
    curve: &[CurvePoint],
    split: &[split::SplitRow],
    load: [Option<f64>; 2],
    cores: usize,
) -> Vec<String> {
    let mut why = Vec::new();
    let limit = NOISY_LOAD_PER_CORE * cores as f64;
    for (when, l) in ["before", "after"].iter().zip(load) {
        if let Some(l) = l.filter(|&l| l > limit) {
            why.push(format!(
                "load average {l:.2} {when} > {limit:.2} ({NOISY_LOAD_PER_CORE} x {cores} cores)"
            ));
        }
    }
    let mut check = |what: String, s: &Spread| {
        let r = s.max_over_min();
        if r > NOISY_SPREAD {
            why.push(format!("{what}: max/min {r:.2} > {NOISY_SPREAD}"));
        }
    };
    for m in mc {
        check(format!("{} naive 1t", m.name), &m.naive);
        check(format!("{} global 1t", m.name), &m.one);
        check(format!("{} global Nt", m.name), &m.many);
    }
    for b in bundles {
        check(format!("{} bundle 1t", b.name), &b.bundle);
        check(format!("{} bundle Nt", b.name), &b.bundle_many);
    }
    for p in curve {
        check(format!("curve {}", p.mesh), &p.ns_per_line);
    }
    for r in split {
        for (what, s) in r.spreads() {
            check(what, s);
        }
    }
    why
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
        "Load average (1 min) {} before, {} after, on {} cores; {} repetitions of every \
         measurement, configurations of a scene interleaved; rates: median [min-max]",
        or_na(r.load[0]),
        or_na(r.load[1]),
        r.cores,
        r.reps
    );
    if r.noise.is_empty() {
        let _ = writeln!(s, "quiet run: load and spreads within the limits");
    } else {
        let _ = writeln!(s, "NOISY RUN (figures are rough indications only):");
        for w in r.noise {
            let _ = writeln!(s, "  {w}");
        }
    }
    if !r.mc.is_empty() {
        let _ = writeln!(
            s,
            "\nGlobal lines with full count accumulation, M lines/s ({budget} s per \
             measurement). 1t: per CPU second of the worker (load does not dilute it); \
             {threads}t: per wall second (shows scaling only on an idle machine)"
        );
        let _ = writeln!(
            s,
            "{:<20} {:>7} {:>6} {:>9} {:>21} {:>21} {:>21} {:>9} {:>6} {:>8} {:>9} {:>7}",
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
            "{:<20} {:>7} {:>6.2} {:>9.4} {:>21} {:>21} {:>21} {:>9.1} {:>6.2} {:>8} {:>9.1} {:>7}",
            m.name,
            m.patches,
            m.hits_per_line,
            m.naive.median / 1e6,
            m.one.millions(),
            m.one_wall.millions(),
            m.many.millions(),
            m.one.median / m.naive.median,
            m.many.median / m.one_wall.median,
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
            "{:<20} {:>21} {:>21} {:>21} {:>21} {:>8} {:>11} {:>11} {:>11} {:>7}",
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
            "{:<20} {:>21} {:>21} {:>21} {:>21} {:>8.2} {:>11.3e} {:>11.3e} {:>11.3} {:>7.1}",
            b.name,
            b.global.millions(),
            b.bundle.millions(),
            b.bundle_wall.millions(),
            b.bundle_many.millions(),
            b.bundle.median / b.global.median,
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
             {:<20} {:>8} {:>19} {:>9} {:>6} {:>12}",
            "mesh", "patches", "ns/line [min-max]", "query ns", "hits", "ns/log2(n)"
        );
    }
    for p in r.curve {
        let _ = writeln!(
            s,
            "{:<20} {:>8} {:>19} {:>9.0} {:>6.2} {:>12.1}",
            p.mesh,
            p.patches,
            format!(
                "{:.0} [{:.0}-{:.0}]",
                p.ns_per_line.median, p.ns_per_line.min, p.ns_per_line.max
            ),
            p.query_ns_per_line,
            p.hits_per_line,
            p.ns_per_line.median / (p.patches as f64).log2()
        );
    }
    split::table(&mut s, r.split);
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
    o.integer("cores", r.cores as u64)?;
    o.integer("repetitions", r.reps as u64)?;
    o.boolean("noisy", !r.noise.is_empty())?;
    o.string("noise", &r.noise.join("; "))?;
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
                spread_json(o, "naive_lines_per_cpu_second", &m.naive)?;
                spread_json(o, "lines_per_cpu_second_1_thread", &m.one)?;
                spread_json(o, "lines_per_second_1_thread", &m.one_wall)?;
                spread_json(o, "lines_per_second", &m.many)?;
                o.number("speedup_over_naive", m.one.median / m.naive.median)?;
                o.number("thread_scaling", m.many.median / m.one_wall.median)?;
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
                spread_json(o, "global_lines_per_cpu_second_1_thread", &b.global)?;
                spread_json(o, "bundle_lines_per_cpu_second_1_thread", &b.bundle)?;
                spread_json(o, "bundle_lines_per_second_1_thread", &b.bundle_wall)?;
                spread_json(o, "bundle_lines_per_second", &b.bundle_many)?;
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
                spread_json(o, "ns_per_line", &p.ns_per_line)?;
                o.number("query_ns_per_line", p.query_ns_per_line)?;
                o.number("hits_per_line", p.hits_per_line)
            })?;
        }
        Ok(())
    })?;
    if !r.split.is_empty() {
        split::json(&mut o, r.split)?;
    }
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

/// `key` = the median, and `key_min`, `key_max`.
fn spread_json<W: std::fmt::Write>(
    o: &mut JsonObject<'_, W>,
    key: &str,
    s: &Spread,
) -> std::fmt::Result {
    o.number(key, s.median)?;
    o.number(&format!("{key}_min"), s.min)?;
    o.number(&format!("{key}_max"), s.max)?;
    Ok(())
}
