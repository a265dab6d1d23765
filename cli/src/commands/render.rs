//! `sceneinfo render`: a 3D scene's radiosity solution through a pinhole camera, pixels
//! supersampled uniformly or adaptively by the entropy or mutual-information contrast
//! (`sceneinfo::supersample`; docs/supersampling.md), and with `--rmse` the three compared
//! at equal total samples against a converged reference, over several seeds.
//!
//! The radiosity is solved as `radiosity` solves it (the façade's `solve_radiosity`: form
//! factors exact or by `--lines`, Gauss–Seidel, per colour channel); the renderer and the oracle are the core's
//! (`supersample::render3`); this command loads, wires, prints and writes pictures.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

use anyhow::{Result, bail};
use sceneinfo::geom::DVec3;
use sceneinfo::image::{Camera3, ToneMap};
use sceneinfo::scene::{Scene3, Subdivision};
use sceneinfo::supersample::Oracle;
use sceneinfo::supersample::render3::{
    Allocation, Image3, RadianceScene3, RenderOptions, Spread, render,
};
use sceneinfo::{ErrorKind, RadiosityJob};

use crate::args::{AdaptiveArg, RenderArgs};
use crate::output::{Loaded, located, write_atomic};
use crate::svg::ColourMap;

/// Seed of the reference image's sample positions: apart from the compared renders'
/// seeds `1..=--seeds`.
const REFERENCE_SEED: u64 = u64::MAX;

pub fn run(args: &RenderArgs, threads: usize) -> Result<()> {
    let path = &args.file;
    let at = |e: sceneinfo::Error| located(path, &e);
    let options = sceneinfo::io::ObjOptions::new(Subdivision::Grid(args.grid))
        .with_emit_from_ka(args.emit_from_ka);
    let loaded = crate::output::load_scene_with(path, &options)?;
    loaded.print_warnings(path, true);
    let scene = loaded.scene;
    let Loaded::Solid(solid) = &scene else {
        bail!(
            "{}: render draws 3D scenes (OBJ, glTF, PLY); a .flat scene has no camera view",
            path.display()
        );
    };
    let oracle = oracle_of(args.adaptive, args.threshold).map_err(at)?;

    // The radiosity solution: the façade's solve_radiosity, as `radiosity` uses it
    let start = Instant::now();
    let budget = crate::job::budget_of(&args.sampling, path)?;
    let form_factors = crate::job::job_of(&args.sampling, budget);
    if budget.is_some() {
        let tracer = scene.tracer().map_err(at)?;
        let method = args.sampling.method.line_method();
        crate::job::check_supported(tracer.as_dyn(), method, path)?;
    }
    let job = RadiosityJob::new(form_factors);
    let mut executor = crate::lines::Threads::new(threads);
    let lit = match sceneinfo::solve_radiosity(&scene, &job, &mut executor) {
        Ok(lit) => lit,
        Err(e) if matches!(e.kind(), ErrorKind::Stopped) => {
            crate::interrupt::stop_if_requested()?;
            return Err(located(path, &e));
        }
        Err(e) => return Err(crate::output::exact_error(path, &e)),
    };
    let (materials, radiosity) = (lit.materials(), &lit.solution().radiosity);
    if !materials.iter().any(|m| m.is_emitter()) {
        eprintln!(
            "note: {}: nothing emits, so the picture is black (old-style lamps: --emit-from-ka)",
            path.display()
        );
    }
    let tone = ToneMap::for_scene(radiosity, materials);
    let radiance = RadianceScene3::new(solid, radiosity, tone).map_err(at)?;
    let solve_seconds = start.elapsed().as_secs_f64();
    let camera = camera_of(args, solid).map_err(at)?;

    // The picture
    let start = Instant::now();
    let allocation = allocation_of(oracle);
    let image = render(
        &radiance,
        &camera,
        allocation,
        &options_of(args, args.render_seed),
    )
    .map_err(at)?;
    let render_seconds = start.elapsed().as_secs_f64();
    if let Some(out) = &args.png {
        write_png(out, &image, |c| c.map(ToneMap::encode))?;
    }
    if let Some(out) = &args.samples_png {
        let most = image.counts.iter().copied().max().unwrap_or(1).max(2);
        let scale = f64::from(most).log2();
        write_counts_png(out, &image, scale)?;
    }

    let mut s = String::new();
    let name = path.display().to_string();
    let _ = writeln!(s, "scene                 {name}");
    let _ = writeln!(
        s,
        "patches               {} (faces cut {}×{})",
        solid.n_patches(),
        args.grid,
        args.grid
    );
    let _ = writeln!(
        s,
        "form factors          {}",
        match budget {
            None => "exact".to_string(),
            Some(_) => format!(
                "{}, seed {}",
                args.sampling.method.line_method().description(),
                args.sampling.seed
            ),
        }
    );
    let _ = writeln!(s, "radiosity solve       {solve_seconds:.2} s");
    let (w, h) = camera.size();
    let _ = writeln!(
        s,
        "image                 {w}×{h}, {} spp on average",
        args.spp
    );
    let neighbours = if matches!(allocation, Allocation::Adaptive(_)) && !args.own_samples_only {
        ", pixel and its 4 neighbours"
    } else {
        ""
    };
    let _ = writeln!(
        s,
        "allocation            {}{neighbours}",
        allocation_name(allocation)
    );
    write_counts(&mut s, &image);
    let _ = writeln!(s, "render                {render_seconds:.2} s");
    if args.rmse {
        compare(&mut s, args, &radiance, &camera)?;
    }
    let mut out = std::io::stdout().lock();
    write!(out, "{s}")?;
    out.flush()?;
    Ok(())
}

/// The sampling options of the flags, with seed `seed`.
fn options_of(args: &RenderArgs, seed: u64) -> RenderOptions {
    let mut options = RenderOptions::new(args.spp, seed);
    options.neighbours = !args.own_samples_only;
    options
}

/// The oracle of `--adaptive` and `--threshold` (without it, each contrast's own default),
/// `None` for uniform sampling.
fn oracle_of(adaptive: AdaptiveArg, threshold: Option<f64>) -> sceneinfo::Result<Option<Oracle>> {
    let oracle = match adaptive {
        AdaptiveArg::None => return Ok(None),
        AdaptiveArg::Entropy => Oracle::entropy(),
        AdaptiveArg::Mi => Oracle::mutual_information(),
    };
    match threshold {
        Some(t) => oracle.with_threshold(t).map(Some),
        None => Ok(Some(oracle)),
    }
}

fn allocation_of(oracle: Option<Oracle>) -> Allocation {
    oracle.map_or(Allocation::Uniform, Allocation::Adaptive)
}

fn allocation_name(a: Allocation) -> String {
    match a {
        Allocation::Uniform => "uniform".to_string(),
        Allocation::Adaptive(o) => format!(
            "adaptive, {} contrast > {}",
            o.measure().name(),
            o.threshold()
        ),
    }
}

/// The camera of `--eye`, `--look`, `--fov`, `--size` (given in the scene's units; the
/// scene is stored in its frame), or the framing one.
fn camera_of(args: &RenderArgs, solid: &Scene3) -> sceneinfo::Result<Camera3> {
    let frame = solid.frame();
    let framing = Camera3::framing(solid.bounds(), args.fov, args.size)?;
    if args.eye.is_none() && args.look.is_none() {
        return Ok(framing);
    }
    let (lo, hi) = solid.bounds();
    let eye = args
        .eye
        .map_or(framing.eye(), |p| frame.to_stored(DVec3::from_array(p)));
    let look = args
        .look
        .map_or((lo + hi) * 0.5, |p| frame.to_stored(DVec3::from_array(p)));
    Camera3::new(eye, look, args.fov, args.size)
}

/// Samples in all, per pixel (least, greatest) and how the adaptive ones were placed.
fn write_counts(s: &mut String, image: &Image3) {
    let least = image.counts.iter().copied().min().unwrap_or(0);
    let most = image.counts.iter().copied().max().unwrap_or(0);
    let _ = writeln!(
        s,
        "samples               {} in all, {least} to {most} per pixel, {} spread evenly \
         after the oracle stopped asking",
        image.samples, image.spread
    );
}

/// `--rmse`: uniform, entropy and mi at the same budget over seeds `1..=--seeds`, each
/// against the reference.
fn compare(
    s: &mut String,
    args: &RenderArgs,
    radiance: &RadianceScene3,
    camera: &Camera3,
) -> Result<()> {
    let threshold = args.threshold;
    let at = |e: sceneinfo::Error| located(&args.file, &e);
    let start = Instant::now();
    let reference = render(
        radiance,
        camera,
        Allocation::Uniform,
        &RenderOptions::new(args.reference_spp, REFERENCE_SEED),
    )
    .map_err(at)?;
    let methods = [
        ("uniform", Allocation::Uniform),
        (
            "entropy",
            allocation_of(oracle_of(AdaptiveArg::Entropy, threshold).map_err(at)?),
        ),
        (
            "mi",
            allocation_of(oracle_of(AdaptiveArg::Mi, threshold).map_err(at)?),
        ),
    ];
    let mut errors = vec![Vec::new(); methods.len()];
    let mut spread = vec![0u64; methods.len()];
    for seed in 1..=args.seeds {
        for (k, (_, allocation)) in methods.iter().enumerate() {
            let image =
                render(radiance, camera, *allocation, &options_of(args, seed)).map_err(at)?;
            let e = image.rmse(&reference).unwrap_or(f64::NAN);
            errors[k].push(e);
            spread[k] += image.spread;
        }
    }
    let _ = writeln!(
        s,
        "reference             uniform, {} spp, seed {REFERENCE_SEED}",
        args.reference_spp
    );
    let _ = writeln!(
        s,
        "RMSE against it       linear display values in [0, 1], {} spp on average, seeds 1..={}",
        args.spp, args.seeds
    );
    let _ = writeln!(
        s,
        "  method    mean RMSE    sd         min        max        mean/uniform  samples spread"
    );
    let uniform = Spread::of(&errors[0]).map_or(f64::NAN, |x| x.mean);
    for (k, (name, _)) in methods.iter().enumerate() {
        let Some(x) = Spread::of(&errors[k]) else {
            continue;
        };
        let _ = writeln!(
            s,
            "  {name:<8}  {:.6}     {:.6}   {:.6}   {:.6}   {:.3}         {}",
            x.mean,
            x.sd,
            x.min,
            x.max,
            x.mean / uniform,
            spread[k]
        );
    }
    let _ = writeln!(
        s,
        "comparison            {:.2} s",
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Writes `image` as PNG, each pixel's linear colour through `encode`.
fn write_png(out: &Path, image: &Image3, encode: impl Fn([f64; 3]) -> [u8; 3]) -> Result<()> {
    let bytes: Vec<u8> = image.rgb.iter().flat_map(|&c| encode(c)).collect();
    let Some(png) = crate::png::encode_rgb(image.width, image.height, &bytes) else {
        bail!("{}: no picture to write", out.display());
    };
    write_atomic(out, &png)
}

/// Writes the samples per pixel as PNG: viridis at `log₂ n / scale`.
fn write_counts_png(out: &Path, image: &Image3, scale: f64) -> Result<()> {
    let bytes: Vec<u8> = image
        .counts
        .iter()
        .flat_map(|&n| {
            let c = ColourMap::Viridis.at(f64::from(n.max(1)).log2() / scale);
            [c.0, c.1, c.2]
        })
        .collect();
    let Some(png) = crate::png::encode_rgb(image.width, image.height, &bytes) else {
        bail!("{}: no picture to write", out.display());
    };
    write_atomic(out, &png)
}
