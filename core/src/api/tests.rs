//! Tests of the façade: exact and line measurements against the expert modules, the
//! line-budget loop, executors and partial results bit for bit.

extern crate std;

use alloc::vec::Vec;
use core::ops::Range;
use std::sync::Mutex;

use super::*;
use crate::ErrorKind;
use crate::io::partial::{fingerprint, merge_partials};
use crate::lines::CHUNK_LINES;
use crate::scene::{Material, Scene2};
use crate::tally::{LineMethod, LineTally};

/// The unit cube, faces facing inwards (an enclosure), as polygons.
const CUBE_VERTICES: [[f64; 3]; 8] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
    [0.0, 1.0, 1.0],
];
const CUBE_FACES: [u32; 24] = [
    0, 1, 2, 3, 4, 7, 6, 5, 0, 4, 5, 1, 1, 5, 6, 2, 2, 6, 7, 3, 3, 7, 4, 0,
];
const CUBE_OFFSETS: [u32; 7] = [0, 4, 8, 12, 16, 20, 24];

fn cube() -> Scene {
    Scene::from_polygons(&CUBE_VERTICES, &CUBE_FACES, &CUBE_OFFSETS, None).unwrap()
}

/// A unit square room (inward-facing sides) with a patch of length 10⁻⁵ on its floor: a
/// few 2¹⁶-line chunks miss it.
fn room_with_a_speck() -> Scene {
    let mut b = Scene2::builder();
    let p = |x, y| crate::geom::DVec2::new(x, y);
    b.segment_with_cuts(p(0.0, 0.0), p(1.0, 0.0), &[0.5, 0.50001])
        .unwrap();
    b.segment(p(1.0, 0.0), p(1.0, 1.0), 2).unwrap();
    b.segment(p(1.0, 1.0), p(0.0, 1.0), 2).unwrap();
    b.segment(p(0.0, 1.0), p(0.0, 0.0), 2).unwrap();
    Scene::Flat(b.build().unwrap())
}

fn lines(n: u64) -> Job {
    Job::Lines(LineJob::new(n).with_seed(7))
}

/// Two measurements are the same bits: form factors, measures, `I_S^c`, lines.
fn assert_same(a: &Measurement, b: &Measurement) {
    assert_eq!(a.form_factors(), b.form_factors());
    assert_eq!(a.measures(), b.measures());
    assert_eq!(a.checks(), b.checks());
    assert_eq!(a.continuous(), b.continuous());
    assert_eq!(a.patch_continuous(), b.patch_continuous());
    assert_eq!(a.lines(), b.lines());
    assert_eq!(a.coverage(), b.coverage());
}

/// An executor of `n` workers on threads: chunks handed out dynamically, each worker's
/// tally merged in reverse order of the workers.
struct Threads(usize);

impl Executor for Threads {
    fn execute(&mut self, work: &ChunkWork<'_>) -> ChunksDone {
        let next = Mutex::new(work.chunks().start);
        let end = work.chunks().end;
        let mut tallies: Vec<LineTally> = std::thread::scope(|s| {
            let workers: Vec<_> = (0..self.0)
                .map(|_| {
                    s.spawn(|| {
                        let mut t = work.new_tally();
                        loop {
                            let chunk = {
                                let mut n = next.lock().unwrap();
                                let c = *n;
                                *n += 1;
                                c
                            };
                            if chunk >= end {
                                break t;
                            }
                            work.cast(chunk, &mut t);
                        }
                    })
                })
                .collect();
            workers.into_iter().map(|w| w.join().unwrap()).collect()
        });
        let mut total = tallies.pop().unwrap_or_else(|| work.new_tally());
        while let Some(t) = tallies.pop() {
            total.merge_owned(t);
        }
        ChunksDone {
            tally: total,
            chunks: end - work.chunks().start,
        }
    }
    /// Rows handed out dynamically from the end (the longest rows last), each worker's
    /// results appended in reverse order of the workers: any order must give the same bits.
    fn execute_rows(&mut self, work: &RowWork<'_>) -> Vec<RowDone> {
        let next = Mutex::new(work.rows().end);
        let mut parts: Vec<Vec<RowDone>> = std::thread::scope(|s| {
            let workers: Vec<_> = (0..self.0)
                .map(|_| {
                    s.spawn(|| {
                        let mut done = Vec::new();
                        loop {
                            let row = {
                                let mut n = next.lock().unwrap();
                                if *n == 0 {
                                    break done;
                                }
                                *n -= 1;
                                *n
                            };
                            done.push(work.run(row));
                        }
                    })
                })
                .collect();
            workers.into_iter().map(|w| w.join().unwrap()).collect()
        });
        let mut all = Vec::new();
        while let Some(p) = parts.pop() {
            all.extend(p);
        }
        all
    }
}

/// An executor that stops (as after Ctrl-C) once it has cast `limit` chunks.
struct StopAfter {
    limit: u64,
    cast: u64,
}

impl Executor for StopAfter {
    fn execute(&mut self, work: &ChunkWork<'_>) -> ChunksDone {
        let mut tally = work.new_tally();
        let mut done = 0;
        for chunk in work.chunks() {
            if self.cast >= self.limit {
                break;
            }
            work.cast(chunk, &mut tally);
            self.cast += 1;
            done += 1;
        }
        ChunksDone {
            tally,
            chunks: done,
        }
    }

    fn stopped(&self) -> bool {
        self.cast >= self.limit
    }
}

#[test]
fn exact_flatland_from_text_is_the_expert_paths_bits() {
    let text = "poly 3 0 0 1 0 0.5 0.8660254037844386 per_side 10\n";
    let (scene, report) = Scene::from_text(text, SceneFormat::Flat, |_| None).unwrap();
    assert!(report.warnings.is_empty());
    assert!(scene.is_flat());
    let m = measure(&scene, &Job::Exact, &mut Serial).unwrap();
    let Scene::Flat(s) = &scene else {
        unreachable!()
    };
    let ff = crate::formfactor::exact_2d::form_factors(s).unwrap();
    assert_eq!(m.form_factors(), Some(&ff));
    assert_eq!(m.measures(), Some(&ff.channel().unwrap().measures()));
    assert_eq!(m.n_patches(), 30);
    assert!(m.warnings().is_empty());
    assert!(m.continuous().is_none() && m.coverage().is_none() && m.lines() == 0);
    // Tables 3.4/3.5: the triangle of 10 patches a side
    let measures = m.measures().unwrap();
    assert!((measures.i_s - 1.168).abs() < 5e-4, "{measures:?}");
    // Per patch: Σ I_i = I_S (6.9) and Σ a_i H_i = H_S (3.2)
    let a = m.patch_sizes();
    let i = m.patch_information().unwrap().unwrap();
    let h = m.patch_entropies().unwrap().unwrap();
    let dot = |x: &[f64]| a.iter().zip(x).map(|(a, x)| a * x).sum::<f64>();
    assert!((i.iter().sum::<f64>() - measures.i_s).abs() < 1e-12);
    assert!((dot(&h) - measures.h_s).abs() < 1e-12);
}

#[test]
fn exact_unoccluded_cube_from_arrays() {
    let m = measure(&cube(), &Job::Exact, &mut Serial).unwrap();
    let measures = m.measures().unwrap();
    assert!((measures.h_p - libm::log2(6.0)).abs() < 1e-12);
    // F_facing = 0.19982, F_adjacent = 0.20004 (×4)
    let (f, g) = (0.199_824_8, 0.200_043_8);
    let h_s = -(f * libm::log2(f) + 4.0 * g * libm::log2(g));
    assert!((measures.h_s - h_s).abs() < 1e-5, "{measures:?}");
    assert_eq!(m.background(), Some(false));
    // The same cube as triangles, and as OBJ text
    let tris: Vec<[u32; 3]> = CUBE_FACES
        .chunks(4)
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    let t = measure(
        &Scene::from_triangles(&CUBE_VERTICES, &tris, None).unwrap(),
        &Job::Exact,
        &mut Serial,
    )
    .unwrap();
    assert!((t.measures().unwrap().h_p - libm::log2(12.0)).abs() < 1e-12);
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
               f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
    let format = SceneFormat::Obj(crate::io::ObjOptions::default());
    let (scene, _) = Scene::from_bytes(obj.as_bytes(), format, |_| None).unwrap();
    let o = measure(&scene, &Job::Exact, &mut Serial).unwrap();
    assert_eq!(o.measures(), m.measures());
}

#[test]
fn lines_in_2d_and_3d_are_the_expert_estimates_bits() {
    let (flat, _) = Scene::from_text(
        "poly 4 0 0 1 0 1 1 0 1 per_side 3\nseg 0.3 0.5 0.7 0.5\n",
        SceneFormat::Flat,
        |_| None,
    )
    .unwrap();
    for method in LineMethod::ALL {
        let job = Job::Lines(LineJob::new(150_000).with_method(method).with_seed(3));
        let m = measure(&flat, &job, &mut Serial).unwrap();
        let Scene::Flat(s) = &flat else {
            unreachable!()
        };
        let est = crate::trace::estimate_2d::Tracer2::estimate(s, method, 3, 150_000).unwrap();
        assert_eq!(m.form_factors(), Some(&est.form_factors), "{method:?}");
        assert_eq!(m.continuous(), Some(est.continuous));
        assert_eq!(m.patch_continuous(), Some(&est.patch_continuous[..]));
        assert_eq!(m.lines(), est.lines);
    }
    let solid = cube();
    let m = measure(&solid, &lines(100_000), &mut Serial).unwrap();
    let Scene::Solid(s) = &solid else {
        unreachable!()
    };
    let est =
        crate::trace::estimate_3d::Tracer3::estimate(s, LineMethod::Global, 7, 100_000).unwrap();
    assert_eq!(m.form_factors(), Some(&est.form_factors));
    assert_eq!(m.continuous(), Some(est.continuous));
    let run = m.line_run().unwrap();
    assert_eq!(
        (run.lines, run.requested, run.budget_done),
        (100_000, 100_000, 100_000)
    );
    assert!(!run.interrupted);
    // The cube's measures from lines are near the exact ones
    let exact = measure(&solid, &Job::Exact, &mut Serial).unwrap();
    let (a, b) = (m.measures().unwrap(), exact.measures().unwrap());
    assert!((a.i_s - b.i_s).abs() < 0.01, "{a:?} {b:?}");
}

#[test]
fn several_workers_give_the_bits_of_one() {
    let scene = room_with_a_speck();
    let job = Job::Lines(LineJob::new(5 * CHUNK_LINES + 123).with_seed(11));
    let one = measure(&scene, &job, &mut Serial).unwrap();
    for workers in [1, 2, 3] {
        let many = measure(&scene, &job, &mut Threads(workers)).unwrap();
        assert_same(&one, &many);
    }
    let solid = cube();
    let one = measure(&solid, &lines(3 * CHUNK_LINES), &mut Serial).unwrap();
    let many = measure(&solid, &lines(3 * CHUNK_LINES), &mut Threads(3)).unwrap();
    assert_same(&one, &many);
}

#[test]
fn until_sampled_is_one_run_of_the_final_count() {
    let scene = room_with_a_speck();
    for start in [CHUNK_LINES, 50_000] {
        let budget = LineBudget::UntilSampled {
            start,
            max: 1 << 24,
        };
        let job = Job::Lines(LineJob::new(0).with_seed(5).with_budget(budget));
        let auto = measure(&scene, &job, &mut Threads(2)).unwrap();
        let run = *auto.line_run().unwrap();
        // Some doubling happened, and it stopped once the speck was reached
        assert!(run.requested > start, "{run:?}");
        assert!(auto.coverage().is_none() && auto.measures().is_some());
        assert_eq!(run.auto_max, Some(1 << 24));
        assert_eq!(run.budget_done, run.requested);
        let fixed = Job::Lines(LineJob::new(run.requested).with_seed(5));
        let once = measure(&scene, &fixed, &mut Serial).unwrap();
        assert_same(&auto, &once);
    }
    // A cap below the count it needs: the coverage, I_S^c, no measures, a warning
    let budget = LineBudget::UntilSampled {
        start: 1000,
        max: 2000,
    };
    let job = Job::Lines(LineJob::new(0).with_seed(5).with_budget(budget));
    let m = measure(&scene, &job, &mut Serial).unwrap();
    assert_eq!(m.lines(), 2000);
    let c = m.coverage().unwrap();
    assert_eq!((c.unsampled, c.first_unsampled), (1, Some(1)));
    assert!(m.measures().is_none() && m.form_factors().is_none());
    assert!(m.continuous().unwrap().value > 0.0);
    assert!(matches!(
        m.warnings()[0],
        Warning::UnsampledPatches { unsampled: 1, .. }
    ));
}

#[test]
fn chunk_ranges_merged_are_the_whole_job() {
    let scene = room_with_a_speck();
    let n = 6 * CHUNK_LINES + 5;
    let whole = measure(&scene, &lines(n), &mut Serial).unwrap();
    let parts: Vec<_> = [0..2, 5..7, 2..5]
        .into_iter()
        .map(|c: Range<u64>| {
            let job = LineJob::new(n).with_seed(7).with_chunks(c);
            measure_partial(&scene, fingerprint(b"room"), &job, &mut Threads(2)).unwrap()
        })
        .collect();
    let merged = merge_partials(parts).unwrap();
    assert_same(&Measurement::from_partial(merged).unwrap(), &whole);
    // A partial's chunks past the job, and chunks given to `measure`, are refused
    let past = LineJob::new(n).with_chunks(6..8);
    assert!(measure_partial(&scene, 0, &past, &mut Serial).is_err());
    let some = Job::Lines(LineJob::new(n).with_chunks(0..1));
    assert!(measure(&scene, &some, &mut Serial).is_err());
}

#[test]
fn a_stopped_executor_gives_the_job_of_the_chunks_it_cast() {
    let scene = room_with_a_speck();
    let job = Job::Lines(LineJob::new(5 * CHUNK_LINES).with_seed(7));
    let mut stop = StopAfter { limit: 2, cast: 0 };
    let m = measure(&scene, &job, &mut stop);
    let run = match &m {
        Ok(m) => *m.line_run().unwrap(),
        Err(e) => panic!("{e}"),
    };
    assert!(run.interrupted);
    assert_eq!(
        (run.lines, run.requested),
        (2 * CHUNK_LINES, 5 * CHUNK_LINES)
    );
    let two = measure(&scene, &lines(2 * CHUNK_LINES), &mut Serial).unwrap();
    assert_eq!(m.unwrap().continuous(), two.continuous());
    // A partial result records the chunks cast
    let mut stop = StopAfter { limit: 1, cast: 0 };
    let job = LineJob::new(5 * CHUNK_LINES).with_chunks(2..4);
    let p = measure_partial(&scene, 1, &job, &mut stop).unwrap();
    assert_eq!(p.chunks, 2..3);
}

#[test]
fn arrays_are_validated_with_their_row() {
    let seg = [[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 1.0, 0.0]];
    let e = Scene::from_segments(&seg, None).unwrap_err();
    assert_eq!(
        (e.kind(), e.line()),
        (&ErrorKind::ZeroLengthSegment, Some(2))
    );
    let e = Scene::from_segments(&seg[..1], Some(&[])).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::DimensionMismatch { .. }));
    let lit = [Material::new([0.5; 3], [1.0; 3]).unwrap()];
    let s = Scene::from_segments(&seg[..1], Some(&lit)).unwrap();
    let Scene::Flat(flat) = &s else {
        unreachable!()
    };
    assert_eq!(flat.patch_material(0), Some(&lit[0]));
    let e = Scene::from_triangles(&CUBE_VERTICES, &[[0, 1, 8]], None).unwrap_err();
    assert_eq!(e.line(), Some(1));
    assert_eq!(e.kind(), &ErrorKind::VertexIndex { index: 8, count: 8 });
    let e = Scene::from_polygons(&CUBE_VERTICES, &CUBE_FACES, &[0, 4, 30], None).unwrap_err();
    assert_eq!(e.line(), Some(2));
    assert!(Scene::from_polygons(&CUBE_VERTICES, &CUBE_FACES, &[1, 4], None).is_err());
    assert!(Scene::from_polygons(&CUBE_VERTICES, &CUBE_FACES, &[4, 0], None).is_err());
    // An empty scene, and bytes that are not UTF-8 (line 2)
    assert!(Scene::from_polygons(&CUBE_VERTICES, &[], &[], None).is_err());
    let e = Scene::from_bytes(b"seg 0 0 1 0\r\nseg \xff", SceneFormat::Flat, |_| None).unwrap_err();
    assert_eq!((e.kind(), e.line()), (&ErrorKind::InvalidUtf8, Some(2)));
}

#[test]
fn budgets_and_memory_are_checked_before_any_work() {
    let scene = cube();
    for bad in [
        LineBudget::Fixed(0),
        LineBudget::Fixed(u64::MAX),
        LineBudget::UntilSampled { start: 0, max: 10 },
    ] {
        let job = Job::Lines(LineJob::new(1).with_budget(bad));
        assert!(measure(&scene, &job, &mut Serial).is_err(), "{bad:?}");
    }
    let e = lines(1000).check_memory(2000, 3, 1 << 20).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::MemoryLimit { .. }));
    assert!(Job::Exact.check_memory(6, 1, 1 << 20).is_ok());
    // A 3D exact job of more than 2,048 patches is stored sparse: judged on its per-patch
    // arrays (64 bytes a patch), not on the dense 8 n² + 8 (n + 1)² (≈ 216 MB here).
    let big = Scene::Solid(crate::scene::Scene3::preset("cubes-512-random", 1).unwrap());
    assert_eq!(big.n_patches(), 3672);
    assert!(Job::Exact.check_memory(3672, 1, 1 << 20).is_err());
    assert!(Job::Exact.check_memory_of(&big, 1, 1 << 20).is_ok());
    let e = Job::Exact.check_memory_of(&big, 1, 1000).unwrap_err();
    assert!(matches!(
        e.kind(),
        ErrorKind::MemoryLimit {
            needed: 235_008,
            ..
        }
    ));
    // A line job keeps its dense tallies' estimate.
    assert!(lines(1000).check_memory_of(&big, 3, 1 << 20).is_err());
}

#[test]
fn a_session_stepped_chunk_by_chunk_is_the_whole_job() {
    let scene = room_with_a_speck();
    let n = 4 * CHUNK_LINES + 77;
    let job = LineJob::new(n).with_seed(7);
    let mut session = LineSession::new(&scene, &job).unwrap();
    assert!(session.measurement().is_err(), "no line cast yet");
    assert_eq!(session.cast(2, &mut Serial), 2 * CHUNK_LINES);
    assert!(!session.is_done());
    // After two chunks: the job of two chunks, marked as stopped short of the budget
    let early = session.measurement().unwrap();
    let two = measure(&scene, &lines(2 * CHUNK_LINES), &mut Serial).unwrap();
    assert_eq!(early.continuous(), two.continuous());
    assert!(early.line_run().unwrap().interrupted);
    // The rest, on workers, in steps that overshoot the end
    while !session.is_done() {
        session.cast(2, &mut Threads(2));
    }
    assert_eq!(session.lines_done(), n);
    let whole = measure(&scene, &Job::Lines(job), &mut Serial).unwrap();
    assert_same(&session.measurement().unwrap(), &whole);
}

/// The unit cube with a lamp for a ceiling and grey walls.
fn lit_cube() -> Scene {
    let grey = Material::new([0.5, 0.6, 0.7], [0.0; 3]).unwrap();
    let lamp = Material::new([0.0; 3], [1.0, 2.0, 3.0]).unwrap();
    let materials = [grey, lamp, grey, grey, grey, grey];
    Scene::from_polygons(&CUBE_VERTICES, &CUBE_FACES, &CUBE_OFFSETS, Some(&materials)).unwrap()
}

#[test]
fn radiosity_on_exact_form_factors_is_the_expert_solve() {
    use crate::radiosity::rgb::{rgb_measures, solve_rgb};
    let scene = lit_cube();
    let job = RadiosityJob::new(Job::Exact);
    let lit = solve_radiosity(&scene, &job, &mut Serial).unwrap();
    let m = Measurement::exact(&scene).unwrap();
    let ff = m.form_factors().unwrap();
    let materials = scene.patch_materials();
    let expert = solve_rgb(
        &ff.matrix(),
        ff.weights(),
        &materials,
        job.solver,
        &job.options,
    )
    .unwrap();
    let measures = rgb_measures(&ff.matrix(), ff.weights(), &expert).unwrap();
    assert_eq!(lit.solution(), &expert);
    assert_eq!(lit.measures(), &measures);
    assert_eq!(lit.form_factors(), ff);
    assert!(lit.lines().is_none());
    // Light flows in every channel, and B = E + ρ F B holds at the solution
    assert!(lit.measures().iter().all(|m| m.light_flows && m.i_s > 0.0));
    let b = &lit.solution().radiosity;
    for (i, row) in b.iter().enumerate() {
        for c in 0..3 {
            let mut gathered = 0.0;
            for (j, bj) in b.iter().enumerate() {
                gathered += ff.get(i, j) * bj[c];
            }
            let m = &materials[i];
            let want = m.emittance[c] + m.reflectance[c] * gathered;
            assert!((row[c] - want).abs() < 1e-8, "B_{i}[{c}]");
        }
    }
}

#[test]
fn radiosity_from_lines_is_the_same_bits_on_any_executor() {
    let scene = lit_cube();
    let job = RadiosityJob::new(Job::Lines(LineJob::new(3 * CHUNK_LINES).with_seed(3)));
    let one = solve_radiosity(&scene, &job, &mut Serial).unwrap();
    let other = solve_radiosity(&scene, &job, &mut Threads(2)).unwrap();
    assert_eq!(one.solution(), other.solution());
    assert_eq!(one.lines(), other.lines());
    let l = one.lines().unwrap();
    assert_eq!(l.lines, 3 * CHUNK_LINES);
    assert!(l.visibility.value > 0.0 && l.radiosity.iter().all(|e| e.value > 0.0));
    // The lines' form factors are close to the exact ones (6 patches, 196 608 lines)
    let exact = solve_radiosity(&scene, &RadiosityJob::new(Job::Exact), &mut Serial).unwrap();
    let (a, b) = (one.form_factors(), exact.form_factors());
    for i in 0..6 {
        for j in 0..6 {
            assert!((a.get(i, j) - b.get(i, j)).abs() < 0.01, "F_{i}{j}");
        }
    }
}

#[test]
fn radiosity_refuses_unsampled_patches_and_stopped_jobs() {
    let scene = room_with_a_speck();
    let job = RadiosityJob::new(Job::Lines(LineJob::new(1000).with_seed(7)));
    let e = solve_radiosity(&scene, &job, &mut Serial).unwrap_err();
    assert!(
        matches!(
            e.kind(),
            ErrorKind::RowsUnknown {
                unsampled: 1,
                n_patches: 9,
                lines: 1000,
                ..
            }
        ),
        "{e}"
    );
    let job = RadiosityJob::new(Job::Lines(LineJob::new(5 * CHUNK_LINES).with_seed(7)));
    let mut stop = StopAfter { limit: 2, cast: 0 };
    let e = solve_radiosity(&scene, &job, &mut stop).unwrap_err();
    assert_eq!(e.kind(), &ErrorKind::Stopped);
    let chunks = Job::Lines(LineJob::new(5 * CHUNK_LINES).with_chunks(0..1));
    assert!(solve_radiosity(&scene, &RadiosityJob::new(chunks), &mut Serial).is_err());
}

#[test]
fn a_dropped_term_of_i_c_reaches_the_warnings() {
    // A clean run: no saturation, no warning
    let scene = cube();
    let clean = measure(&scene, &lines(CHUNK_LINES), &mut Serial).unwrap();
    assert!(!clean.line_run().unwrap().sums_out_of_range);
    assert!(!clean.warnings().contains(&Warning::SumsOutOfRange));
    // The same lines, then one NaN term (as a degenerate pair could give): the fixed-point
    // sums drop it and flag it, and the flag must reach the measurement, not vanish
    let tracer = scene.tracer().unwrap();
    let job = LineJob::new(CHUNK_LINES);
    let mut run = LineRun::cast_lines(
        tracer.as_dyn(),
        job.method,
        job.seed,
        job.budget,
        &mut Serial,
    );
    assert!(!run.tally.sums_out_of_range());
    run.tally.continuous.add_group(f64::NAN, 1);
    assert!(run.tally.sums_out_of_range());
    let info = LineRunInfo {
        method: job.method,
        seed: job.seed,
        lines: run.tally.lines(),
        requested: run.lines,
        budget_done: run.budget_done,
        interrupted: false,
        auto_max: None,
        continuous: run.tally.continuous(),
        sums_out_of_range: run.tally.sums_out_of_range(),
    };
    let m = Measurement::of_tally(run.tally, tracer.as_dyn(), info, &mut crate::Serial).unwrap();
    assert!(
        m.warnings().contains(&Warning::SumsOutOfRange),
        "{:?}",
        m.warnings()
    );
    // A per-patch sum out of range counts too
    let mut run = LineRun::cast_lines(
        tracer.as_dyn(),
        job.method,
        job.seed,
        job.budget,
        &mut Serial,
    );
    run.tally.patch_info[2].add(f64::INFINITY);
    assert!(run.tally.sums_out_of_range());
}

/// `Measurement::exact_within` measures a 3D scene in which a polygon hides part of another
/// (`Job::Exact` refuses it: the cost depends on a tolerance the caller must choose): the
/// error estimates come with it, within the tolerance; an unoccluded scene has none.
#[test]
fn exact_within_measures_an_occluded_scene_with_estimates() {
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
               f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
    let inner =
        "v 0.4 0.4 0.4\nv 0.6 0.4 0.4\nv 0.6 0.6 0.4\nv 0.4 0.6 0.4\nf 12 11 10 9\nf 9 10 11 12\n";
    let format = SceneFormat::Obj(crate::io::ObjOptions::default());
    let (open, _) = Scene::from_bytes(obj.as_bytes(), format, |_| None).unwrap();
    assert!(
        measure(&open, &Job::Exact, &mut Serial)
            .unwrap()
            .exact_errors()
            .is_none()
    );
    let text = alloc::format!("{obj}{inner}");
    let (scene, _) = Scene::from_bytes(text.as_bytes(), format, |_| None).unwrap();
    let refused = measure(&scene, &Job::Exact, &mut Serial).unwrap_err();
    assert!(
        matches!(refused.kind(), ErrorKind::MayBeOccluded),
        "{refused}"
    );
    let options = crate::formfactor::occluded_3d::OcclusionOptions::new(1e-4);
    let m = Measurement::exact_within(&scene, &options, &mut Serial).unwrap();
    let e = m.exact_errors().unwrap();
    assert!(e.pairs_integrated > 0 && e.over_tolerance == 0 && e.max_error <= 1e-4);
    // A closed scene (the square is two-sided): rows within their estimates of 1.
    assert!(m.max_row_deficit().unwrap() <= e.max_row_error + 1e-12);
    let bad = crate::formfactor::occluded_3d::OcclusionOptions::new(0.0);
    assert!(Measurement::exact_within(&scene, &bad, &mut Serial).is_err());
}

/// The exact 3D job with occlusion gives the same bits on 1, 2 and 3 threads (rows handed
/// out in another order), and on an unoccluded scene `measure_exact`'s bits; an executor
/// that computes no row stops the job.
#[test]
fn exact_within_is_the_same_on_any_thread_count() {
    let room = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n";
    let plate =
        "v 0.3 0.2 0.5\nv 0.7 0.2 0.5\nv 0.7 0.6 0.5\nv 0.3 0.6 0.5\nf 12 11 10 9\nf 9 10 11 12\n";
    let format = SceneFormat::Obj(crate::io::ObjOptions::default());
    let options = crate::formfactor::occluded_3d::OcclusionOptions::new(1e-4);
    let (open, _) = Scene::from_bytes(room.as_bytes(), format, |_| None).unwrap();
    let serial = Measurement::exact(&open).unwrap();
    for threads in 1..=3 {
        let m = Measurement::exact_within(&open, &options, &mut Threads(threads)).unwrap();
        assert_same(&serial, &m);
    }
    let text = alloc::format!("{room}{plate}");
    let (scene, _) = Scene::from_bytes(text.as_bytes(), format, |_| None).unwrap();
    let serial = Measurement::exact_within(&scene, &options, &mut Serial).unwrap();
    assert!(serial.exact_errors().unwrap().pairs_integrated > 0);
    for threads in 1..=3 {
        let m = Measurement::exact_within(&scene, &options, &mut Threads(threads)).unwrap();
        assert_same(&serial, &m);
        assert_eq!(serial.exact_errors(), m.exact_errors());
    }
    // Stopped before any row (as after Ctrl-C): no result, a typed error
    struct NoRows;
    impl Executor for NoRows {
        fn execute(&mut self, work: &ChunkWork<'_>) -> ChunksDone {
            Serial.execute(work)
        }
        fn execute_rows(&mut self, _: &RowWork<'_>) -> Vec<RowDone> {
            Vec::new()
        }
    }
    let stopped = Measurement::exact_within(&scene, &options, &mut NoRows).unwrap_err();
    assert!(matches!(stopped.kind(), ErrorKind::Stopped), "{stopped}");
}

/// The room with a two-sided plate of `exact_within_is_the_same_on_any_thread_count`.
fn room_with_plate() -> Scene {
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\n\
                v 0.3 0.2 0.5\nv 0.7 0.2 0.5\nv 0.7 0.6 0.5\nv 0.3 0.6 0.5\n\
                f 12 11 10 9\nf 9 10 11 12\n";
    let format = SceneFormat::Obj(crate::io::ObjOptions::default());
    Scene::from_bytes(text.as_bytes(), format, |_| None)
        .unwrap()
        .0
}

/// Every non-zero entry `(i, j, F_ij, error)` of a measurement.
fn entries(m: &Measurement) -> Vec<(usize, usize, u64, Option<u64>)> {
    let mut out = Vec::new();
    m.for_each_form_factor(|i, j, v, e| out.push((i, j, v.to_bits(), e.map(f64::to_bits))));
    out
}

/// Exact rows computed whole, or in three ranges on different executors, through their
/// files and merged in any order, give the dense job's form factors and error estimates
/// bit for bit, stored sparse; the channel measures agree to rounding.
#[test]
fn exact_rows_in_ranges_merge_into_the_dense_job_bit_for_bit() {
    let scene = room_with_plate();
    let options = crate::formfactor::occluded_3d::OcclusionOptions::new(1e-4);
    let dense = Measurement::exact_within(&scene, &options, &mut Serial).unwrap();
    assert!(!dense.form_factors().unwrap().is_sparse());
    let whole = ExactRows::compute(&scene, 7, &options, None, &mut Threads(2)).unwrap();
    assert!(whole.is_complete() && whole.rows() == (0..8));
    let sparse = Measurement::from_exact_rows(whole.clone()).unwrap();
    assert!(sparse.form_factors().unwrap().is_sparse());
    assert_eq!(entries(&dense), entries(&sparse));
    let (d, s) = (
        dense.exact_errors().unwrap(),
        sparse.exact_errors().unwrap(),
    );
    assert!(d.pairs_integrated > 0);
    assert_eq!(
        (
            d.max_error,
            d.max_row_error,
            d.pairs_integrated,
            d.over_tolerance
        ),
        (
            s.max_error,
            s.max_row_error,
            s.pairs_integrated,
            s.over_tolerance
        )
    );
    let (dm, sm) = (dense.measures().unwrap(), sparse.measures().unwrap());
    assert!((dm.i_s - sm.i_s).abs() <= 1e-13 && (dm.h_s - sm.h_s).abs() <= 1e-13);
    // Three ranges, each through its file, merged in another order
    let mut parts = Vec::new();
    for (rows, threads) in [(3..6, 1), (0..3, 3), (6..8, 2)] {
        let p = ExactRows::compute(&scene, 7, &options, Some(rows), &mut Threads(threads));
        let bytes = p.unwrap().to_bytes();
        parts.push(ExactRows::from_bytes(&bytes).unwrap());
    }
    let merged = ExactRows::merge(parts.clone()).unwrap();
    assert_eq!(merged, whole);
    let m = Measurement::from_exact_rows(merged).unwrap();
    assert_eq!(entries(&m), entries(&sparse));
    assert_eq!(m.exact_errors(), sparse.exact_errors());
    // Merged in stages too
    let first = ExactRows::merge(parts[..2].to_vec()).unwrap();
    assert_eq!(first.rows(), 0..6);
    assert_eq!(
        ExactRows::merge(alloc::vec![parts[2].clone(), first]).unwrap(),
        whole
    );
}

/// Where the row cap has work to do (the closed room with a plate at loose tolerances,
/// whose rows come out above 1 within their estimates), the dense job and exact rows
/// (sparse) still give the same bits, the same count of rows scaled, rows at most 1, and
/// (no row scaled, no pair over the tolerance) every estimate within the tolerance.
#[test]
fn the_row_cap_gives_the_same_bits_dense_and_sparse() {
    let scene = room_with_plate();
    let Scene::Solid(solid) = &scene else {
        unreachable!("a 3D scene")
    };
    let polygons: Vec<(usize, usize)> =
        solid.patches().iter().map(|p| (p.first, p.count)).collect();
    let mut capped_somewhere = false;
    for tol in [1e-1, 3e-2, 1e-2] {
        let options = crate::formfactor::occluded_3d::OcclusionOptions::new(tol);
        // The rows before the cap: is some row above 1?
        let raw = crate::formfactor::occluded_3d::occluded_rows_by(
            solid.points(),
            &polygons,
            &options,
            0..polygons.len(),
            &mut |n, row| Some((0..n).map(row).collect()),
        )
        .unwrap();
        let mut sums = alloc::vec![0.0; polygons.len()];
        for (i, row) in raw.rows.iter().enumerate() {
            for &(j, flux, _) in &row.pairs {
                sums[i] += (flux / raw.areas[i]).min(1.0);
                sums[j] += (flux / raw.areas[j]).min(1.0);
            }
        }
        capped_somewhere |= sums.iter().any(|&s| s > 1.0);
        let dense = Measurement::exact_within(&scene, &options, &mut Serial).unwrap();
        let rows = ExactRows::compute(&scene, 7, &options, None, &mut Threads(2)).unwrap();
        let sparse = Measurement::from_exact_rows(rows).unwrap();
        assert_eq!(entries(&dense), entries(&sparse), "tolerance {tol}");
        let (d, s) = (
            dense.exact_errors().unwrap(),
            sparse.exact_errors().unwrap(),
        );
        assert_eq!(
            (
                d.max_error,
                d.max_row_error,
                d.rows_scaled,
                d.over_tolerance
            ),
            (
                s.max_error,
                s.max_row_error,
                s.rows_scaled,
                s.over_tolerance
            ),
            "tolerance {tol}"
        );
        let ff = dense.form_factors().unwrap();
        for i in 0..ff.n_patches() {
            let row: f64 = (0..ff.n_patches()).map(|j| ff.get(i, j)).sum();
            assert!(row <= 1.0 + 1e-14, "tolerance {tol}, row {i}: {row}");
        }
        if d.rows_scaled == 0 && d.over_tolerance == 0 {
            assert!(d.max_error <= tol, "tolerance {tol}: {}", d.max_error);
        }
    }
    assert!(capped_somewhere, "no row above 1: the test checks nothing");
}

/// Incomplete, overlapping, gapped and foreign row ranges are refused with typed errors;
/// so are damaged files, flatland scenes and rows outside the scene.
#[test]
fn exact_rows_refuse_what_is_not_one_job() {
    let scene = room_with_plate();
    let options = crate::formfactor::occluded_3d::OcclusionOptions::new(1e-3);
    let part = |rows: Range<usize>, fp: u64, o| {
        ExactRows::compute(&scene, fp, &o, Some(rows), &mut Serial).unwrap()
    };
    let kind = |e: crate::Error| e.kind().clone();
    let a = part(0..4, 1, options);
    assert!(matches!(
        kind(Measurement::from_exact_rows(a.clone()).unwrap_err()),
        ErrorKind::MissingRows { have, total: 8 } if have == (0..4)
    ));
    let overlap = ExactRows::merge(alloc::vec![a.clone(), part(3..8, 1, options)]).unwrap_err();
    assert!(matches!(kind(overlap), ErrorKind::RowRanges { .. }));
    let gap = ExactRows::merge(alloc::vec![a.clone(), part(5..8, 1, options)]).unwrap_err();
    let text = alloc::format!("{gap}");
    assert!(
        text.contains("rows 4..5 are in no partial result"),
        "{text}"
    );
    let other = ExactRows::merge(alloc::vec![a.clone(), part(4..8, 2, options)]).unwrap_err();
    assert!(matches!(
        kind(other),
        ErrorKind::PartialMismatch { field: "scene" }
    ));
    let looser = crate::formfactor::occluded_3d::OcclusionOptions::new(1e-2);
    let other = ExactRows::merge(alloc::vec![a.clone(), part(4..8, 1, looser)]).unwrap_err();
    assert!(matches!(
        kind(other),
        ErrorKind::PartialMismatch { field: "tolerance" }
    ));
    // Every single damaged byte, and every cut, is refused
    let bytes = a.to_bytes();
    for k in 0..bytes.len() {
        let mut bad = bytes.clone();
        bad[k] ^= 0x10;
        assert!(ExactRows::from_bytes(&bad).is_err(), "byte {k}");
        assert!(ExactRows::from_bytes(&bytes[..k]).is_err(), "cut at {k}");
    }
    let line_partial = b"SCNINFOP\x01\x00\x00\x00";
    assert!(ExactRows::from_bytes(line_partial).is_err());
    let flat = Scene::Flat(Scene2::catalogue("l-room-0", 2).unwrap());
    let e = ExactRows::compute(&flat, 0, &options, None, &mut Serial).unwrap_err();
    assert!(matches!(kind(e), ErrorKind::UnsupportedMethod { .. }));
    let e = ExactRows::compute(&scene, 0, &options, Some(4..9), &mut Serial).unwrap_err();
    assert!(matches!(
        kind(e),
        ErrorKind::BadParameter { name: "rows", .. }
    ));
}

/// A pair of small patches hidden behind a plate, whose unoccluded flux fits the
/// tolerance, is decided as `0 ± U` by the bound (`occluded_3d::budget`): its value is 0
/// (not a stored entry) and its estimate is read by `for_each_zero_with_error`, the same
/// from the dense job and from exact rows (sparse).
#[test]
fn a_hidden_pair_decided_by_its_bound_keeps_its_estimate() {
    // Squares of side 0.01 at z = 0 (facing up) and z = 1 (facing down), a plate of side
    // 1 at z = 0.5 facing down between them.
    let text = "v 0 0 0\nv 0.01 0 0\nv 0.01 0.01 0\nv 0 0.01 0\n\
                v 0 0 1\nv 0.01 0 1\nv 0.01 0.01 1\nv 0 0.01 1\n\
                v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n\
                f 1 2 3 4\nf 5 8 7 6\nf 9 12 11 10\n";
    let format = SceneFormat::Obj(crate::io::ObjOptions::default());
    let (scene, _) = Scene::from_bytes(text.as_bytes(), format, |_| None).unwrap();
    let options = crate::formfactor::occluded_3d::OcclusionOptions::new(1e-3);
    let dense = Measurement::exact_within(&scene, &options, &mut Serial).unwrap();
    let ff = dense.form_factors().unwrap();
    assert_eq!(ff.get(0, 1), 0.0);
    assert_eq!(ff.get(1, 0), 0.0);
    let zeros = |m: &Measurement| {
        let mut out = Vec::new();
        m.for_each_zero_with_error(|i, j, e| out.push((i, j, e.to_bits())));
        out
    };
    let found = zeros(&dense);
    let pairs: Vec<(usize, usize)> = found.iter().map(|&(i, j, _)| (i, j)).collect();
    assert_eq!(pairs, [(0, 1), (1, 0)]);
    // The unoccluded F between the squares is about A / (π d²) = 3.2e-5: the estimate
    // is that, within the tolerance.
    for &(_, _, e) in &found {
        let e = f64::from_bits(e);
        assert!(e > 1e-5 && e <= 1e-3, "{e}");
    }
    let whole = ExactRows::compute(&scene, 3, &options, None, &mut Serial).unwrap();
    let sparse = Measurement::from_exact_rows(whole).unwrap();
    assert_eq!(zeros(&sparse), found);
    assert_eq!(entries(&sparse), entries(&dense));
}

/// Whole rows of `F` from only the job's rows they need (`ExactRows::form_factor_rows`): without
/// occlusion (the cube) the rows `0..max(P) + 1`, with it (the room with a plate) every
/// row; either way each row held is the whole matrix's row bit for bit, values and
/// estimates, and a row not held is refused. At 1e-1 the room's rows are capped
/// (`the_row_cap_gives_the_same_bits_dense_and_sparse`).
#[test]
fn exact_form_factor_rows_are_the_whole_matrix_s_rows_bit_for_bit() {
    let options = crate::formfactor::occluded_3d::OcclusionOptions::new(1e-4);
    let loose = crate::formfactor::occluded_3d::OcclusionOptions::new(1e-1);
    for (scene, occluded, options) in [
        (cube(), false, options),
        (room_with_plate(), true, options),
        (room_with_plate(), true, loose),
    ] {
        let n = scene.n_patches();
        let all = ExactRows::compute(&scene, 7, &options, None, &mut Threads(2)).unwrap();
        let whole = Measurement::from_exact_rows(all).unwrap();
        let ff = whole.form_factors().unwrap();
        let mut expected = alloc::vec![0.0; ff.n_states()];
        let mut got = alloc::vec![0.0; n];
        for wanted in [&[0][..], &[2, 1, 2], &[n - 1], &[]] {
            let rows =
                ExactRows::form_factor_rows(&scene, 7, &options, wanted, &mut Threads(2)).unwrap();
            let end = wanted.iter().max().map_or(0, |&p| p + 1);
            let held = if occluded && end > 0 { 0..n } else { 0..end };
            assert_eq!(rows.rows(), held, "{wanted:?}");
            assert_eq!(rows.may_occlude(), occluded);
            let computed = ExactRows::compute(&scene, 7, &options, Some(held.clone()), &mut Serial)
                .unwrap()
                .pair_count();
            assert_eq!(rows.pair_count(), computed, "{wanted:?}");
            for p in held.clone() {
                ff.dense_row_into(p, &mut expected).unwrap();
                rows.row_into(p, &mut got).unwrap();
                let bits = |r: &[f64]| r[..n].iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&got), bits(&expected), "row {p} of {wanted:?}");
                // The estimates of the non-zero entries, as the measurement keeps them
                let mut mine = Vec::new();
                rows.for_each_in_row(p, |j, v, e| {
                    if v != 0.0 {
                        mine.push((j, v.to_bits(), e.to_bits()));
                    }
                })
                .unwrap();
                let theirs: Vec<_> = entries(&whole)
                    .into_iter()
                    .filter(|&(i, j, _, _)| i == p && j < n)
                    .map(|(_, j, v, e)| (j, v, e.unwrap_or(0.0f64.to_bits())))
                    .collect();
                assert_eq!(mine, theirs, "row {p} of {wanted:?}");
            }
            if held.end < n {
                let e = rows.row_into(held.end, &mut got).unwrap_err();
                assert!(matches!(e.kind(), ErrorKind::MissingRows { .. }), "{e}");
            }
        }
        let e = ExactRows::form_factor_rows(&scene, 7, &options, &[n], &mut Serial).unwrap_err();
        assert!(
            matches!(e.kind(), ErrorKind::PatchIndex { index, len } if *index == n && *len == n)
        );
    }
    // A range not from row 0 is refused; the first rows of an occluded job hold no row
    let scene = room_with_plate();
    let late = ExactRows::compute(&scene, 7, &options, Some(2..4), &mut Serial).unwrap();
    let e = late.whole_rows().unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::MissingRows { .. }), "{e}");
    let early = ExactRows::compute(&scene, 7, &options, Some(0..4), &mut Serial).unwrap();
    assert_eq!(early.whole_rows().unwrap().rows(), 0..0);
}
