//! `sceneinfo bench --split`: what a line job's casting costs alone, against the same job
//! with its tally, on 3D scenes.
//!
//! For each scene, global lines and bundles on 1 thread and on `--threads`: the full job
//! (the lines cast and tallied: counts, `I_S^c` terms, merge) and the same lines cast
//! alone ([`Tracer3::cast_chunk`]: the same sampler, BVH queries or bundle rasters, each
//! line's hits found and sorted as the tally would get them, then only counted, with a
//! checksum of the patches). The configurations of a scene are interleaved, repetition
//! after repetition. Rates are marginal, `L / (t(2L) − t(L))` from jobs of `L` and `2L`
//! lines, per second of wall time (on one thread also per second of the worker's CPU
//! time), so what a job pays once (allocating and merging tallies, starting threads) is
//! left out: the per-line cost of casting, and of casting and tallying. The tally's share
//! is `1 − full / alone`, per repetition, then the median. Every pair's `2L` jobs cast the
//! same lines, so their hits must agree (the full job's samples): the table flags it when
//! they do not.
//!
//! The figure the Embree harness (`bench/embree`) compares with its own casting loops.

use std::fmt::Write as _;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use anyhow::{Result, bail};
use sceneinfo::scene::Scene3;
use sceneinfo::tally::{LineMethod, LineTracer};
use sceneinfo::trace::estimate_3d::{CastCount, Tracer3};
use sceneinfo_report::JsonObject;

use super::{SEED, Spread, spread_json};
use crate::lines::{JobTimes, thread_cpu_seconds};

/// The scenes of `--split` without `--scene` (those `--only` selects): the three of the
/// Embree harness.
pub(super) const SCENES: [super::Named<Scene3>; 3] = [
    ("cube 5400", || Scene3::cube(30)),
    ("cornell (grid 10)", || Scene3::preset("cornell", 10)),
    ("room, 512 cubes", || Scene3::preset("cubes-512-random", 1)),
];

/// One configuration: a method on some threads, with the tally or without.
#[derive(Clone, Copy)]
struct Config {
    method: LineMethod,
    threads: usize,
    tally: bool,
}

/// What one job of a configuration did.
struct Job {
    times: JobTimes,
    lines: u64,
    hits: u64,
    checksum: Option<u64>,
}

impl Config {
    fn job(&self, tracer: &Tracer3, lines: u64) -> Result<Job> {
        if self.tally {
            let (tally, times) =
                crate::lines::run_timed(tracer, self.method, SEED, lines, self.threads);
            return Ok(Job {
                times,
                lines: tally.lines(),
                hits: tally.continuous().samples,
                checksum: None,
            });
        }
        let (count, times) = cast_timed(tracer, self.method, lines, self.threads)?;
        Ok(Job {
            times,
            lines: count.lines,
            hits: count.hits,
            checksum: Some(count.patch_checksum),
        })
    }
}

/// Casts the chunks of a job of `lines` lines without a tally on `threads` threads
/// (chunks handed out in increasing order, as the full job's are), timing it as the full
/// job is timed ([`crate::lines::run_timed`]).
fn cast_timed(
    tracer: &Tracer3,
    method: LineMethod,
    lines: u64,
    threads: usize,
) -> Result<(CastCount, JobTimes)> {
    let chunks = sceneinfo::LineSession::chunk_count(lines);
    let next = AtomicU64::new(0);
    let threads = threads
        .max(1)
        .min(usize::try_from(chunks).unwrap_or(usize::MAX).max(1));
    let start = Instant::now();
    let parts: Vec<Result<(CastCount, Option<f64>)>> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let cpu = thread_cpu_seconds();
                    let mut count = CastCount::default();
                    // Bounded: each chunk is taken once
                    loop {
                        let chunk = next.fetch_add(1, Ordering::Relaxed);
                        if chunk >= chunks {
                            break;
                        }
                        count.merge(&tracer.cast_chunk(method, SEED, lines, chunk)?);
                    }
                    Ok((count, cpu.zip(thread_cpu_seconds()).map(|(a, b)| b - a)))
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
            .collect()
    });
    let mut total = CastCount::default();
    let mut cpu = Some(0.0);
    for part in parts {
        let (count, c) = part?;
        total.merge(&count);
        cpu = cpu.zip(c).map(|(a, b)| a + b);
    }
    let times = JobTimes {
        wall: start.elapsed().as_secs_f64(),
        worker_cpu: cpu,
        budget_done: lines,
    };
    Ok((total, times))
}

/// One repetition of a configuration: marginal rates and the hits of its `2L` job.
struct Sample {
    wall: f64,
    cpu: Option<f64>,
    lines: u64,
    hits: u64,
}

/// The marginal rate `L / (t(2L) − t(L))`, or that of the `2L` job where the difference is
/// not positive (noise larger than a job).
fn marginal(lines: u64, t1: f64, t2: f64) -> f64 {
    if t2 > t1 {
        lines as f64 / (t2 - t1)
    } else {
        2.0 * lines as f64 / t2.max(1e-9)
    }
}

/// A method on some threads: full and cast-alone rates, the tally's share, the hits.
pub(super) struct SplitRow {
    pub(super) scene: String,
    pub(super) patches: usize,
    method: LineMethod,
    threads: usize,
    /// Job length `L` (jobs of `L` and `2L` lines).
    lines: u64,
    /// Lines per wall second, marginal.
    full: Spread,
    alone: Spread,
    /// On one thread: lines per CPU second of the worker, marginal.
    full_cpu: Option<Spread>,
    alone_cpu: Option<Spread>,
    /// `1 − full / alone` of each repetition's wall rates.
    tally_share: Spread,
    /// Hits per line of the `2L` jobs (full: the tally's samples).
    hits_per_line_full: f64,
    hits_per_line_alone: f64,
    /// Whether every repetition's `2L` jobs cast the same lines and found the same hits.
    same_hits: bool,
    /// The patch checksum of the cast-alone `2L` job.
    checksum: u64,
}

/// The split of every configuration of one scene, interleaved `reps` times.
pub(super) fn scene_rows(
    name: &str,
    scene: &Scene3,
    methods: &[LineMethod],
    lines: Option<u64>,
    budget: f64,
    threads: usize,
    reps: usize,
) -> Result<Vec<SplitRow>> {
    let tracer = Tracer3::new(scene)?;
    let mut configs = Vec::new();
    for &method in methods {
        let mut counts = vec![1];
        if threads > 1 {
            counts.push(threads);
        }
        for t in counts {
            for tally in [true, false] {
                configs.push(Config {
                    method,
                    threads: t,
                    tally,
                });
            }
        }
    }
    // Job lengths: given, or grown (×2 from 4096) until the full job takes half the budget
    let mut lengths = Vec::new();
    for c in &configs {
        let l = match lines {
            Some(l) => l.max(1),
            None if !c.tally => *lengths.last().unwrap_or(&4096),
            None => {
                let mut l = 4096u64;
                while c.job(&tracer, l)?.times.wall < budget / 2.0 && l < 1 << 40 {
                    l *= 2;
                }
                l
            }
        };
        lengths.push(l);
    }
    let mut samples: Vec<Vec<Sample>> = configs.iter().map(|_| Vec::new()).collect();
    let mut checksums = vec![0u64; configs.len()];
    for _ in 0..reps.max(1) {
        for (k, (c, &l)) in configs.iter().zip(&lengths).enumerate() {
            let a = c.job(&tracer, l)?;
            let b = c.job(&tracer, 2 * l)?;
            let cpu = a
                .times
                .worker_cpu
                .zip(b.times.worker_cpu)
                .map(|(x, y)| marginal(l, x, y));
            if let Some(s) = b.checksum {
                checksums[k] = s;
            }
            samples[k].push(Sample {
                wall: marginal(l, a.times.wall, b.times.wall),
                cpu,
                lines: b.lines,
                hits: b.hits,
            });
        }
    }
    let mut rows = Vec::new();
    for (k, pair) in configs.chunks(2).enumerate() {
        let (full, alone) = (&samples[2 * k], &samples[2 * k + 1]);
        let Some((f, a)) = full.last().zip(alone.last()) else {
            bail!("no repetition measured");
        };
        let spread = |v: &[Sample], g: &dyn Fn(&Sample) -> f64| {
            Spread::of(&v.iter().map(g).collect::<Vec<_>>())
        };
        let cpu_spread = |v: &[Sample]| {
            let c: Option<Vec<f64>> = v.iter().map(|s| s.cpu).collect();
            c.map(|c| Spread::of(&c))
        };
        let share: Vec<f64> = full
            .iter()
            .zip(alone)
            .map(|(f, a)| 1.0 - f.wall / a.wall)
            .collect();
        let one = pair[0].threads == 1;
        rows.push(SplitRow {
            scene: name.to_string(),
            patches: tracer.n_patches(),
            method: pair[0].method,
            threads: pair[0].threads,
            lines: lengths[2 * k],
            full: spread(full, &|s| s.wall),
            alone: spread(alone, &|s| s.wall),
            full_cpu: if one { cpu_spread(full) } else { None },
            alone_cpu: if one { cpu_spread(alone) } else { None },
            tally_share: Spread::of(&share),
            hits_per_line_full: f.hits as f64 / f.lines.max(1) as f64,
            hits_per_line_alone: a.hits as f64 / a.lines.max(1) as f64,
            same_hits: lengths[2 * k] == lengths[2 * k + 1]
                && full
                    .iter()
                    .zip(alone)
                    .all(|(f, a)| f.lines == a.lines && f.hits == a.hits),
            checksum: checksums[2 * k + 1],
        });
    }
    Ok(rows)
}

/// The 3D scene of a `--scene` file.
pub(super) fn load(path: &Path) -> Result<Scene3> {
    match crate::output::load_scene(path)?.scene {
        sceneinfo::Scene::Solid(s) => Ok(s),
        sceneinfo::Scene::Flat(_) => {
            bail!("{}: --split casts 3D scenes, not flatland", path.display())
        }
    }
}

impl SplitRow {
    /// The spreads `noise` checks: `(what, spread)`.
    pub(super) fn spreads(&self) -> [(String, &Spread); 2] {
        let what = format!("{} {} {}t", self.scene, self.method.name(), self.threads);
        [
            (format!("{what} full"), &self.full),
            (format!("{what} cast alone"), &self.alone),
        ]
    }
}

pub(super) fn table(s: &mut String, rows: &[SplitRow]) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "\nCasting alone vs casting and tallying (the same lines; marginal rates L/(t(2L)-t(L)), \
         M lines/s per wall second, median [min-max]; 1t also per CPU second; tally share = \
         1 - full/alone)"
    );
    let _ = writeln!(
        s,
        "{:<22} {:>7} {:>7} {:>3} {:>10} {:>21} {:>21} {:>9} {:>9} {:>7} {:>6} {:>5}",
        "scene",
        "patches",
        "method",
        "t",
        "L",
        "full",
        "cast alone",
        "full cpu",
        "alone cpu",
        "tally",
        "hits",
        "same"
    );
    for r in rows {
        let cpu =
            |c: &Option<Spread>| c.map_or("-".to_string(), |c| format!("{:.3}", c.median / 1e6));
        let _ = writeln!(
            s,
            "{:<22} {:>7} {:>7} {:>3} {:>10} {:>21} {:>21} {:>9} {:>9} {:>6.1}% {:>6.3} {:>5}",
            r.scene,
            r.patches,
            r.method.name(),
            r.threads,
            r.lines,
            r.full.millions(),
            r.alone.millions(),
            cpu(&r.full_cpu),
            cpu(&r.alone_cpu),
            100.0 * r.tally_share.median,
            r.hits_per_line_alone,
            if r.same_hits { "yes" } else { "NO" }
        );
    }
}

pub(super) fn json<W: std::fmt::Write>(
    o: &mut JsonObject<'_, W>,
    rows: &[SplitRow],
) -> std::fmt::Result {
    o.object("split", |o| {
        for r in rows {
            let key = format!("{} {} {}t", r.scene, r.method.name(), r.threads);
            o.object(&key, |o| {
                o.string("scene", &r.scene)?;
                o.integer("patches", r.patches as u64)?;
                o.string("method", r.method.name())?;
                o.integer("threads", r.threads as u64)?;
                o.integer("lines", r.lines)?;
                spread_json(o, "full_lines_per_second", &r.full)?;
                spread_json(o, "alone_lines_per_second", &r.alone)?;
                if let Some(c) = &r.full_cpu {
                    spread_json(o, "full_lines_per_cpu_second", c)?;
                }
                if let Some(c) = &r.alone_cpu {
                    spread_json(o, "alone_lines_per_cpu_second", c)?;
                }
                spread_json(o, "tally_share", &r.tally_share)?;
                o.number("hits_per_line_full", r.hits_per_line_full)?;
                o.number("hits_per_line_alone", r.hits_per_line_alone)?;
                o.boolean("same_hits", r.same_hits)?;
                o.integer("patch_checksum", r.checksum)
            })?;
        }
        Ok(())
    })
}
