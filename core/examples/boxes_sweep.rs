//! How honest the occluded exact path's error estimates are, over random rooms: a room
//! `[0, 4]³` (inward faces) with two random boxes (as in the property test
//! `random_boxes_in_a_room_honour_their_estimates`), its form factors at tolerance `TOL`
//! against a reference at `REF`; an entry counts as outside its estimate when
//! `|F − F_ref| − e_ref > e`, with `e`, `e_ref` the two runs' estimates.
//!
//! ```text
//! cargo run --release -p sceneinfo --example boxes_sweep -- N SEED TOL REF
//! ```
//!
//! prints each room with an entry outside (the worst ratio `(|F − F_ref| − e_ref) / e`, the
//! entry, the boxes), then how many of the `N` rooms had one and the points the `TOL` runs
//! evaluated. `SWEEP_POINTS=1` also prints every room's points.
use sceneinfo::formfactor::occluded_3d::{OcclusionOptions, scene_form_factors_occluded};
use sceneinfo::io::{ObjOptions, parse_obj};
use std::fmt::Write as _;
fn box_obj(lo: [f64; 3], hi: [f64; 3], inwards: bool, first: usize, out: &mut String) {
    for i in 0..8 {
        let c = |a: usize| if i >> a & 1 == 0 { lo[a] } else { hi[a] };
        writeln!(out, "v {} {} {}", c(0), c(1), c(2)).unwrap();
    }
    for f in [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ] {
        let mut f = f.map(|k| k + first + 1);
        if inwards {
            f.reverse();
        }
        writeln!(out, "f {} {} {} {}", f[0], f[1], f[2], f[3]).unwrap();
    }
}
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().collect();
    if a.len() != 5 {
        return Err("usage: boxes_sweep N SEED TOL REF (e.g. 60 3 1e-3 1e-5)".into());
    }
    let (n, seed, tol, rtol): (u64, u64, f64, f64) =
        (a[1].parse()?, a[2].parse()?, a[3].parse()?, a[4].parse()?);
    let mut s = seed.wrapping_mul(0x9E3779B97F4A7C15) | 1;
    let mut u = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut bad, mut worst, mut pts) = (0, 0.0f64, 0u64);
    for case in 0..n {
        let mut obj = String::new();
        box_obj([0.0; 3], [4.0; 3], true, 0, &mut obj);
        let mut desc = String::new();
        for k in 0..2 {
            let lo = [0.2 + 2.8 * u(), 3.0 * u(), 0.2 + 2.8 * u()];
            let sz = [0.3 + 0.7 * u(), 0.3 + 0.7 * u(), 0.3 + 0.7 * u()];
            let hi = [lo[0] + sz[0], lo[1] + sz[1], lo[2] + sz[2]];
            write!(desc, "({:?},{:?}),", lo, sz).unwrap();
            box_obj(lo, hi, false, 8 * (k + 1), &mut obj);
        }
        let scene = parse_obj(&obj, &ObjOptions::default(), |_| None)?.0;
        let np = scene.n_patches();
        let c = scene_form_factors_occluded(&scene, &OcclusionOptions::new(tol))?;
        let r = scene_form_factors_occluded(&scene, &OcclusionOptions::new(rtol))?;
        pts += c.points;
        if std::env::var_os("SWEEP_POINTS").is_some() {
            println!("case {case}: {} points, boxes [{desc}]", c.points);
        }
        let mut case_worst = 0.0f64;
        let mut at = (0, 0);
        for i in 0..np {
            for j in 0..np {
                let d = (c.form_factors.get(i, j) - r.form_factors.get(i, j)).abs()
                    - r.errors[i * np + j];
                let ratio = d / c.errors[i * np + j].max(1e-300);
                if d > 0.0 && ratio > case_worst {
                    case_worst = ratio;
                    at = (i, j);
                }
            }
        }
        worst = worst.max(case_worst);
        if case_worst > 1.0 {
            bad += 1;
            println!("case {case}: worst {case_worst:.2} at {at:?} boxes [{desc}]");
        }
    }
    println!(
        "{bad} of {n} cases with an entry outside its estimate; worst ratio {worst:.2}; points {pts}"
    );
    Ok(())
}
