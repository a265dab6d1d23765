//! `sceneinfo refine FILE.obj`: hierarchical radiosity driven by an oracle (thesis §6.4),
//! the final mesh's channel measures, its RMS error against a reference solution, and
//! pictures of it (PLY with radiosities, PNG rendering).
//!
//! The numbers come from the core ([`Hierarchy`], the channel and the line tallies); this
//! module validates the flags, runs the lines on threads, reads a reference PLY and draws.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use sceneinfo::ContinuousEstimate;
use sceneinfo::LineSession;
use sceneinfo::geom::DVec3;
use sceneinfo::hierarchy::{Hierarchy, HrOptions, OracleChoice3};
use sceneinfo::image::{Camera3, Picture3, ToneMap};
use sceneinfo::scene::{Material, Scene3};
use sceneinfo::tally::LineTracer;
use sceneinfo::trace::estimate_2d::LineMethod;
use sceneinfo::trace::estimate_3d::Tracer3;
use sceneinfo_report::{HierarchyReport, JsonObject, LeafMeasures};

use crate::args::{Oracle, RefineArgs};
use crate::lines::LineBudget;
use crate::output::{Loaded, job_refused, located, write_atomic};
use crate::ply::Ply;
use crate::svg::Rgb;

/// Leaves aimed at when neither `--eps` nor `--target` is given.
pub const DEFAULT_TARGET: usize = 1000;
/// Global lines that first measure the final mesh's channel when `--lines` is not given
/// (16 seeded chunks, `2²⁰`).
pub const DEFAULT_LINES: u64 = 16 * LineSession::CHUNK_LINES;
/// Most global lines the automatic budget doubles up to (`2²⁵`, 32 × [`DEFAULT_LINES`]) for
/// every leaf to receive some.
pub const MAX_AUTO_LINES: u64 = 32 * DEFAULT_LINES;

/// The validated settings.
#[derive(Debug)]
struct Config {
    oracle: &'static str,
    eps: Option<f64>,
    target: usize,
    options: HrOptions,
    /// The first line budget of the mesh's measures.
    lines: u64,
    /// Whether the budget may double (no `--lines`) until every leaf is sampled.
    auto_lines: bool,
    threads: usize,
}

impl Config {
    fn new(args: &RefineArgs, threads: usize) -> Result<Self> {
        let file = args.file.display();
        let oracle = match args.oracle {
            Oracle::Power => "power",
            Oracle::Ks => "ks",
            Oracle::KsAv => "ks-av",
            Oracle::Mi => "mi",
            Oracle::MiIncrease => "mi-increase",
            Oracle::Regular => "regular",
            Oracle::De => bail!(
                "{file}: --oracle de refines flatland scenes; a .obj scene takes power, ks, \
                 ks-av, mi, mi-increase or regular"
            ),
        };
        if let Some(path) = &args.svg {
            bail!(
                "{file}: --svg draws flatland meshes; for a .obj scene use --ply or --png (not {})",
                path.display()
            );
        }
        if args.output.is_some() {
            bail!("{file}: -o writes refined .flat scenes; for a .obj scene use --ply or --png");
        }
        // The camera's flags were read by clap (sizes, points, field of view); the pair here
        // is checked before the job rather than at the picture
        if args.eye.is_some() && args.eye == args.look {
            bail!("{file}: --eye and --look must differ (the camera looks from one to the other)");
        }
        let pairs = args.pairs.unwrap_or(10) as usize;
        if !(1..=HrOptions::MAX_PAIRS).contains(&pairs) {
            bail!(
                "{file}: --pairs {pairs} must be 1 to {}",
                HrOptions::MAX_PAIRS
            );
        }
        if let Some(e) = args.eps {
            // Checked again by the core, with the oracle's own rule for `regular`.
            OracleChoice3::new(oracle, e).map_err(|e| located(&args.file, &e))?;
        }
        let target = match args.target {
            Some(0) => bail!("{file}: --target must be at least 1"),
            Some(t) => t,
            None => DEFAULT_TARGET,
        };
        let min_area = args.min_area.unwrap_or(HrOptions::default().min_area);
        if !(min_area.is_finite() && (0.0..1.0).contains(&min_area)) {
            bail!("{file}: --min-area {min_area} must be a fraction of the scene's area, 0 to 1");
        }
        let lines = args.lines.unwrap_or(DEFAULT_LINES);
        if lines == 0 {
            return Err(located(&args.file, &sceneinfo::ErrorKind::NoLines.into()));
        }
        Ok(Self {
            oracle,
            eps: args.eps,
            target,
            options: HrOptions {
                pairs,
                seed: args.seed,
                min_area,
                ..HrOptions::default()
            },
            lines,
            auto_lines: args.lines.is_none(),
            threads,
        })
    }
}

/// Runs `refine` on a `.obj` scene.
pub fn run(args: &RefineArgs, threads: usize) -> Result<()> {
    let config = Config::new(args, threads)?;
    // Hierarchical radiosity uses the materials: their warnings are printed too
    let loaded = crate::output::load_scene(&args.file)?;
    loaded.print_warnings(&args.file, true);
    let Loaded::Solid(scene) = loaded.scene else {
        bail!("{}: not a 3D scene", args.file.display());
    };
    let at = |e: sceneinfo::Error| located(&args.file, &e);
    // The scene loaded as for every command: what hierarchical radiosity refuses is a job
    // refusal, not a verdict on the file
    let refused = |e: sceneinfo::Error| {
        job_refused(
            &args.file,
            format_args!("hierarchical radiosity: {}", e.kind()),
        )
    };
    // The reference is read (and refused if it must be) before the job, not after it
    let reference = args.reference.as_deref().map(read_reference).transpose()?;
    let start = Instant::now();
    let (eps, h) = match config.eps {
        Some(eps) => {
            let oracle = OracleChoice3::new(config.oracle, eps).map_err(at)?;
            (
                eps,
                Hierarchy::build(&scene, &oracle, &config.options).map_err(refused)?,
            )
        }
        None => Hierarchy::build_to_target(&scene, config.oracle, config.target, &config.options)
            .map_err(refused)?,
    };
    let hr_seconds = start.elapsed().as_secs_f64();
    // The pictures and the RMS error need only the hierarchy: they come first, so a mesh
    // whose channel cannot be measured still gives them.
    if let Some(path) = &args.ply {
        write_atomic(path, mesh_ply(&h, &args.file, &config, eps)?.as_bytes())?;
    }
    if let Some(path) = &args.png {
        let png = render(&h, &scene, args)?;
        write_atomic(path, &png)?;
    }
    let rms = match (&args.reference, &reference) {
        (Some(path), Some(reference)) => Some(rms_error(&h, path, reference)?),
        _ => None,
    };
    let measures = measure(&h, &config, args.seed, &args.file)?;
    if let Some(w) = &measures.warning {
        eprintln!("sceneinfo: warning: {}: {w}", args.file.display());
    }
    let seconds = start.elapsed().as_secs_f64();
    let report = Report {
        config: &config,
        eps,
        h: &h,
        m: &measures,
        rms,
        hr_seconds,
        seconds,
    };
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", report.json(args.seed)?)?;
    } else {
        write!(out, "{}", report.table(&args.file.display().to_string()))?;
    }
    out.flush()?;
    Ok(())
}

/// The leaves' channel: discrete measures and `I_S^c` from global lines.
///
/// A global line meets a leaf with a probability proportional to its area, so the smallest
/// leaves of a fine mesh may receive none of `config.lines`. Without `--lines` the budget
/// then doubles ([`sceneinfo::LineRun::cast_lines`]: the tally grows by the seeded chunks of the
/// larger job, so the result equals one run of the final budget) up to
/// [`MAX_AUTO_LINES`]. A leaf still unsampled after that (or with `--lines` given) leaves
/// the measures NaN, with a warning that says how many lines to ask for
/// ([`sceneinfo::tally::coverage`]).
fn measure(h: &Hierarchy, config: &Config, seed: u64, file: &Path) -> Result<LeafMeasures> {
    let at = |e: sceneinfo::Error| located(file, &e);
    // Leaves too small to validate as patches: the file was fine, the mesh went too fine
    let too_fine = |e: sceneinfo::Error| {
        job_refused(
            file,
            format_args!(
                "the refined mesh cannot be measured: a leaf: {}; a larger --min-area or a \
                 smaller --target keeps the elements larger",
                e.kind()
            ),
        )
    };
    let leaves = h.leaf_scene().map_err(too_fine)?;
    let tracer = Tracer3::new(&leaves).map_err(too_fine)?;
    let budget = if config.auto_lines {
        LineBudget::UntilSampled {
            start: config.lines,
            max: MAX_AUTO_LINES,
        }
    } else {
        LineBudget::Fixed(config.lines)
    };
    let mut executor = crate::lines::Threads::new(config.threads);
    let run =
        sceneinfo::LineRun::cast_lines(&tracer, LineMethod::Global, seed, budget, &mut executor);
    // A job cut short by Ctrl-C is not the one asked for: nothing is reported
    crate::interrupt::stop_if_requested()?;
    let lines = run.lines;
    if !run.tally.all_sampled() {
        let c = run.tally.coverage(tracer.patch_sizes());
        let first = c.first_unsampled.unwrap_or(0);
        let area = leaves.patches().get(first).map_or(0.0, |p| p.area) / leaves.total_area();
        let more = match c.lines_to_sample_all {
            Some(m) => format!("about {m}"),
            None => format!("more than {lines}"),
        };
        return Ok(LeafMeasures::unmeasured(
            leaves.n_patches(),
            lines,
            format!(
                "the mesh's channel is not measured: {} of the {} leaves (the first, leaf \
                 {first}, {area:.1e} of the scene's area) received none of the {lines} global \
                 lines; cast more with --lines ({more}), or bound the leaves with --min-area",
                c.unsampled, c.n_patches
            ),
        ));
    }
    let est = run.tally.finish(&tracer).map_err(at)?;
    let m = est.form_factors.channel().map_err(at)?.measures();
    Ok(LeafMeasures {
        n_patches: leaves.n_patches(),
        i_s: m.i_s,
        h_s: m.h_s,
        h_j: m.h_j,
        i_s_continuous: est.continuous.value,
        i_s_continuous_stderr: est.continuous.stderr,
        background: est.form_factors.has_background(),
        lines,
        warning: None,
    })
}

/// A reference solution: polygons with their radiosities.
type Reference = Vec<(Vec<DVec3>, [f64; 3])>;

/// Reads a reference solution: a PLY written by `refine --ply` (faces with float
/// `radiosity_red/green/blue` properties), as polygons with their radiosities, through the
/// one PLY reader ([`crate::formats::ply_scene::read_mesh`]: ASCII or binary).
fn read_reference(path: &Path) -> Result<Reference> {
    let cap = crate::formats::input_cap(crate::formats::MAX_FILE_BYTES);
    let bytes = crate::formats::read_capped_to(path, cap, "reference solutions")?;
    let mesh = crate::formats::ply_scene::read_mesh(path, &bytes)?;
    let bad = |what: String| anyhow::anyhow!("{}: {what}", path.display());
    if mesh.faces.iter().any(|f| f.radiosity.is_none()) {
        return Err(bad(
            "faces carry no radiosity_red/green/blue: write the reference with `sceneinfo \
             refine FILE.obj --ply REF.ply`"
                .to_owned(),
        ));
    }
    let mut faces = Vec::with_capacity(mesh.faces.len());
    for (k, face) in mesh.faces.iter().enumerate() {
        let mut poly = Vec::new();
        mesh.polygon(path, k, &mut poly)?;
        let b = face.radiosity.unwrap_or_default();
        if b.iter().any(|x| !x.is_finite()) {
            return Err(bad(format!("PLY face {k}: radiosity is NaN or infinite")));
        }
        faces.push((poly, b));
    }
    Ok(faces)
}

/// The RMS difference from `reference`, the reference PLY read from `path` (named in errors).
fn rms_error(h: &Hierarchy, path: &Path, reference: &Reference) -> Result<f64> {
    h.rms_difference(reference.iter().map(|(p, b)| (p.as_slice(), *b)))
        .map_err(|e| located(path, &e))
        .with_context(|| "comparing with the reference solution")
}

/// The tone map of the pictures: [`ToneMap::for_scene`] over the leaves (white at the
/// largest radiosity channel of a non-emitting leaf, or of any leaf if everything emits), so
/// `refine` and `radiosity` colour a radiosity alike; white at 1 when nothing is lit, so
/// the picture is black rather than divided by zero.
fn tone_map(h: &Hierarchy) -> ToneMap {
    let (radiosity, materials): (Vec<[f64; 3]>, Vec<Material>) = h
        .leaves()
        .map(|e| {
            let material = Material {
                reflectance: e.rho,
                emittance: e.emission,
            };
            (e.radiosity, material)
        })
        .unzip();
    let tone = ToneMap::for_scene(&radiosity, &materials);
    if tone.white > 0.0 {
        tone
    } else {
        ToneMap { white: 1.0 }
    }
}

/// The leaves as a PLY mesh: display colours and the radiosities themselves.
fn mesh_ply(h: &Hierarchy, file: &Path, config: &Config, eps: f64) -> Result<String> {
    let mut ply = Ply::in_frame(h.frame());
    ply.comment(&format!("sceneinfo refine {}", file.display()));
    ply.comment(&format!(
        "hierarchical radiosity, oracle {} eps {eps}, {} pairs per evaluation, seed {}",
        config.oracle, config.options.pairs, config.options.seed
    ));
    ply.comment(&format!(
        "{} leaves (elements), {} links, {} rays",
        h.n_leaves(),
        h.links().len(),
        h.rays()
    ));
    let tone = tone_map(h);
    ply.comment(&format!(
        "colour: radiosity / {} (brightest non-emitter = white), then the sRGB curve; \
         radiosity_red/green/blue: the radiosity B",
        tone.white
    ));
    for e in h.leaves() {
        let [r, g, b] = tone.rgb(e.radiosity);
        ply.polygon_with_radiosity(e.polygon.vertices(), Rgb(r, g, b), e.radiosity);
    }
    ply.finish()
}

/// Renders the leaves: Gouraud-shaded radiosity, element edges, z-buffer; PNG bytes.
fn render(h: &Hierarchy, scene: &Scene3, args: &RefineArgs) -> Result<Vec<u8>> {
    let (lo, hi) = scene.bounds();
    let bad_camera = |e: sceneinfo::Error| {
        anyhow::anyhow!(
            "--eye and --look must differ and --fov lie strictly between 0 and 180 degrees \
             (got {}): {e}",
            args.fov
        )
    };
    let framing = Camera3::framing((lo, hi), args.fov, args.size).map_err(bad_camera)?;
    // Given in the scene's units; the leaves are in its stored frame
    let stored = |p: &Option<[f64; 3]>, default: DVec3| {
        p.map_or(default, |p| scene.frame().to_stored(DVec3::from_array(p)))
    };
    let camera = Camera3::new(
        stored(&args.eye, framing.eye()),
        stored(&args.look, framing.look()),
        args.fov,
        args.size,
    )
    .map_err(bad_camera)?;
    let tone = tone_map(h);
    let mut picture = Picture3::new(camera, (hi - lo).length(), [0.0; 3]);
    let colours = h.vertex_radiosities();
    for (e, c) in h.leaves().zip(&colours) {
        picture.polygon(e.polygon.vertices(), e.normal, c);
    }
    // Edges dark grey: 5 % of white
    for e in h.leaves() {
        picture.outline(e.polygon.vertices(), e.normal, [0.05 * tone.white; 3]);
    }
    let (width, height) = args.size;
    crate::png::encode_rgb(width, height, &picture.to_rgb8(&tone)).context("empty image")
}

/// What `refine` prints.
struct Report<'a> {
    config: &'a Config,
    eps: f64,
    h: &'a Hierarchy,
    m: &'a LeafMeasures,
    rms: Option<f64>,
    hr_seconds: f64,
    seconds: f64,
}

impl Report<'_> {
    fn json(&self, seed: u64) -> Result<String, std::fmt::Error> {
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s)?;
        self.hierarchy(seed).write_fields(&mut o)?;
        o.number("seconds", self.seconds)?;
        o.finish()?;
        Ok(s)
    }

    /// The report crate's view of the run (the keys `refine --json` shares with the 3D lab).
    fn hierarchy(&self, seed: u64) -> HierarchyReport<'_> {
        HierarchyReport {
            oracle: self.config.oracle,
            eps: self.eps,
            pairs: self.config.options.pairs,
            hierarchy: self.h,
            leaves: self.m,
            rms_error: self.rms,
            seed,
        }
    }

    fn table(&self, name: &str) -> String {
        let (h, m) = (self.h, self.m);
        let mut s = String::new();
        let _ = writeln!(s, "scene                 {name}");
        let _ = writeln!(
            s,
            "oracle                {} (eps {}, {} pairs per evaluation, {} passes)",
            self.config.oracle,
            self.eps,
            self.config.options.pairs,
            h.passes()
        );
        let _ = writeln!(
            s,
            "mesh                  {} leaves of {} elements, {} links, {} rays ({:.2} s; budget hit: {})",
            h.n_leaves(),
            h.elements().len(),
            h.links().len(),
            h.rays(),
            self.hr_seconds,
            self.hierarchy(0).budget_hit()
        );
        if m.warning.is_some() {
            let _ = writeln!(
                s,
                "I_S, H_S, H_J, I_S^c  not measured: a leaf received none of {} global lines",
                m.lines
            );
        } else {
            let _ = writeln!(
                s,
                "I_S, H_S, H_J         {:.4}, {:.4}, {:.4} bits ({} global lines)",
                m.i_s, m.h_s, m.h_j, m.lines
            );
            let _ = writeln!(
                s,
                "I_S^c (4.13)          {:.4} ± {:.4} bits; δ̄ = {:.2} %",
                m.i_s_continuous,
                m.i_s_continuous_stderr,
                100.0 * ContinuousEstimate::relative_discretisation_error(m.i_s_continuous, m.i_s)
            );
        }
        if let Some(r) = self.rms {
            let _ = writeln!(s, "RMS error             {r:.6} (against the reference)");
        }
        let _ = writeln!(s, "time                  {:.2} s", self.seconds);
        s
    }
}
