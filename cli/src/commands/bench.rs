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
//! A rate is the marginal rate of jobs of `L` and `2L` lines, `L` grown until a job takes a
//! quarter of the time budget (see `rate`).

use std::fmt::Write as _;
use std::io::Write;
use std::time::Instant;

use anyhow::{Context, Result};
use sceneinfo::formfactor::estimate_2d::FlatTracer;
use sceneinfo::formfactor::estimate_3d::SceneTracer;
use sceneinfo::formfactor::tally::{LineMethod, LineTally, LineTracer};
use sceneinfo::formfactor::{exact_2d, exact_3d};
use sceneinfo::geom::DVec3;
use sceneinfo::report::JsonObject;
use sceneinfo::scene::{FlatScene, Scene, Subdivision, catalogue_scene, preset_3d};

use crate::args::BenchArgs;

/// Seed of every benchmark job.
const SEED: u64 = 9;

/// One Monte Carlo benchmark scene.
struct McRow {
    name: &'static str,
    patches: usize,
    /// Samples (crossings) per line.
    hits_per_line: f64,
    naive: f64,
    one: f64,
    many: f64,
    peak_mb: Option<f64>,
    count_bytes: usize,
    pairs: u64,
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
    hits_per_line: f64,
}

pub fn run(args: &BenchArgs) -> Result<()> {
    let budget = if args.full { 3.0 } else { 0.25 };
    let threads = args
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, std::num::NonZero::get));
    let start = Instant::now();
    let mut mc = Vec::new();
    let quiet = args.json;
    let note = |s: &str| {
        if !quiet {
            eprintln!("bench: {s}");
        }
    };

    // Monte Carlo scenes: flatland, then 3D
    let flat: [(&'static str, FlatScene); 2] = [
        ("triangle (30)", FlatScene::regular_polygon(3, 10)?),
        ("64-squares-a", catalogue_scene("64-squares-a", 10)?),
    ];
    for (name, scene) in flat {
        note(name);
        reset_peak();
        let tracer = FlatTracer::new(&scene)?;
        let naive = FlatTracer::new(&scene)?.naive_baseline();
        mc.push(bench_scene(name, &tracer, &naive, budget, threads));
    }
    let mut solid: Vec<(&'static str, Scene)> = vec![
        ("cube 600", Scene::cube(10)?),
        ("cube 5400", Scene::cube(30)?),
        ("cornell (grid 10)", preset_3d("cornell", 10)?),
        ("room, 512 cubes", preset_3d("cubes-512-random", 1)?),
        ("cube 99846", Scene::cube(129)?),
    ];
    for (name, scene) in solid.drain(..) {
        note(name);
        reset_peak();
        let tracer = SceneTracer::new(&scene)?;
        let naive = SceneTracer::new(&scene)?.naive_baseline();
        mc.push(bench_scene(name, &tracer, &naive, budget, threads));
    }

    // Exact form factors
    note("exact form factors");
    let mut exact = Vec::new();
    let scene = catalogue_scene("16-squares-4", 52)?;
    let t = Instant::now();
    let ff = exact_2d::form_factors(&scene)?;
    exact.push(ExactRow {
        name: "flatland 16-squares-4",
        patches: ff.n_patches(),
        seconds: t.elapsed().as_secs_f64(),
    });
    let cube = Scene::cube(10)?;
    let polygons: Vec<(usize, usize)> = cube.patches().iter().map(|p| (p.first, p.count)).collect();
    let t = Instant::now();
    let ff = exact_3d::form_factors_unoccluded(cube.points(), &polygons)?;
    exact.push(ExactRow {
        name: "3D cube",
        patches: ff.n_patches(),
        seconds: t.elapsed().as_secs_f64(),
    });

    // Cost per line against the number of patches
    let mut curve = Vec::new();
    let grids: &[u32] = if args.full {
        &[4, 13, 41, 129, 408]
    } else {
        &[4, 13, 41, 129]
    };
    for &k in grids {
        note(&format!("curve: cube grid {k}"));
        curve.push(curve_point(
            format!("cube grid {k}"),
            &Scene::cube(k)?,
            budget,
        )?);
    }
    let levels: &[u32] = if args.full { &[1, 3, 5, 7] } else { &[1, 3, 5] };
    for &l in levels {
        note(&format!("curve: triangulated cube level {l}"));
        let scene = triangulated_cube(l)?;
        curve.push(curve_point(format!("cube triangles {l}"), &scene, budget)?);
    }

    let total = start.elapsed().as_secs_f64();
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", json(&mc, &exact, &curve, threads, total)?)?;
    } else {
        write!(
            out,
            "{}",
            table(&mc, &exact, &curve, threads, budget, total)
        )?;
    }
    out.flush()?;
    Ok(())
}

/// The unit cube with each face cut into triangles (`Subdivision::Triangles(level)`:
/// `2 · 4^level` per face), the faces of [`Scene::cube`] — a mesh the BVH holds patch by
/// patch (no grid sheets), for the cost curve.
fn triangulated_cube(level: u32) -> Result<Scene> {
    let cube = Scene::cube(1)?;
    let mut b = Scene::builder();
    for f in 0..cube.faces().len() {
        let v: Vec<DVec3> = cube.face_vertices(f).to_vec();
        b.polygon(&v, Subdivision::Triangles(level))?;
    }
    Ok(b.build()?)
}

/// Lines per second of `tracer` on `threads` threads, and the tally of the last job.
///
/// Jobs of `L` and `2L` lines give the marginal rate `L / (t(2L) − t(L))`, `L` grown
/// (×4) until that difference reaches a quarter of `budget`: it leaves out what a job pays
/// once (allocating and merging the tallies — 233 MB a thread for the 5400-patch cube's
/// dense counts — and starting threads), so it is the rate of a long job.
fn rate<T: LineTracer + Sync>(tracer: &T, budget: f64, threads: usize) -> (f64, LineTally) {
    let timed = |lines: u64| {
        let t = Instant::now();
        let tally = crate::lines::run(tracer, LineMethod::Global, SEED, lines, threads);
        (t.elapsed().as_secs_f64(), tally)
    };
    let mut lines = 1024u64;
    loop {
        let (t1, _) = timed(lines);
        let (t2, tally) = timed(2 * lines);
        if t2 - t1 >= budget / 4.0 || lines >= 1 << 40 {
            return (lines as f64 / (t2 - t1).max(1e-9), tally);
        }
        lines *= 4;
    }
}

fn bench_scene<T: LineTracer + Sync>(
    name: &'static str,
    tracer: &T,
    naive: &T,
    budget: f64,
    threads: usize,
) -> McRow {
    let (naive_rate, _) = rate(naive, budget, 1);
    let (one, _) = rate(tracer, budget, 1);
    let (many, tally) = rate(tracer, budget, threads);
    let (count_bytes, pairs) = tally.count_memory();
    let samples = tally.continuous().samples;
    McRow {
        name,
        patches: tracer.n_patches(),
        hits_per_line: samples as f64 / tally.lines().max(1) as f64,
        naive: naive_rate,
        one,
        many,
        peak_mb: peak_bytes().map(|b| b as f64 / 1e6),
        count_bytes,
        pairs,
    }
}

fn curve_point(mesh: String, scene: &Scene, budget: f64) -> Result<CurvePoint> {
    let tracer = SceneTracer::new(scene)?;
    let (r, tally) = rate(&tracer, budget, 1);
    Ok(CurvePoint {
        mesh,
        patches: tracer.n_patches(),
        ns_per_line: 1e9 / r,
        hits_per_line: tally.continuous().samples as f64 / tally.lines().max(1) as f64,
    })
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

fn table(
    mc: &[McRow],
    exact: &[ExactRow],
    curve: &[CurvePoint],
    threads: usize,
    budget: f64,
    total: f64,
) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Global lines with full count accumulation, M lines/s ({budget} s per measurement; \
         other load on the machine lowers every rate, so compare within one run)"
    );
    let _ = writeln!(
        s,
        "{:<20} {:>7} {:>6} {:>9} {:>8} {:>8} {:>9} {:>6} {:>8} {:>9} {:>7}",
        "scene",
        "patches",
        "hits",
        "naive 1t",
        "BVH 1t",
        format!("BVH {threads}t"),
        "BVH/naive",
        "Nt/1t",
        "peak MB",
        "counts MB",
        "B/pair"
    );
    for r in mc {
        let per_pair = if r.pairs > 0 && r.patches > sceneinfo::formfactor::DENSE_COUNT_LIMIT {
            format!("{:.1}", r.count_bytes as f64 / r.pairs as f64)
        } else {
            "dense".to_string()
        };
        let _ = writeln!(
            s,
            "{:<20} {:>7} {:>6.2} {:>9.4} {:>8.3} {:>8.3} {:>9.1} {:>6.2} {:>8} {:>9.1} {:>7}",
            r.name,
            r.patches,
            r.hits_per_line,
            r.naive / 1e6,
            r.one / 1e6,
            r.many / 1e6,
            r.one / r.naive,
            r.many / r.one,
            r.peak_mb.map_or("n/a".to_string(), |m| format!("{m:.0}")),
            r.count_bytes as f64 / 1e6,
            per_pair
        );
    }
    let _ = writeln!(s, "\nExact form factors");
    for e in exact {
        let _ = writeln!(
            s,
            "{:<24} {:>6} patches {:>8.3} s",
            e.name, e.patches, e.seconds
        );
    }
    let _ = writeln!(
        s,
        "\nCost per global line against patches (1 thread, full tally)\n{:<20} {:>8} {:>9} {:>6} {:>12}",
        "mesh", "patches", "ns/line", "hits", "ns/log2(n)"
    );
    for p in curve {
        let _ = writeln!(
            s,
            "{:<20} {:>8} {:>9.0} {:>6.2} {:>12.1}",
            p.mesh,
            p.patches,
            p.ns_per_line,
            p.hits_per_line,
            p.ns_per_line / (p.patches as f64).log2()
        );
    }
    let _ = writeln!(s, "\ntotal {total:.1} s");
    s
}

fn json(
    mc: &[McRow],
    exact: &[ExactRow],
    curve: &[CurvePoint],
    threads: usize,
    total: f64,
) -> Result<String> {
    let mut s = String::new();
    let mut o = JsonObject::new(&mut s).context("json")?;
    o.integer("threads", threads as u64)?;
    o.object("monte_carlo", |o| {
        for r in mc {
            o.object(r.name, |o| {
                o.integer("patches", r.patches as u64)?;
                o.number("hits_per_line", r.hits_per_line)?;
                o.number("naive_lines_per_second", r.naive)?;
                o.number("lines_per_second_1_thread", r.one)?;
                o.number("lines_per_second", r.many)?;
                o.number("speedup_over_naive", r.one / r.naive)?;
                o.number("thread_scaling", r.many / r.one)?;
                if let Some(m) = r.peak_mb {
                    o.number("peak_mb", m)?;
                }
                o.integer("count_bytes", r.count_bytes as u64)?;
                o.integer("nonzero_pairs", r.pairs)
            })?;
        }
        Ok(())
    })?;
    o.object("exact", |o| {
        for e in exact {
            o.object(e.name, |o| {
                o.integer("patches", e.patches as u64)?;
                o.number("seconds", e.seconds)
            })?;
        }
        Ok(())
    })?;
    o.object("cost_per_line", |o| {
        for p in curve {
            o.object(&p.mesh, |o| {
                o.integer("patches", p.patches as u64)?;
                o.number("ns_per_line", p.ns_per_line)?;
                o.number("hits_per_line", p.hits_per_line)
            })?;
        }
        Ok(())
    })?;
    o.number("seconds", total)?;
    o.finish()?;
    Ok(s)
}
