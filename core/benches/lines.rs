//! Criterion benchmarks of the line-casting hot paths, each beside its naive baseline.
//!
//! `cargo bench -p sceneinfo` (add `-- --quick` for a fast pass). Whole jobs, threads and
//! memory are measured by `sceneinfo bench`.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use sceneinfo::accel::{Bvh2, Bvh3, Hit2, Hit3};
use sceneinfo::formfactor::exact_3d;
use sceneinfo::geom::{DVec2, DVec3, Segment};
use sceneinfo::lines::{BoundingCircle, BoundingSphere, Line2, Line3, canonical, chunk_rng};
use sceneinfo::scene::{Scene2, Scene3};
use sceneinfo::tally::{LineMethod, LineTracer};
use sceneinfo::trace::estimate_2d::Tracer2;
use sceneinfo::trace::estimate_3d::Tracer3;

/// Lines per measured batch.
const BATCH: usize = 4096;

fn lines_2d(scene: &Scene2) -> Vec<Line2> {
    let (lo, hi) = scene.bounds();
    let circle = BoundingCircle::of_bounds(lo, hi);
    let mut rng = chunk_rng(1, 0);
    (0..BATCH)
        .map(|_| Line2::global(&circle, [canonical(&mut rng), canonical(&mut rng)]))
        .collect()
}

fn lines_3d(scene: &Scene3) -> Vec<Line3> {
    let (lo, hi) = scene.bounds();
    let sphere = BoundingSphere::of_bounds(lo, hi);
    let mut rng = chunk_rng(1, 0);
    (0..BATCH)
        .map(|_| {
            let u = [(); 4].map(|()| canonical(&mut rng));
            Line3::global(&sphere, u)
        })
        .collect()
}

fn queries_2d(c: &mut Criterion) {
    let scene = Scene2::catalogue("64-squares-a", 10).unwrap();
    let segments: Vec<Segment> = scene.patches().iter().map(|p| p.segment).collect();
    let bvh = Bvh2::build(&segments).unwrap();
    let lines = lines_2d(&scene);
    let mut g = c.benchmark_group("all_hits 2D, 64 squares");
    g.throughput(Throughput::Elements(BATCH as u64));
    let mut hits = Vec::new();
    g.bench_function("bvh", |b| {
        b.iter(|| {
            for l in &lines {
                bvh.all_hits(l, &mut hits);
                black_box(&hits);
            }
        });
    });
    g.bench_function("naive", |b| {
        b.iter(|| {
            for l in &lines {
                Hit2::all_naive(&segments, l, &mut hits);
                black_box(&hits);
            }
        });
    });
    g.finish();
}

fn queries_3d(c: &mut Criterion) {
    let room = sceneinfo::scene::Scene3::preset("cubes-512-random", 1).unwrap();
    let points = room.points().to_vec();
    let polygons: Vec<(usize, usize)> = room.patches().iter().map(|p| (p.first, p.count)).collect();
    let bvh = Bvh3::build(&points, &polygons).unwrap();
    let lines = lines_3d(&room);
    let mut g = c.benchmark_group("all_hits 3D, room with 512 cubes");
    g.throughput(Throughput::Elements(BATCH as u64));
    let mut hits = Vec::new();
    g.bench_function("bvh", |b| {
        b.iter(|| {
            for l in &lines {
                bvh.all_hits(l, &mut hits);
                black_box(&hits);
            }
        });
    });
    g.finish();

    let scene = Scene3::cube(30).unwrap();
    let points = scene.points().to_vec();
    let polygons: Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    let bvh = Bvh3::build(&points, &polygons).unwrap();
    let lines = lines_3d(&scene);
    let mut g = c.benchmark_group("all_hits 3D, cube 5400");
    g.throughput(Throughput::Elements(BATCH as u64));
    let mut hits = Vec::new();
    g.bench_function("bvh", |b| {
        b.iter(|| {
            for l in &lines {
                bvh.all_hits(l, &mut hits);
                black_box(&hits);
            }
        });
    });
    g.sample_size(10);
    g.bench_function("naive", |b| {
        b.iter(|| {
            for l in &lines[..256] {
                Hit3::all_naive(&points, &polygons, l, &mut hits);
                black_box(&hits);
            }
        });
    });
    g.finish();
}

fn sampling(c: &mut Criterion) {
    let sphere = BoundingSphere::of_bounds(DVec3::ZERO, DVec3::ONE);
    let circle = BoundingCircle::of_bounds(DVec2::ZERO, DVec2::ONE);
    let mut g = c.benchmark_group("global line sampling");
    g.throughput(Throughput::Elements(BATCH as u64));
    g.bench_function("3D (4 canonical samples)", |b| {
        let mut rng = chunk_rng(2, 0);
        b.iter(|| {
            for _ in 0..BATCH {
                let u = [(); 4].map(|()| canonical(&mut rng));
                black_box(Line3::global(&sphere, u));
            }
        });
    });
    g.bench_function("2D (2 canonical samples)", |b| {
        let mut rng = chunk_rng(2, 0);
        b.iter(|| {
            for _ in 0..BATCH {
                black_box(Line2::global(
                    &circle,
                    [canonical(&mut rng), canonical(&mut rng)],
                ));
            }
        });
    });
    g.finish();
}

/// Whole chunks: sampling, queries and the full tally, against the naive tracer.
fn chunks(c: &mut Criterion) {
    let lines = BATCH as u64;
    let mut g = c.benchmark_group("global-line chunk with tally");
    g.throughput(Throughput::Elements(lines));
    let flat = Scene2::catalogue("64-squares-a", 10).unwrap();
    // One tally per tracer, reused: a long job allocates its tallies once.
    let tracer = Tracer2::new(&flat).unwrap();
    let mut tally = tracer.new_tally(LineMethod::Global);
    g.bench_function("64 squares, bvh", |b| {
        b.iter(|| {
            tracer.trace_chunk(3, lines, 0, &mut tally);
            black_box(tally.lines())
        });
    });
    // A chunk of BATCH lines is a sheaf of 16 bundles (a whole sheaf has 65,536 lines),
    // π/16 apart, each re-sorting much of the segments' depth order, the pairs drained
    // once at its end: slower per line than a long job.
    let mut tally = tracer.new_tally(LineMethod::Bundle);
    g.bench_function("64 squares, bundles", |b| {
        b.iter(|| {
            tracer.trace_chunk(3, lines, 0, &mut tally);
            black_box(tally.lines())
        });
    });
    let naive = Tracer2::new(&flat).unwrap().naive_baseline();
    let mut tally = naive.new_tally(LineMethod::Global);
    g.bench_function("64 squares, naive", |b| {
        b.iter(|| {
            naive.trace_chunk(3, lines, 0, &mut tally);
            black_box(tally.lines())
        });
    });
    let cube = Scene3::cube(30).unwrap();
    let tracer = Tracer3::new(&cube).unwrap();
    let mut tally = tracer.new_tally(LineMethod::Global);
    g.bench_function("cube 5400, bvh", |b| {
        b.iter(|| {
            tracer.trace_chunk(3, lines, 0, &mut tally);
            black_box(tally.lines())
        });
    });
    g.finish();
}

fn exact(c: &mut Criterion) {
    let cube = Scene3::cube(10).unwrap();
    let polygons: Vec<(usize, usize)> = cube.patches().iter().map(|p| (p.first, p.count)).collect();
    let mut g = c.benchmark_group("exact form factors");
    g.sample_size(10);
    g.bench_function("3D cube 600", |b| {
        b.iter(|| black_box(exact_3d::form_factors_unoccluded(cube.points(), &polygons).unwrap()));
    });
    let flat = Scene2::catalogue("16-squares-4", 52).unwrap();
    g.bench_function("flatland 16-squares-4 (605)", |b| {
        b.iter(|| black_box(sceneinfo::formfactor::exact_2d::form_factors(&flat).unwrap()));
    });
    g.finish();
}

criterion_group!(benches, queries_2d, queries_3d, sampling, chunks, exact);
criterion_main!(benches);
