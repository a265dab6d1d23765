//! MI-based mesh simplification (issue 20, item 3; `docs/simplify.md`): every merge loses
//! exactly the `I_S` it reports, a merge undone by a split gives the `I_S` back, and at equal
//! patch count the MI-simplified mesh keeps at least the `I_S` of regular coarsening on the
//! scenes below (flatland with and without occluders, a lit room, 3D enclosures).

use sceneinfo::channel::Channel;
use sceneinfo::formfactor::{FormFactors, exact_2d, exact_3d};
use sceneinfo::io::{ObjOptions, parse_flat, parse_obj};
use sceneinfo::refine::proposition::{StateSplit, split_gain};
use sceneinfo::scene::{Scene2, Scene3, Subdivision};
use sceneinfo::simplify::adjacency::{adjacency_2d, adjacency_3d, coarse_scene_2d};
use sceneinfo::simplify::{
    MergeChain, MergeCriterion, Simplifier, compare_criteria, polish::Polished,
};

/// Tolerance of the issue: a merge's loss against the recomputed `I_S` difference. Both
/// are sums of `O(n²)` terms of a few bits at most, in `f64` with compensated sums.
const LOSS_TOLERANCE: f64 = 1e-12;

fn lit_room() -> Scene2 {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/lit-room.flat"
    ))
    .unwrap();
    parse_flat(&text).unwrap()
}

/// The flatland scenes of these tests: rooms without and with occluders, and the lit room.
fn flat_scenes() -> Vec<(String, Scene2)> {
    let mut scenes: Vec<(String, Scene2)> = [
        ("l-room-0", 8),
        ("l-room-2", 8),
        ("triangle-3", 10),
        ("star-2", 4),
        ("three-objects-2", 8),
        ("pentagonal-star-3", 6),
    ]
    .into_iter()
    .map(|(name, k)| {
        (
            format!("{name} ({k} per side)"),
            Scene2::catalogue(name, k).unwrap(),
        )
    })
    .collect();
    scenes.push(("scenes/lit-room.flat".into(), lit_room()));
    scenes
}

fn chain_of(ff: &FormFactors) -> MergeChain {
    MergeChain::new(ff.weights(), &ff.matrix()).unwrap()
}

fn i_s_of(scene: &Scene2) -> f64 {
    exact_2d::form_factors(scene)
        .unwrap()
        .channel()
        .unwrap()
        .i_s()
}

#[test]
fn every_merge_loses_exactly_the_recomputed_i_s_difference() {
    for (name, scene) in flat_scenes() {
        let ff = exact_2d::form_factors(&scene).unwrap();
        let n = scene.n_patches();
        let pairs = adjacency_2d(&scene);
        let mut s =
            Simplifier::new(chain_of(&ff), n, &pairs, MergeCriterion::Information, None).unwrap();
        let mut before = s.chain().i_s().unwrap();
        // The chain's I_S is the channel's, to rounding (the joint made exactly symmetric).
        assert!((before - ff.channel().unwrap().i_s()).abs() < LOSS_TOLERANCE);
        let mut worst = 0.0f64;
        while s.n_patches() > n / 4 {
            let Some(step) = s.step().unwrap() else { break };
            let after = s.chain().i_s().unwrap();
            let gap = (before - after - step.loss).abs();
            worst = worst.max(gap);
            assert!(gap <= LOSS_TOLERANCE, "{name} step {}: {gap:e}", step.step);
            assert!((step.i_s - after).abs() <= LOSS_TOLERANCE, "{name}");
            assert!(step.loss >= 0.0 && step.i_s <= before + LOSS_TOLERANCE);
            before = after;
        }
        // The coarse mesh as geometry: exact form factors of the merged patches give the
        // same I_S as the merged chain (additivity of form factors).
        let coarse = coarse_scene_2d(&scene, s.chain().clusters()).unwrap();
        assert_eq!(coarse.n_patches(), s.n_patches(), "{name}");
        let geometric = i_s_of(&coarse);
        assert!(
            (geometric - s.i_s()).abs() <= 1e-9,
            "{name}: coarse scene {geometric} vs merged chain {}",
            s.i_s()
        );
        println!(
            "{name}: {} → {} patches, worst |ΔI_S − loss| {worst:.1e}, coarse-scene I_S off by {:.1e}",
            n,
            s.n_patches(),
            (geometric - s.i_s()).abs()
        );
    }
}

#[test]
fn merging_then_splitting_back_restores_i_s() {
    for (name, scene) in flat_scenes() {
        let ff = exact_2d::form_factors(&scene).unwrap();
        let n = scene.n_patches();
        let pairs = adjacency_2d(&scene);
        let fine = chain_of(&ff);
        let start = fine.i_s().unwrap();
        let mut s = Simplifier::new(fine, n, &pairs, MergeCriterion::Information, None).unwrap();
        let step = s.step().unwrap().unwrap();
        // The chain: the split of the merged state back into the two patches, by
        // Proposition 3 (split_gain, conditions checked), gains the loss back.
        let (states, w, f) = s.chain().coarse_form_factors();
        let m = states.len();
        let channel = Channel::from_dense(&w, &f).unwrap();
        let c = states.iter().position(|&x| x == step.kept).unwrap();
        let fine_chain = chain_of(&ff);
        let (a, b) = (step.kept, step.absorbed);
        let weights = [fine_chain.weight(a), fine_chain.weight(b)];
        let mut rows = vec![0.0; 2 * m];
        let mut columns = vec![0.0; 2 * m];
        for (k, &x) in [a, b].iter().enumerate() {
            for (r, &y) in states.iter().enumerate() {
                if r == c {
                    continue;
                }
                let p = fine_chain.joint_row(x)[y];
                rows[k * m + r] = p / weights[k];
                columns[k * m + r] = p / w[r];
            }
        }
        let block: Vec<f64> = [(0, 0), (0, 1), (1, 0), (1, 1)]
            .iter()
            .map(|&(k, l)| fine_chain.joint_row([a, b][k])[[a, b][l]] / weights[k])
            .collect();
        let split = StateSplit {
            state: c,
            weights: &weights,
            rows: &rows,
            columns: &columns,
            block: &block,
        };
        let gain = split_gain(&channel, &split).unwrap();
        assert!((gain - step.loss).abs() <= LOSS_TOLERANCE, "{name}");
        assert!(
            (channel.i_s() + gain - start).abs() <= LOSS_TOLERANCE,
            "{name}"
        );
        // The geometry: the coarse scene with the merged patch cut back where it was.
        let coarse = coarse_scene_2d(&scene, s.chain().clusters()).unwrap();
        let patch = &scene.patches()[a];
        let surface = &coarse.surfaces()[patch.surface];
        let local_fine = a - scene.surfaces()[patch.surface].patches.start;
        let cut = scene.surfaces()[patch.surface].cuts[local_fine];
        let k = surface.cuts.partition_point(|&t| t < cut);
        let t0 = if k == 0 { 0.0 } else { surface.cuts[k - 1] };
        let t1 = surface.cuts.get(k).copied().unwrap_or(1.0);
        let resplit = coarse
            .split_patch(surface.patches.start + k, (cut - t0) / (t1 - t0))
            .unwrap();
        assert_eq!(resplit.n_patches(), n);
        let back = i_s_of(&resplit);
        assert!(
            (back - start).abs() <= 1e-9,
            "{name}: split back {back} vs {start}"
        );
    }
}

/// A mesh nobody on the project wrote: tinyobjloader's
/// `models/issue-295-trianguation-failure.obj` (tests/data/corpus/SOURCES.md, MIT), a closed
/// 1 × 1 × 3 box of 14 unit quads at coordinates near 10⁴. Its quads face outwards (no
/// patch sees another), so each is turned to face inwards (vertex order reversed), making
/// the box an enclosure, and cut `grid × grid`.
fn corpus_box(grid: u32) -> Scene3 {
    let text = include_str!("data/corpus/obj/tinyobjloader/issue-295-trianguation-failure.obj");
    let options = ObjOptions::new(Subdivision::Grid(1));
    let outward = parse_obj(text, &options, |_| None).unwrap().0;
    assert_eq!(outward.faces().len(), 14);
    let mut builder = Scene3::builder();
    for f in 0..outward.faces().len() {
        let mut v = outward.face_vertices(f).to_vec();
        v.reverse();
        builder.polygon(&v, Subdivision::Grid(grid)).unwrap();
    }
    builder.build().unwrap()
}

/// The 3D scenes: enclosures with exact unoccluded form factors.
fn solid_scenes() -> Vec<(String, Scene3)> {
    vec![
        ("corpus box (issue-295), grid 2".into(), corpus_box(2)),
        ("corpus box (issue-295), grid 3".into(), corpus_box(3)),
        ("cube, grid 4".into(), Scene3::cube(4).unwrap()),
        (
            "tetrahedron, grid 6".into(),
            Scene3::tetrahedron()
                .unwrap()
                .subdivided(Subdivision::Grid(6))
                .unwrap(),
        ),
        (
            "octahedron, grid 3".into(),
            Scene3::preset("octahedron", 1)
                .unwrap()
                .subdivided(Subdivision::Grid(3))
                .unwrap(),
        ),
    ]
}

/// The property of the issue, tried over scenes and patch counts: at equal count the
/// MI mesh keeps at least the `I_S` of regular coarsening. Every scene and count is tried
/// and every failure listed before the test fails; each row is printed (`--nocapture`).
///
/// The mi row is `Polished::of` (`simplify::polish`): the greedy merge and a top-down split
/// of the whole surfaces, each polished by boundary moves, per-surface dynamic programming,
/// exact re-splits of two adjacent clusters and transfers (only changes that raise `I_S`),
/// the better kept. Neither start nor any move looks at regular coarsening. Before the
/// exact re-split and the top-down start, 2 cases failed (star-2 at 48: every side cut
/// 1 + 3, 2.955517 against 2.969771 bits; the cube grid 4 at 12: staircase cuts, 0.454479
/// against 0.464811); the greedy alone failed 7. Both now reach regular's value exactly
/// (from the top-down start), and MI is above regular in most other cases.
///
/// 12 scenes (six flatland rooms, the lit room, a corpus box at two grids, a cube,
/// tetrahedron and octahedron cut into grids) at `n/2`, `n/4`, `n/8`: 36 rows; a few
/// seconds in the test profile.
#[test]
fn mi_simplification_keeps_at_least_the_i_s_of_regular_coarsening() {
    let mut failures = Vec::new();
    let mut rows = Vec::new();
    let mut check = |name: &str,
                     ff: &FormFactors,
                     n: usize,
                     pairs: &[(usize, usize)],
                     materials: &[sceneinfo::scene::Material]| {
        let fine = chain_of(ff);
        for target in [n / 2, n / 4, n / 8] {
            let c = compare_criteria(&fine, n, pairs, materials, target).unwrap();
            let (mi, regular, power) = (&c.outcomes[0], &c.outcomes[1], &c.outcomes[2]);
            assert_eq!(mi.n_patches, regular.n_patches, "{name}: equal counts");
            rows.push(format!(
                "{name:>30} {n:>4} → {:>4}: I_S mi {:.6} regular {:.6} bits (kept {:.4} / {:.4}, power {:.4}){}",
                mi.n_patches,
                mi.i_s,
                regular.i_s,
                mi.kept,
                regular.kept,
                power.kept,
                if c.polished.top_down { ", top-down start" } else { "" }
            ));
            if mi.i_s < regular.i_s - LOSS_TOLERANCE {
                failures.push(format!(
                    "{name} at {} patches: mi {} < regular {}",
                    mi.n_patches, mi.i_s, regular.i_s
                ));
            }
        }
    };
    for (name, scene) in flat_scenes() {
        let ff = exact_2d::form_factors(&scene).unwrap();
        check(
            &name,
            &ff,
            scene.n_patches(),
            &adjacency_2d(&scene),
            &scene.patch_materials(),
        );
    }
    for (name, scene) in solid_scenes() {
        let ff = exact_3d::scene_form_factors(&scene).unwrap();
        check(
            &name,
            &ff,
            scene.n_patches(),
            &adjacency_3d(&scene),
            &scene.patch_materials(),
        );
    }
    for row in &rows {
        println!("{row}");
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// A 3D scene cut into triangles: adjacency crosses the diagonal of each quad (two
/// triangles of one face plane), and merges still lose what `I_S` loses.
#[test]
fn triangulated_faces_merge_across_their_diagonals() {
    let scene = Scene3::cube(1)
        .unwrap()
        .subdivided(Subdivision::Triangles(1))
        .unwrap();
    let pairs = adjacency_3d(&scene);
    assert!(!pairs.is_empty());
    let ff = exact_3d::scene_form_factors(&scene).unwrap();
    let n = scene.n_patches();
    let mut s =
        Simplifier::new(chain_of(&ff), n, &pairs, MergeCriterion::Information, None).unwrap();
    let mut before = s.i_s();
    while let Some(step) = s.step().unwrap() {
        let after = s.chain().i_s().unwrap();
        assert!((before - after - step.loss).abs() <= LOSS_TOLERANCE);
        before = after;
    }
    // Everything of one face plane merged: the six faces are left.
    assert_eq!(s.n_patches(), 6);
    let faces = Scene3::cube(1).unwrap();
    let whole = exact_3d::scene_form_factors(&faces)
        .unwrap()
        .channel()
        .unwrap()
        .i_s();
    assert!((s.i_s() - whole).abs() <= 1e-9, "{} vs {whole}", s.i_s());
}

/// The polish (`simplify::polish`) after the greedy merge: at the same patch count it never
/// keeps less `I_S` than the greedy mesh, and the polished mesh as geometry (the coarse
/// `.flat` scene of its clusters) has exactly the `I_S` it reports — its clusters are runs
/// of one surface, so every merge it implies is a merge of adjacent patches.
#[test]
fn polishing_never_loses_and_the_polished_scene_measures_what_it_reports() {
    for (name, scene) in flat_scenes() {
        let ff = exact_2d::form_factors(&scene).unwrap();
        let n = scene.n_patches();
        let pairs = adjacency_2d(&scene);
        let fine = chain_of(&ff);
        for target in [n / 2, n / 4] {
            let mut s = Simplifier::new(fine.clone(), n, &pairs, MergeCriterion::Information, None)
                .unwrap();
            s.run(target, None).unwrap();
            let p = Polished::of(&fine, n, &pairs, s.chain().clusters()).unwrap();
            assert!((p.start_i_s - s.i_s()).abs() <= LOSS_TOLERANCE, "{name}");
            assert!(p.i_s >= p.start_i_s, "{name} at {target}");
            assert_eq!(p.chain.live_states().len(), s.chain().live_states().len());
            let coarse = coarse_scene_2d(&scene, p.chain.clusters()).unwrap();
            assert_eq!(coarse.n_patches(), s.n_patches(), "{name}");
            let geometric = i_s_of(&coarse);
            assert!(
                (geometric - p.i_s).abs() <= 1e-9,
                "{name}: polished scene {geometric} vs {}",
                p.i_s
            );
            println!(
                "{name} at {target}: greedy {:.6} → polished {:.6} bits ({} moves, {} transfers)",
                p.start_i_s, p.i_s, p.moves, p.transfers
            );
        }
    }
}
