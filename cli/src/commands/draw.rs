//! `sceneinfo draw`: a flatland scene as SVG, its patches coloured by a per-patch measure
//! (I_i, H_i, I_i^c or I_i^c − I_i), and optionally the mutual information matrix I_ij (6.7)
//! as a heat map (thesis Fig. 6.14).
//!
//! Every measure comes from the core; this module only picks values and maps them to colours.

mod solid;
use anyhow::Result;
use sceneinfo::formfactor::FormFactors;
use sceneinfo::scene::Scene2;
use sceneinfo::trace::estimate_2d::{LineEstimate, LineMethod, Tracer2};

use crate::args::{Colour, DrawArgs};
use crate::output::{located, write_atomic};
use crate::picture::{Legend, MARGIN, range, scene_picture};
use crate::svg::{Anchor, ColourMap, Rgb, Scale, Svg, number};

/// Lines cast for `ic` and `delta` when `--lines` is not given.
const DEFAULT_LINES: u64 = 1_000_000;
/// Up to this many patches, the discrete I_i of `delta` (and the matrix) use exact form
/// factors; above it, the Monte Carlo form factors of the same run.
const EXACT_LIMIT: usize = 2000;
/// The matrix picture has at most this many rows and columns of cells.
const MATRIX_BINS: usize = 400;

/// Where the discrete form factors come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Source {
    Exact,
    MonteCarlo,
}

/// The validated command.
#[derive(Debug)]
struct Config {
    colour: Colour,
    /// Lines of the Monte Carlo run, if there is one.
    lines: Option<u64>,
    /// Where the discrete form factors come from, if they are needed.
    discrete: Option<Source>,
    seed: u64,
    threads: usize,
}

impl Config {
    fn new(args: &DrawArgs, n_patches: usize, threads: usize) -> sceneinfo::Result<Self> {
        let lines = match args.color {
            Colour::Ic | Colour::Delta => Some(args.lines.unwrap_or(DEFAULT_LINES)),
            Colour::I | Colour::H => args.lines,
        };
        if let Some(n) = lines {
            sceneinfo::LineJob::check_lines(n)?;
        }
        let needs_discrete = args.color != Colour::Ic || args.matrix_svg.is_some();
        let discrete = needs_discrete.then_some(match (args.color, lines) {
            (_, None) => Source::Exact,
            (Colour::I | Colour::H, Some(_)) => Source::MonteCarlo,
            _ if n_patches <= EXACT_LIMIT => Source::Exact,
            _ => Source::MonteCarlo,
        });
        Ok(Self {
            colour: args.color,
            lines,
            discrete,
            seed: args.seed,
            threads,
        })
    }
}

/// What a run computed.
struct Computed {
    /// The per-patch values that colour the picture.
    values: Vec<f64>,
    /// The discrete form factors, if needed.
    ff: Option<FormFactors>,
    /// Legend lines describing where the numbers come from.
    notes: Vec<String>,
}

/// Runs `draw`: a `.flat` scene as SVG here, a 3D scene as PLY in [`solid`].
pub fn run(args: &DrawArgs, threads: usize) -> Result<()> {
    if crate::output::is_3d(&args.file) {
        return solid::run(args, threads);
    }
    let Some(svg_path) = &args.svg else {
        anyhow::bail!(
            "{}: a .flat scene is drawn as SVG: give --svg OUT.svg (--ply is for .obj scenes)",
            args.file.display()
        );
    };
    if args.ply.is_some() || args.per_area {
        anyhow::bail!(
            "{}: --ply and --per-area are for .obj scenes; a .flat scene is drawn with --svg",
            args.file.display()
        );
    }
    let at = |e: sceneinfo::Error| located(&args.file, &e);
    let scene = crate::output::load_flat(&args.file)?;
    let config = Config::new(args, scene.n_patches(), threads).map_err(at)?;
    let computed = compute(&scene, &config);
    // After Ctrl-C the line job stopped early: draw nothing
    crate::interrupt::stop_if_requested()?;
    let computed = computed.map_err(at)?;
    let name = args.file.display().to_string();
    let width = f64::from(args.width);
    let svg = scene_picture(
        &scene,
        &computed.values,
        config.colour,
        &name,
        &computed.notes,
        width,
    );
    write_atomic(svg_path, svg.as_bytes())?;
    if let (Some(path), Some(ff)) = (&args.matrix_svg, &computed.ff) {
        let grid = information_grid(ff, scene.n_patches()).map_err(at)?;
        let mut notes = vec![source_note(config.discrete, "I_ij")];
        if ff.has_background() {
            notes
                .push("open scene: the background state's row and column are not drawn".to_owned());
        }
        let svg = matrix_picture(&grid, &scene, args.log, &name, &notes, width);
        write_atomic(path, svg.as_bytes())?;
    }
    Ok(())
}

/// Runs the Monte Carlo lines and the core measures the colouring needs.
fn compute(scene: &Scene2, config: &Config) -> sceneinfo::Result<Computed> {
    let n = scene.n_patches();
    let estimate: Option<LineEstimate> = match config.lines {
        None => None,
        Some(lines) => {
            let tracer = Tracer2::new(scene)?;
            let tally = crate::lines::run(
                &tracer,
                LineMethod::Global,
                config.seed,
                lines,
                config.threads,
            );
            Some(tally.finish(&tracer)?)
        }
    };
    let mut notes = Vec::new();
    if let Some(lines) = config.lines {
        notes.push(format!(
            "Monte Carlo: {lines} global lines, seed {}",
            config.seed
        ));
    }
    let open = estimate
        .as_ref()
        .is_some_and(|e| e.form_factors.has_background());
    let (ff, continuous) = match (config.discrete, estimate) {
        (Some(Source::MonteCarlo), Some(est)) => {
            (Some(est.form_factors), Some(est.patch_continuous))
        }
        (Some(_), est) => (
            Some(sceneinfo::Scene::Flat(scene.clone()).exact_form_factors()?),
            est.map(|e| e.patch_continuous),
        ),
        (None, est) => (None, est.map(|e| e.patch_continuous)),
    };
    let discrete = |measure: PatchMeasure| {
        ff.as_ref()
            .map_or(Ok(Vec::new()), |ff| patch_values(ff, n, measure))
    };
    let values = match config.colour {
        Colour::I => {
            notes.push(source_note(config.discrete, "I_i"));
            discrete(PatchMeasure::Information)?
        }
        Colour::H => {
            notes.push(source_note(config.discrete, "H_i"));
            discrete(PatchMeasure::Entropy)?
        }
        Colour::Ic => continuous.unwrap_or_default(),
        Colour::Delta => {
            let mut note = source_note(config.discrete, "I_i");
            if config.discrete == Some(Source::Exact) {
                note.push_str(&format!(" (≤ {EXACT_LIMIT} patches)"));
            }
            notes.push(note);
            let i = discrete(PatchMeasure::Information)?;
            let ic = continuous.unwrap_or_default();
            ic.iter().zip(&i).map(|(c, d)| c - d).collect()
        }
    };
    if open || ff.as_ref().is_some_and(FormFactors::has_background) {
        notes.push("open scene: some lines leave to the background state (not drawn)".to_owned());
    }
    Ok(Computed { values, ff, notes })
}

/// A discrete per-patch measure of the core.
#[derive(Clone, Copy, Debug)]
pub(super) enum PatchMeasure {
    /// I_i (6.8).
    Information,
    /// H_i (3.2).
    Entropy,
}

/// The core's `measure` of the first `n` states (the patches) of the channel of `ff`.
pub(super) fn patch_values(
    ff: &FormFactors,
    n: usize,
    measure: PatchMeasure,
) -> sceneinfo::Result<Vec<f64>> {
    let channel = ff.channel()?;
    let mut out = vec![0.0; ff.n_states()];
    match measure {
        PatchMeasure::Information => channel.patch_mutual_information(&mut out)?,
        PatchMeasure::Entropy => channel.patch_entropies(&mut out)?,
    }
    out.truncate(n);
    Ok(out)
}

/// "`what` from exact form factors" or "… from the Monte Carlo form factors of this run".
fn source_note(source: Option<Source>, what: &str) -> String {
    match source {
        Some(Source::MonteCarlo) => format!("{what} from the Monte Carlo form factors of this run"),
        _ => format!("{what} from exact form factors"),
    }
}

/// The I_ij matrix of the scene's patches, summed into at most `MATRIX_BINS²` cells.
#[derive(Debug)]
struct Grid {
    /// Rows and columns.
    bins: usize,
    /// Patches.
    n: usize,
    /// Row-major `bins × bins` sums of I_ij.
    cells: Vec<f64>,
    /// Whether some pair of the cell sees each other (`P_ij > 0`).
    visible: Vec<bool>,
}

impl Grid {
    fn bin(&self, i: usize) -> usize {
        // i < n ≤ 4·10⁶ and bins ≤ 400: no overflow in u64.
        (i as u64 * self.bins as u64 / self.n as u64) as usize
    }
}

/// Sums the core's I_ij (6.7) of the patch pairs into the grid's cells (the background state,
/// if any, is left out).
fn information_grid(ff: &FormFactors, n: usize) -> sceneinfo::Result<Grid> {
    let channel = ff.channel()?;
    let bins = n.min(MATRIX_BINS);
    let mut grid = Grid {
        bins,
        n,
        cells: Vec::new(),
        visible: Vec::new(),
    };
    let mut sums = vec![0.0; bins * bins];
    let mut visible = vec![false; bins * bins];
    channel.for_each_pair_information(|i, j, v| {
        if i < n && j < n {
            let k = grid.bin(i) * bins + grid.bin(j);
            sums[k] += v;
            visible[k] = true;
        }
    });
    grid.cells = sums;
    grid.visible = visible;
    Ok(grid)
}

/// The colour of cells whose patches do not see each other.
const HIDDEN: Rgb = Rgb(0xff, 0xff, 0xff);

/// The heat map of I_ij, rows i from top to bottom, with surface boundaries and a legend.
fn matrix_picture(
    grid: &Grid,
    scene: &Scene2,
    log: bool,
    name: &str,
    notes: &[String],
    width: f64,
) -> String {
    let left = MARGIN + 20.0;
    let top = MARGIN + 20.0;
    let side = width - left - MARGIN;
    let height = top + side + 10.0;
    let shown = || {
        grid.cells
            .iter()
            .zip(&grid.visible)
            .filter(|(_, v)| **v)
            .map(|(c, _)| *c)
    };
    let (lo, hi) = range(shown());
    let smallest_positive = shown().filter(|&v| v > 0.0).fold(f64::INFINITY, f64::min);
    let (map, scale, how) = if log && hi > 0.0 {
        let floor = smallest_positive.max(hi * 1e-6);
        let how = format!(
            "log colours; cells ≤ {} (negative ones too) take the lowest colour",
            number(floor)
        );
        (ColourMap::Viridis, Scale::Log { lo: floor, hi }, how)
    } else if lo < 0.0 {
        let how = "linear colours diverging about 0, each side scaled to its extreme \
                   (blue: I_ij < 0, less transfer than independence)"
            .to_owned();
        (
            ColourMap::CoolWarm,
            Scale::Diverging {
                lo,
                hi: hi.max(0.0),
            },
            how,
        )
    } else {
        let how = "linear colours".to_owned();
        (ColourMap::Viridis, Scale::Linear { lo: 0.0, hi }, how)
    };
    let bins = grid.bins;
    let surfaces = scene.surfaces();
    let mut legend_notes = notes.to_vec();
    legend_notes.push(how);
    legend_notes.push(if surfaces.len() <= 64 && surfaces.len() > 1 {
        "white: the patches do not see each other (P_ij = 0); grey lines: surface boundaries"
            .to_owned()
    } else {
        "white: the patches do not see each other (P_ij = 0)".to_owned()
    });
    let cells = if bins < grid.n {
        format!("{bins} × {bins} cells, each the sum of the I_ij of its patch pairs")
    } else {
        format!("{bins} × {bins} cells")
    };
    let legend = Legend {
        heading: format!("{name}: {} patches; {cells}", grid.n),
        notes: legend_notes,
        label: format!(
            "I_ij: mutual information matrix (6.7), bits; cells from {} to {}",
            number(lo),
            number(hi)
        ),
        map,
        scale,
    };
    let mut svg = Svg::new(
        width,
        height + legend.height(),
        &format!("sceneinfo draw {name}: I_ij"),
    );
    let colour = |k: usize| {
        if grid.visible[k] {
            map.at(scale.fraction(grid.cells[k]))
        } else {
            HIDDEN
        }
    };
    svg.open_cells((left, top), side / bins as f64);
    for r in 0..bins {
        let mut start = 0;
        while start < bins {
            let c = colour(r * bins + start);
            let mut end = start + 1;
            while end < bins && colour(r * bins + end) == c {
                end += 1;
            }
            svg.rect(start as f64, r as f64, (end - start) as f64, 1.0, c);
            start = end;
        }
    }
    svg.close_group();
    // Surface boundaries, where they are few enough to read.
    if surfaces.len() <= 64 {
        let n = grid.n as f64;
        let mut lines = Vec::new();
        for s in surfaces.iter().skip(1) {
            let t = side * s.patches.start as f64 / n;
            lines.push(((left + t, top), (left + t, top + side)));
            lines.push(((left, top + t), (left + side, top + t)));
        }
        svg.segments(&lines, Rgb(0x90, 0x90, 0x90), 0.8);
    }
    svg.frame(left, top, side, side, Rgb(0, 0, 0), 1.0);
    let last = grid.n - 1;
    svg.text(left, top - 6.0, 12.0, Anchor::Start, "j = 0");
    svg.text(
        left + side,
        top - 6.0,
        12.0,
        Anchor::End,
        &format!("j = {last}"),
    );
    svg.text(
        left + side / 2.0,
        top - 6.0,
        12.0,
        Anchor::Middle,
        "patch j →",
    );
    svg.text(left - 4.0, top + 12.0, 12.0, Anchor::End, "i = 0");
    svg.text(left - 4.0, top + side / 2.0, 12.0, Anchor::End, "i ↓");
    svg.text(
        left - 4.0,
        top + side,
        12.0,
        Anchor::End,
        &format!("{last}"),
    );
    legend.draw(&mut svg, height, width);
    svg.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::svg::check::well_formed;

    fn triangle() -> Scene2 {
        sceneinfo::io::parse_flat("poly 3 0 0 1 0 0.5 0.866 per_side 4\n").unwrap()
    }

    fn config(colour: Colour, lines: Option<u64>, matrix: bool, n: usize) -> Config {
        let args = DrawArgs {
            file: "t.flat".into(),
            svg: Some("t.svg".into()),
            ply: None,
            per_area: false,
            color: colour,
            lines,
            seed: 3,
            threads: Some(2),
            matrix_svg: matrix.then(|| "m.svg".into()),
            log: false,
            width: 400,
        };
        Config::new(&args, n, 2).unwrap()
    }

    #[test]
    fn sources_follow_the_colouring() {
        assert_eq!(
            config(Colour::I, None, false, 10).discrete,
            Some(Source::Exact)
        );
        assert_eq!(
            config(Colour::I, Some(100), false, 10).discrete,
            Some(Source::MonteCarlo)
        );
        assert_eq!(config(Colour::Ic, None, false, 10).discrete, None);
        assert_eq!(
            config(Colour::Ic, None, false, 10).lines,
            Some(DEFAULT_LINES)
        );
        assert_eq!(
            config(Colour::Ic, None, true, 10).discrete,
            Some(Source::Exact)
        );
        assert_eq!(
            config(Colour::Delta, None, false, EXACT_LIMIT).discrete,
            Some(Source::Exact)
        );
        assert_eq!(
            config(Colour::Delta, None, false, EXACT_LIMIT + 1).discrete,
            Some(Source::MonteCarlo)
        );
    }

    #[test]
    fn every_colouring_draws_a_well_formed_picture() {
        let scene = triangle();
        for colour in [Colour::I, Colour::H, Colour::Ic, Colour::Delta] {
            let lines = matches!(colour, Colour::Ic | Colour::Delta).then_some(20_000);
            let c = config(colour, lines, true, scene.n_patches());
            let computed = compute(&scene, &c).unwrap();
            assert_eq!(computed.values.len(), scene.n_patches());
            assert!(computed.values.iter().all(|v| v.is_finite()));
            let svg = scene_picture(
                &scene,
                &computed.values,
                colour,
                "t & <u>.flat",
                &computed.notes,
                400.0,
            );
            well_formed(&svg).unwrap();
            assert_eq!(
                svg.matches("<line ").count(),
                scene.n_patches() + 3,
                "patches + bar ticks"
            );
            assert!(
                !svg.split(|c: char| !c.is_alphanumeric())
                    .any(|w| w == "NaN" || w == "inf")
            );
            let grid = information_grid(computed.ff.as_ref().unwrap(), scene.n_patches()).unwrap();
            for log in [false, true] {
                let m = matrix_picture(&grid, &scene, log, "t.flat", &computed.notes, 400.0);
                well_formed(&m).unwrap();
            }
        }
    }

    #[test]
    fn the_matrix_sums_into_bins() {
        let scene = sceneinfo::io::parse_flat("poly 4 0 0 1 0 1 1 0 1 per_side 120\n").unwrap();
        let ff = sceneinfo::Scene::Flat(scene.clone())
            .exact_form_factors()
            .unwrap();
        let grid = information_grid(&ff, scene.n_patches()).unwrap();
        assert_eq!(grid.bins, MATRIX_BINS);
        let total: f64 = grid.cells.iter().sum();
        let i_s = ff.channel().unwrap().i_s();
        assert!(
            (total - i_s).abs() < 1e-9 * i_s.max(1.0),
            "{total} vs {i_s}"
        );
        assert_eq!(grid.bin(0), 0);
        assert_eq!(grid.bin(scene.n_patches() - 1), MATRIX_BINS - 1);
    }

    #[test]
    fn a_flat_scene_of_one_horizontal_segment_still_fits() {
        let scene = sceneinfo::io::parse_flat("seg 0 0 3 0 5\n").unwrap();
        let svg = scene_picture(&scene, &[1.0; 5], Colour::H, "s.flat", &[], 300.0);
        well_formed(&svg).unwrap();
        assert!(!svg.contains("NaN"));
    }
}
