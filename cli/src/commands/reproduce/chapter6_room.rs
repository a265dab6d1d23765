//! The cube room of Figures 6.7/6.8, 6.10 and 6.11 (issue 22) by the thesis' protocol:
//! `scenes/cube_room.obj` (a room with a table and four chairs; what is invented:
//! docs/chapter6-protocol.md), hierarchical Monte Carlo radiosity at the captions' rays and
//! patch counts times `--cube-room-scale`, each oracle over `--cube-room-seeds` seeds,
//! against a Monte Carlo reference on a regular fine mesh (`McHierarchy::reference`; the deterministic
//! reference of the Cornell box is far too slow here), with the image errors from the two
//! views of Figs. 6.7 and 6.8.

use anyhow::{Result, anyhow, bail};
use sceneinfo::geom::DVec3;
use sceneinfo::hierarchy::{McComparison, McHierarchy, McReference};
use sceneinfo::image::Camera3;
use sceneinfo::io::{ObjOptions, parse_obj};
use sceneinfo::scene::{Scene3, Subdivision};

use super::chapter6_mc::{Config, rows, run_configs, write_panels};
use super::{Row, Runner, Table, cell};
use crate::args::ReproduceArgs;

/// The scene and its materials, compiled in (so `reproduce` runs from anywhere).
const ROOM_OBJ: &str = include_str!("../../../../scenes/cube_room.obj");
const ROOM_MTL: &str = include_str!("../../../../scenes/cube_room.mtl");

/// The two views, in the scene's metres: Fig. 6.7 from the front-left corner towards the
/// right wall (the chair near it and its shadow), Fig. 6.8 from the back-right corner
/// towards the front wall (the chair near it, the table).
const VIEWS: [([f64; 3], [f64; 3]); 2] = [
    ([0.35, 2.7, 0.3], [2.9, 0.7, 2.6]),
    ([3.65, 2.7, 3.7], [1.3, 0.7, 0.9]),
];
/// Vertical field of view of both views, degrees.
const FOV: f64 = 70.0;
/// Pixels of the pictures the image errors are measured on.
const IMAGE: (u32, u32) = (160, 120);
/// Pixels of each panel of the written pictures.
const PANEL: (u32, u32) = (320, 240);
/// The thesis' captions: leaves (the mean of the two meshes' counts) and radiosity rays.
const FIG_6_7: (f64, f64) = (13_890.0, 402_650.0);
const FIG_6_10: (f64, f64) = (13_724.0, 402_565.0);
const FIG_6_11: (f64, f64) = (18_338.0, 2_684_260.0);
/// The reference: at least this many leaves, and 3 times the largest mesh compared.
const MIN_REFERENCE_LEAVES: f64 = 20_000.0;
/// The reference's rays: to make its regular mesh, and to solve it, per leaf.
const REFERENCE_MESH_RAYS_PER_LEAF: f64 = 10.0;
const REFERENCE_RAYS_PER_LEAF: f64 = 200.0;
/// Seed offset of the reference's frozen solves (as `McHierarchy::reference`'s).
const FROZEN_SEED: u64 = 0x6672_6f7a;
/// Rays of each mesh's frozen re-solve, per radiosity ray of its run.
const FROZEN_PER_RAY: u64 = 10;
/// Distance (metres) from a surface in another plane within which a leaf counts as lying
/// along a junction (`McHierarchy::share_near_junctions`).
const JUNCTION: f64 = 0.1;

fn err(e: sceneinfo::Error) -> anyhow::Error {
    anyhow!("cube room: {e}")
}

/// The cube room as a scene.
pub(super) fn scene() -> Result<Scene3> {
    let (scene, _) = parse_obj(ROOM_OBJ, &ObjOptions::new(Subdivision::None), |name| {
        (name == "cube_room.mtl").then(|| ROOM_MTL.to_string())
    })
    .map_err(|e| anyhow!("scenes/cube_room.obj: {e}"))?;
    Ok(scene)
}

/// The views of Figs. 6.7 and 6.8 at `size`.
fn views(scene: &Scene3, size: (u32, u32)) -> sceneinfo::Result<Vec<Camera3>> {
    VIEWS
        .iter()
        .map(|(eye, look)| {
            Camera3::in_scene_units(
                scene,
                DVec3::from_array(*eye),
                DVec3::from_array(*look),
                FOV,
                size,
            )
        })
        .collect()
}

/// The section.
pub(super) fn cube_room(runner: &Runner, args: &ReproduceArgs) -> Result<Table> {
    let s = args.cube_room_scale;
    if !(s > 0.0 && s <= 1.0) {
        bail!("--cube-room-scale must lie in (0, 1] (got {s})");
    }
    let seeds = args.cube_room_seeds.clamp(1, 20);
    let scene = scene()?;
    let at =
        |(leaves, rays): (f64, f64)| ((leaves * s).round() as usize, (rays * s).round() as u64);
    let configs = [
        Config {
            label: "6.7/6.8",
            leaves: at(FIG_6_7).0,
            rays: at(FIG_6_7).1,
            pairs: 10,
            oracles: &["power", "ks-av", "mi"],
            total_rays: true,
        },
        Config {
            label: "6.10",
            leaves: at(FIG_6_10).0,
            rays: at(FIG_6_10).1,
            pairs: 4,
            oracles: &["ks-av", "mi"],
            total_rays: false,
        },
        Config {
            label: "6.11",
            leaves: at(FIG_6_11).0,
            rays: at(FIG_6_11).1,
            pairs: 10,
            oracles: &["power", "mi"],
            total_rays: false,
        },
    ];
    // The reference: one regular mesh, re-solved frozen by two seeds, averaged; each
    // solve against the mean measures the mean's noise (docs/chapter6-protocol.md)
    let n_ref = MIN_REFERENCE_LEAVES.max(3.0 * FIG_6_11.0 * s);
    let min_area = 1.0 / (2.0 * n_ref);
    let mesh = McHierarchy::reference_mesh(
        &scene,
        min_area,
        (REFERENCE_MESH_RAYS_PER_LEAF * n_ref) as u64,
        runner.seed,
    )
    .map_err(err)?;
    let halves = super::chapter6_mc::run_jobs(
        runner,
        &[
            runner.seed ^ FROZEN_SEED,
            runner.seed ^ 0x5eed ^ FROZEN_SEED,
        ],
        |&seed| mesh.resolve_frozen(&scene, (REFERENCE_RAYS_PER_LEAF * n_ref) as u64, seed),
    )?;
    let [first, second] = <[McHierarchy; 2]>::try_from(halves)
        .map_err(|_| anyhow!("the two reference solves did not run"))?;
    let reference = first.mean_with(&second).map_err(err)?;
    let leaves = reference.shaded_leaves();
    let mc_ref = McReference::new(&scene, &leaves, &views(&scene, IMAGE).map_err(err)?)
        .map_err(err)?
        .with_halves(&scene, &[&first, &second])
        .map_err(err)?;
    let noise = mc_ref.noise(&scene, &[&first, &second]).map_err(err)?;
    crate::interrupt::stop_if_requested()?;
    let out = run_configs(
        runner,
        &scene,
        &mc_ref,
        &configs,
        seeds,
        |c| FROZEN_PER_RAY * c.rays,
        Some(JUNCTION),
    )?;
    // What the reference's noise leaves in the corrected RMS, over every run
    let residual: Vec<f64> = out
        .all()
        .filter_map(|c| c.reference_error(&noise))
        .collect();
    let residual_max = residual.iter().copied().fold(0.0, f64::max);
    let residual_mean = McComparison::mean_spread(&residual).0;
    // The same for the other measures (`McComparison::reference_errors`' order)
    let others: Vec<Vec<Option<f64>>> = out.all().map(|c| c.reference_errors(&noise)).collect();
    let other_rows: Vec<Row> = [
        "mesh RMS",
        "boundary RMS",
        "image RMSE",
        "image edges",
        "image 2 RMSE",
        "image 2 edges",
    ]
    .iter()
    .enumerate()
    .filter_map(|(m, name)| {
        let r: Vec<f64> = others
            .iter()
            .filter_map(|e| e.get(m).copied().flatten())
            .collect();
        (!r.is_empty()).then(|| Row {
            label: format!("reference: its noise left in a corrected {name}"),
            cells: vec![
                cell("mean", McComparison::mean_spread(&r).0, 0.0, None),
                cell("max", r.iter().copied().fold(0.0, f64::max), 0.0, None),
            ],
        })
    })
    .collect();
    let mut out = out;
    out.without_reference_noise(&noise);
    let mut noise_cells = vec![
        cell("RMS", noise.rms, 0.0, None),
        cell("boundary RMS", noise.boundary_rms, 0.0, None),
    ];
    for (v, names) in [
        ("image RMSE", "image edge RMSE"),
        ("image RMSE 2", "image edge RMSE 2"),
    ]
    .iter()
    .enumerate()
    {
        if let Some(e) = noise.images.get(v) {
            noise_cells.push(cell(names.0, e.rmse, 0.0, None));
            noise_cells.push(cell(names.1, e.boundary_rmse, 0.0, None));
        }
    }
    let mut table_rows = vec![
        Row {
            label: format!(
                "reference, {} leaves, {} rays (mean of 2 solves): its noise, removed below",
                reference.n_leaves(),
                reference.rays()
            ),
            cells: noise_cells,
        },
        Row {
            label: "reference: what its noise leaves in a corrected RMS (over every run)".into(),
            cells: vec![
                cell("mean", residual_mean, 0.0, None),
                cell("max", residual_max, 0.0, None),
            ],
        },
    ];
    table_rows.extend(other_rows);
    table_rows.extend(rows(&configs, &out, 2));
    // Where each oracle's mesh puts its leaves: the share along junctions
    for (k, c) in configs.iter().enumerate() {
        for &o in c.oracles {
            let (m, sd) = McComparison::mean_spread(&out.near_junctions(k, o));
            table_rows.push(Row {
                label: format!(
                    "Fig. {} ({} pairs): {o}: near junctions ({JUNCTION} m)",
                    c.label, c.pairs
                ),
                cells: vec![cell("share", m, sd, None)],
            });
        }
    }
    // Fig. 6.11 against 6.7: MI's more accurate solution
    let mi_rms = |k: usize| {
        let v: Vec<f64> = out.pick(k, "mi").iter().map(|r| r.rms_error).collect();
        McComparison::mean_spread(&v).0
    };
    table_rows.push(Row {
        label: "6.11 vs 6.7 RMS: MI at 6.11's budget over MI at 6.7's".into(),
        cells: vec![cell("ratio", mi_rms(2) / mi_rms(0), 0.0, None)],
    });
    if let Some(dir) = &args.figures {
        let panels = views(&scene, PANEL).map_err(err)?;
        let tone = mc_ref.images[0].tone;
        for (k, v, file) in [
            (0, 0, "ch6mc_fig67.png"),
            (0, 1, "ch6mc_fig68.png"),
            (1, 0, "ch6mc_fig610.png"),
            (2, 0, "ch6mc_fig611.png"),
        ] {
            let mut meshes: Vec<&McHierarchy> = configs[k]
                .oracles
                .iter()
                .filter_map(|o| out.mesh(k, o))
                .collect();
            if k == 0 {
                meshes.push(&reference);
            }
            write_panels(&dir.join(file), &scene, &meshes, &panels[v], &tone)?;
        }
    }
    Ok(Table {
        key: "figures_6_7_6_11_cube_room",
        title: format!(
            "Figs. 6.7/6.8, 6.10, 6.11 by the thesis' protocol: the cube room \
             (scenes/cube_room.obj, {} patches), hierarchical Monte Carlo radiosity at {s} \
             times the captions' leaves and rays ({seeds} seeds, ± = standard deviation over \
             seeds); RMS against a Monte Carlo reference on a regular mesh, the mean of two \
             solves, its noise (first row) removed in quadrature from every error; mesh RMS: re-solved frozen with {FROZEN_PER_RAY}x the run's rays; \
             image RMSE (8-bit levels, {}x{} pixels): view 1 of Fig. 6.7, view 2 of Fig. 6.8",
            scene.n_patches(),
            IMAGE.0,
            IMAGE.1
        ),
        rows: table_rows,
    })
}
