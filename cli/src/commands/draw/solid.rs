//! `sceneinfo draw FILE.obj --ply OUT.ply`: a 3D scene as an ASCII PLY mesh, each patch a
//! polygon of one colour given by a per-patch measure (I_i, H_i, I_i^c or I_i^c − I_i).
//!
//! Every measure comes from the core; this module picks the form factors' source, the values
//! and their colours (the same maps as the flatland SVG, [`crate::picture`]).

use std::path::Path;

use anyhow::{Result, bail};
use sceneinfo::formfactor::FormFactors;
use sceneinfo::formfactor::exact_3d;
use sceneinfo::scene::Scene3;
use sceneinfo::trace::estimate_2d::LineMethod;
use sceneinfo::trace::estimate_3d::Tracer3;

use super::{PatchMeasure, Source, patch_values};
use crate::args::{Colour, DrawArgs};
use crate::output::{Loaded, located, write_atomic};
use crate::picture::{patch_colours, range};
use crate::ply::Ply;
use crate::svg::{ColourMap, number};

/// Lines cast for `ic` and `delta`, and for `i` and `h` when exact form factors are out of
/// reach, when `--lines` is not given.
const DEFAULT_LINES: u64 = 1_000_000;
/// Up to this many patches, exact form factors are tried (when no patch may hide another);
/// above it, Monte Carlo (the exact double contour integrals take seconds at 2000 patches).
const EXACT_LIMIT: usize = 2000;

/// The validated command.
#[derive(Debug)]
struct Config {
    colour: Colour,
    per_area: bool,
    /// Lines of the Monte Carlo run, if there is one.
    lines: Option<u64>,
    /// Where the discrete form factors come from, if they are needed (not for `ic`).
    discrete: Option<Source>,
    seed: u64,
    threads: usize,
}

impl Config {
    /// `exact_possible` is asked only when exact form factors would be used: whether the
    /// scene is small enough and no patch may hide another.
    fn new(args: &DrawArgs, threads: usize, exact_possible: impl FnOnce() -> bool) -> Result<Self> {
        if let Some(n) = args.lines {
            sceneinfo::LineJob::check_lines(n)?;
        }
        if args.per_area && args.color == Colour::H {
            bail!(
                "--per-area divides a patch's share of I_S or I_S^c by its relative area; \
                 H_i (3.2) is a row entropy, not a share: drop --per-area or pick i, ic or delta"
            );
        }
        let (lines, discrete) = match (args.color, args.lines) {
            (Colour::Ic, n) => (Some(n.unwrap_or(DEFAULT_LINES)), None),
            (Colour::I | Colour::H, Some(n)) => (Some(n), Some(Source::MonteCarlo)),
            (Colour::I | Colour::H, None) => {
                if exact_possible() {
                    (None, Some(Source::Exact))
                } else {
                    (Some(DEFAULT_LINES), Some(Source::MonteCarlo))
                }
            }
            (Colour::Delta, n) => {
                let source = if exact_possible() {
                    Source::Exact
                } else {
                    Source::MonteCarlo
                };
                (Some(n.unwrap_or(DEFAULT_LINES)), Some(source))
            }
        };
        Ok(Self {
            colour: args.color,
            per_area: args.per_area,
            lines,
            discrete,
            seed: args.seed,
            threads,
        })
    }
}

/// Whether exact form factors can be computed for `scene`: at most [`EXACT_LIMIT`] patches
/// and no pair that may be occluded.
fn exact_possible(scene: &Scene3) -> bool {
    if scene.n_patches() > EXACT_LIMIT {
        return false;
    }
    let polygons: Vec<(usize, usize)> =
        scene.patches().iter().map(|p| (p.first, p.count)).collect();
    !exact_3d::may_be_occluded(scene.points(), &polygons)
}

/// What a run computed.
#[derive(Debug)]
struct Computed {
    /// One value per patch (the background state, if any, left out).
    values: Vec<f64>,
    /// Header comments on where the numbers come from.
    notes: Vec<String>,
}

pub fn run(args: &DrawArgs, threads: usize) -> Result<()> {
    let Some(ply_path) = &args.ply else {
        bail!(
            "{}: a .obj scene is written as a coloured PLY mesh: give --ply OUT.ply",
            args.file.display()
        );
    };
    if args.svg.is_some() || args.matrix_svg.is_some() {
        bail!(
            "{}: --svg and --matrix-svg draw .flat scenes; for a .obj scene use --ply OUT.ply",
            args.file.display()
        );
    }
    let loaded = crate::output::load_scene(&args.file)?;
    // Pictures of visibility: the material warnings are not theirs
    loaded.print_warnings(&args.file, false);
    let Loaded::Solid(scene) = loaded.scene else {
        bail!("{}: not a 3D scene", args.file.display());
    };
    let config = Config::new(args, threads, || exact_possible(&scene))?;
    let computed = compute(&args.file, &scene, &config);
    // After Ctrl-C the line job stopped early: write nothing
    crate::interrupt::stop_if_requested()?;
    let computed = computed?;
    let name = args.file.display().to_string();
    let (ply, (lo, hi)) = mesh(&scene, &computed, &config, &name);
    write_atomic(ply_path, ply.finish()?.as_bytes())?;
    println!(
        "{name}: {} patches, {} from {} to {} {} -> {}",
        scene.n_patches(),
        short_name(config.colour, config.per_area),
        number(lo),
        number(hi),
        units(config.per_area),
        ply_path.display()
    );
    Ok(())
}

/// Runs the Monte Carlo lines and the core measures the colouring needs.
fn compute(path: &Path, scene: &Scene3, config: &Config) -> Result<Computed> {
    let at = |e: sceneinfo::Error| located(path, &e);
    let n = scene.n_patches();
    let mut notes = Vec::new();
    let estimate = match config.lines {
        None => None,
        Some(lines) => {
            let tracer = Tracer3::new(scene).map_err(at)?;
            let tally = crate::lines::run(
                &tracer,
                LineMethod::Global,
                config.seed,
                lines,
                config.threads,
            );
            notes.push(format!(
                "Monte Carlo: {lines} global lines, seed {}",
                config.seed
            ));
            Some(tally.finish(&tracer).map_err(at)?)
        }
    };
    let (ff, continuous): (Option<FormFactors>, Option<Vec<f64>>) =
        match (config.discrete, estimate) {
            (Some(Source::MonteCarlo), Some(est)) => {
                (Some(est.form_factors), Some(est.patch_continuous))
            }
            (Some(_), est) => (
                Some(crate::output::exact_3d_form_factors(path, scene)?),
                est.map(|e| e.patch_continuous),
            ),
            (None, est) => (None, est.map(|e| e.patch_continuous)),
        };
    match config.discrete {
        Some(Source::Exact) => notes.push(
            "form factors: exact (no patch can hide another; unoccluded double contour \
             integrals)"
                .to_owned(),
        ),
        Some(Source::MonteCarlo) => {
            notes.push("form factors: Monte Carlo, from the global lines of this run".to_owned());
        }
        None => {}
    }
    if ff.as_ref().is_some_and(FormFactors::has_background) {
        notes.push(
            "open scene: lines leaving the scene go to a background state; its row is ignored \
             (values over the patches only)"
                .to_owned(),
        );
    }
    let discrete = |measure| -> Result<Vec<f64>> {
        match &ff {
            Some(ff) => patch_values(ff, n, measure).map_err(at),
            None => Ok(Vec::new()),
        }
    };
    let mut continuous = continuous.unwrap_or_default();
    continuous.truncate(n);
    let mut values = match config.colour {
        Colour::I => discrete(PatchMeasure::Information)?,
        Colour::H => discrete(PatchMeasure::Entropy)?,
        Colour::Ic => continuous,
        Colour::Delta => {
            let i = discrete(PatchMeasure::Information)?;
            continuous.iter().zip(&i).map(|(c, d)| c - d).collect()
        }
    };
    if values.len() != n {
        bail!(
            "{}: {} values for {n} patches (internal error)",
            path.display(),
            values.len()
        );
    }
    if config.per_area {
        let mut a = vec![0.0; n];
        scene.relative_areas_into(&mut a).map_err(at)?;
        for (v, a) in values.iter_mut().zip(&a) {
            *v /= a;
        }
        notes.push(
            "per area: each value divided by the patch's relative area a_i = A_i / A_T".to_owned(),
        );
    }
    Ok(Computed { values, notes })
}

/// The short name of the quantity, in ASCII.
fn short_name(colour: Colour, per_area: bool) -> &'static str {
    match (colour, per_area) {
        (Colour::I, false) => "I_i",
        (Colour::I, true) => "I_i / a_i",
        (Colour::H, _) => "H_i",
        (Colour::Ic, false) => "I_i^c",
        (Colour::Ic, true) => "I_i^c / a_i",
        (Colour::Delta, false) => "I_i^c - I_i",
        (Colour::Delta, true) => "(I_i^c - I_i) / a_i",
    }
}

/// The quantity with its equation, in ASCII.
fn long_name(colour: Colour) -> &'static str {
    match colour {
        Colour::I => "information transfer of patch i (6.8)",
        Colour::H => "entropy of patch i (3.2)",
        Colour::Ic => "continuous information transfer of patch i (6.37, Monte Carlo)",
        Colour::Delta => "discretisation error of patch i (6.5.2)",
    }
}

fn units(per_area: bool) -> &'static str {
    if per_area {
        "bits per unit relative area"
    } else {
        "bits"
    }
}

/// The coloured mesh and the values' range.
fn mesh(scene: &Scene3, computed: &Computed, config: &Config, name: &str) -> (Ply, (f64, f64)) {
    let values = &computed.values;
    let (map, scale) = patch_colours(config.colour, values);
    let (lo, hi) = range(values.iter().copied());
    let mut ply = Ply::in_frame(scene.frame());
    ply.comment(&format!("sceneinfo draw {name}"));
    ply.comment(&format!(
        "quantity: {}, {}",
        short_name(config.colour, config.per_area),
        long_name(config.colour)
    ));
    ply.comment(&format!("units: {}", units(config.per_area)));
    ply.comment(&format!("min: {lo}"));
    ply.comment(&format!("max: {hi}"));
    ply.comment(match map {
        ColourMap::Viridis => "colour map: viridis, linear from min to max",
        ColourMap::CoolWarm => {
            "colour map: cool-warm diverging about 0: grey at 0, blue below (deepest at min if \
             min < 0), red above (deepest at max if max > 0), each side scaled to its extreme"
        }
    });
    for note in &computed.notes {
        ply.comment(note);
    }
    ply.comment(&format!(
        "{} patches: one face each, with its own vertices so colours stay flat",
        scene.n_patches()
    ));
    for (i, v) in values.iter().enumerate() {
        ply.polygon(scene.patch_vertices(i), map.at(scale.fraction(*v)));
    }
    (ply, (lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ply::check::parse;
    use sceneinfo::geom::DVec3;
    use sceneinfo::scene::Subdivision;

    fn args(colour: Colour, lines: Option<u64>, per_area: bool) -> DrawArgs {
        DrawArgs {
            file: "t.obj".into(),
            svg: None,
            ply: Some("t.ply".into()),
            per_area,
            color: colour,
            lines,
            seed: 5,
            threads: Some(2),
            matrix_svg: None,
            log: false,
            width: 400,
        }
    }

    fn config(colour: Colour, lines: Option<u64>, exact: bool) -> Config {
        Config::new(&args(colour, lines, false), 2, || exact).unwrap()
    }

    #[test]
    fn sources_follow_the_colouring_and_the_scene() {
        let c = config(Colour::I, None, true);
        assert_eq!((c.lines, c.discrete), (None, Some(Source::Exact)));
        let c = config(Colour::H, None, false);
        assert_eq!(
            (c.lines, c.discrete),
            (Some(DEFAULT_LINES), Some(Source::MonteCarlo))
        );
        let c = config(Colour::I, Some(100), true);
        assert_eq!((c.lines, c.discrete), (Some(100), Some(Source::MonteCarlo)));
        let c = config(Colour::Ic, None, true);
        assert_eq!((c.lines, c.discrete), (Some(DEFAULT_LINES), None));
        let c = config(Colour::Delta, Some(7), true);
        assert_eq!((c.lines, c.discrete), (Some(7), Some(Source::Exact)));
        let c = config(Colour::Delta, None, false);
        assert_eq!(
            (c.lines, c.discrete),
            (Some(DEFAULT_LINES), Some(Source::MonteCarlo))
        );
        assert!(Config::new(&args(Colour::I, Some(0), false), 2, || true).is_err());
        assert!(Config::new(&args(Colour::H, None, true), 2, || true).is_err());
        // The occlusion test is not run when it is not needed.
        Config::new(&args(Colour::Ic, None, false), 2, || panic!("asked")).unwrap();
    }

    #[test]
    fn the_cube_is_exact_and_every_colouring_writes_a_valid_mesh() {
        let scene = Scene3::cube(2).unwrap();
        assert!(exact_possible(&scene));
        for colour in [Colour::I, Colour::H, Colour::Ic, Colour::Delta] {
            for per_area in [false, true] {
                if per_area && colour == Colour::H {
                    continue;
                }
                let a = args(colour, Some(20_000), per_area);
                let a = DrawArgs {
                    lines: matches!(colour, Colour::Ic | Colour::Delta).then_some(20_000),
                    ..a
                };
                let c = Config::new(&a, 2, || exact_possible(&scene)).unwrap();
                let computed = compute(Path::new("t.obj"), &scene, &c).unwrap();
                assert_eq!(computed.values.len(), 24);
                assert!(computed.values.iter().all(|v| v.is_finite()));
                let (ply, (lo, hi)) = mesh(&scene, &computed, &c, "t.obj");
                assert!(lo <= hi);
                let p = parse(&ply.finish().unwrap()).unwrap();
                assert_eq!(p.faces.len(), 24);
                assert_eq!(p.vertices.len(), 96);
                assert!(p.comments.iter().any(|c| c.starts_with("quantity: ")));
                assert!(p.comments.iter().any(|c| c.starts_with("min: ")));
                assert!(
                    p.comments
                        .iter()
                        .any(|c| c.contains("exact") || c.contains("Monte Carlo"))
                );
            }
        }
    }

    #[test]
    fn per_area_values_are_the_shares_divided_by_relative_area() {
        let scene = Scene3::cube(2).unwrap();
        let run = |per_area| {
            let c = Config::new(&args(Colour::I, None, per_area), 2, || true).unwrap();
            compute(Path::new("t.obj"), &scene, &c).unwrap().values
        };
        let (shares, density) = (run(false), run(true));
        // 24 equal patches: a_i = 1/24.
        for (s, d) in shares.iter().zip(&density) {
            assert!((d - 24.0 * s).abs() < 1e-12 * d.abs().max(1.0), "{s} {d}");
        }
    }

    #[test]
    fn an_open_scene_drops_the_background_row() {
        // Two facing unit squares: most lines leave to the background.
        let mut b = Scene3::builder();
        let sq = |z: f64, up: bool| {
            let mut v = vec![
                DVec3::new(0.0, 0.0, z),
                DVec3::new(1.0, 0.0, z),
                DVec3::new(1.0, 1.0, z),
                DVec3::new(0.0, 1.0, z),
            ];
            if !up {
                v.reverse();
            }
            v
        };
        b.polygon(&sq(0.0, true), Subdivision::Grid(2)).unwrap();
        b.polygon(&sq(1.0, false), Subdivision::Grid(2)).unwrap();
        let scene = b.build().unwrap();
        for (colour, lines) in [(Colour::I, None), (Colour::Delta, Some(20_000))] {
            let c = Config::new(&args(colour, lines, false), 2, || exact_possible(&scene)).unwrap();
            let computed = compute(Path::new("t.obj"), &scene, &c).unwrap();
            assert_eq!(computed.values.len(), 8);
            assert!(computed.notes.iter().any(|n| n.contains("background")));
        }
    }
}
