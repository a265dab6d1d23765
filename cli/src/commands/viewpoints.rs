//! `sceneinfo viewpoints`: the viewpoint channel of a 3D scene — viewpoint entropy, viewpoint
//! mutual information, the best views, a greedy selection of views and mesh saliency
//! (`sceneinfo::viewpoint`). Rows (one rasterised view each) run on threads; each depends
//! only on its viewpoint, so the output is the same for any `--threads`.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;
use std::sync::Mutex;
use std::time::Instant;

use anyhow::{Result, bail};
use sceneinfo::geom::DVec3;
use sceneinfo::scene::Scene3;
use sceneinfo::viewpoint::{
    IdRaster, ViewTotals, ViewWeighting, ViewpointChannel, ViewpointJob, ViewpointOptions,
};
use sceneinfo_report::ViewpointReport;

use crate::args::{SphereColour, ViewWeightingArg, ViewpointsArgs};
use crate::output::{Loaded, located, write_atomic};
use crate::ply::Ply;
use crate::svg::{ColourMap, Rgb, Scale};

pub fn run(args: &ViewpointsArgs, threads: usize) -> Result<()> {
    let at = |e: sceneinfo::Error| located(&args.file, &e);
    let loaded = crate::output::load_scene(&args.file)?;
    // Visibility only: the material warnings are not ours
    loaded.print_warnings(&args.file, false);
    let Loaded::Solid(scene) = loaded.scene else {
        bail!(
            "{}: viewpoints need a 3D scene (OBJ, glTF, PLY)",
            args.file.display()
        );
    };
    let options = ViewpointOptions {
        views: args.views,
        resolution: args.resolution,
        distance: args.distance,
        weighting: match args.weighting {
            ViewWeightingArg::Uniform => ViewWeighting::Uniform,
            ViewWeightingArg::Area => ViewWeighting::ProjectedArea,
        },
    };
    let job = ViewpointJob::new(&scene, options).map_err(at)?;
    let threads = threads.clamp(1, job.n_views());
    let start = Instant::now();
    let channel = run_rows(&job, threads).map_err(|e| match e.downcast::<sceneinfo::Error>() {
        Ok(e) => at(e),
        Err(e) => e,
    })?;
    let seconds = start.elapsed().as_secs_f64();
    if !(0.0..=1.0).contains(&args.fraction) {
        return Err(at(sceneinfo::ErrorKind::BadParameter {
            name: "fraction (0 to 1)",
            value: args.fraction,
        }
        .into()));
    }
    let report = ViewpointReport::with_fraction(&job, &channel, args.best, args.fraction);
    if report.blind > 0 {
        eprintln!(
            "warning: {}: {} of {} viewpoints see no polygon (seen edge-on, or polygons \
             too small for --resolution); they get p(v) = 0",
            args.file.display(),
            report.blind,
            job.n_views()
        );
    }
    if let Some(path) = &args.ply {
        write_atomic(
            path,
            saliency_ply(&scene, &report, &args.file)
                .finish()?
                .as_bytes(),
        )?;
    }
    if let Some(path) = &args.sphere_ply {
        let ply = sphere_ply(&scene, &job, &report, args.sphere_color);
        write_atomic(path, ply.finish()?.as_bytes())?;
    }
    if let Some(path) = &args.png {
        for (k, &v) in report.best.iter().enumerate() {
            let png = saliency_png(&job, v, &report.saliency, args.png_size).map_err(at)?;
            write_atomic(&numbered(path, k + 1), &png)?;
        }
    }
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", report.to_json())?;
    } else {
        write!(out, "{}", table(args, &scene, &report, seconds, threads))?;
    }
    out.flush()?;
    Ok(())
}

/// Every row of `job` on `threads` threads (rows handed out one at a time), then the channel.
fn run_rows(job: &ViewpointJob<'_>, threads: usize) -> Result<ViewpointChannel> {
    let n_o = job.scene().n_patches();
    let n_v = job.n_views();
    let mut rows = vec![0.0; n_v * n_o];
    let zero = ViewTotals {
        background: 0.0,
        window: 0.0,
    };
    let mut totals = vec![zero; n_v];
    {
        let work = Mutex::new(rows.chunks_mut(n_o).zip(totals.iter_mut()).enumerate());
        let resolution = job.options().resolution;
        std::thread::scope(|s| -> Result<()> {
            let handles: Vec<_> = (0..threads)
                .map(|_| {
                    s.spawn(|| -> Result<()> {
                        let mut raster = IdRaster::new(resolution)?;
                        loop {
                            crate::interrupt::stop_if_requested()?;
                            let next = work
                                .lock()
                                .map_err(|_| anyhow::anyhow!("worker failed"))?
                                .next();
                            let Some((v, (row, total))) = next else {
                                return Ok(());
                            };
                            *total = job.row(v, &mut raster, row)?;
                        }
                    })
                })
                .collect();
            for h in handles {
                h.join()
                    .map_err(|_| anyhow::anyhow!("a worker thread panicked"))??;
            }
            Ok(())
        })?;
    }
    Ok(ViewpointChannel::from_rows(job, rows, totals)?)
}

/// The tables of the best views, the selection and the channel's measures.
fn table(
    args: &ViewpointsArgs,
    scene: &Scene3,
    r: &ViewpointReport,
    seconds: f64,
    threads: usize,
) -> String {
    let mut s = String::new();
    let n_v = r.directions.len();
    let _ = writeln!(
        s,
        "{}: {} polygons, {} viewpoints at {} radii, {}×{} pixels per view, p(v) {}; {:.2} s on {} thread{}",
        args.file.display(),
        scene.n_patches(),
        n_v,
        r.distance,
        r.resolution,
        r.resolution,
        match r.weighting {
            ViewWeighting::Uniform => "uniform",
            ViewWeighting::ProjectedArea => "by projected area",
        },
        seconds,
        threads,
        if threads == 1 { "" } else { "s" }
    );
    let _ = writeln!(
        s,
        "I(V;O) = {:.6}  H(O) = {:.6}  H(O|V) = {:.6}  H(V) = {:.6}  bits; VE max log2(N+1) = {:.6}",
        r.i_vo,
        r.h_o,
        r.h_o_given_v,
        r.h_v,
        (r.n_polygons as f64 + 1.0).log2()
    );
    let dir = |v: usize| r.directions.get(v).copied().unwrap_or_default();
    let _ = writeln!(s, "\nbest views (least VMI)");
    let _ = writeln!(
        s,
        "{:>4} {:>6}  {:>26}  {:>9}  {:>9}  {:>11}  {:>9}",
        "rank", "view", "direction (x, y, z)", "VMI", "VE", "instability", "saliency"
    );
    let row = |s: &mut String, label: &str, v: usize| {
        let d = dir(v);
        let _ = writeln!(
            s,
            "{label:>4} {v:>6}  ({:>7.4}, {:>7.4}, {:>7.4})  {:>9.6}  {:>9.6}  {:>11.3e}  {:>9.3e}",
            d.x,
            d.y,
            d.z,
            r.vmi.get(v).copied().unwrap_or(f64::NAN),
            r.ve.get(v).copied().unwrap_or(f64::NAN),
            r.instability.get(v).copied().unwrap_or(f64::NAN),
            r.viewpoint_saliency.get(v).copied().unwrap_or(f64::NAN),
        );
    };
    for (k, &v) in r.best.iter().enumerate() {
        row(&mut s, &(k + 1).to_string(), v);
    }
    if let Some(worst) = (0..n_v).max_by(|&a, &b| r.vmi[a].total_cmp(&r.vmi[b]).then(b.cmp(&a))) {
        row(&mut s, "max", worst);
    }
    let best_ve = (0..n_v).max_by(|&a, &b| r.ve[a].total_cmp(&r.ve[b]).then(b.cmp(&a)));
    if let Some(v) = best_ve {
        let _ = writeln!(s, "\nbest view by viewpoint entropy (most VE)");
        row(&mut s, "VE", v);
    }
    let _ = writeln!(
        s,
        "\ngreedy selection (each view split off maximises I(V^;O) of the clustered channel)"
    );
    let _ = writeln!(
        s,
        "{:>4} {:>6}  {:>10}  {:>9}",
        "step", "view", "I(V^;O)", "of I(V;O)"
    );
    for (k, &(v, i)) in r.selection.iter().enumerate() {
        let frac = if r.i_vo > 0.0 { i / r.i_vo } else { 1.0 };
        let _ = writeln!(s, "{:>4} {v:>6}  {i:>10.6}  {:>8.2}%", k + 1, 100.0 * frac);
    }
    let _ = writeln!(
        s,
        "\nrepresentative views (each added makes the mixture's VMI I(v^;O) least)"
    );
    let _ = writeln!(s, "{:>4} {:>6}  {:>10}", "step", "view", "I(v^;O)");
    for (k, &(v, i)) in r.representative.iter().enumerate() {
        let _ = writeln!(s, "{:>4} {v:>6}  {i:>10.6}", k + 1);
    }
    let (lo, hi) = range(&r.saliency);
    let _ = writeln!(
        s,
        "\nmesh saliency S(o): min {lo:.4e}, max {hi:.4e}; polygonal MI I(o;V): min {:.4}, max {:.4} bits",
        range(&r.polygonal_mi).0,
        range(&r.polygonal_mi).1
    );
    s
}

fn range(values: &[f64]) -> (f64, f64) {
    values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        })
}

/// The mesh, one polygon per patch coloured by saliency (viridis, min to max).
fn saliency_ply(scene: &Scene3, r: &ViewpointReport, file: &Path) -> Ply {
    let (lo, hi) = range(&r.saliency);
    let scale = Scale::Linear { lo, hi };
    let mut ply = Ply::in_frame(scene.frame());
    ply.comment(&format!("sceneinfo viewpoints {}", file.display()));
    ply.comment("quantity: mesh saliency S(o), Feixas, Sbert, Gonzalez 2009 (bits)");
    ply.comment(&format!("min: {lo}"));
    ply.comment(&format!("max: {hi}"));
    ply.comment("colour map: viridis, linear from min to max");
    for (i, &v) in r.saliency.iter().enumerate() {
        ply.polygon(
            scene.patch_vertices(i),
            ColourMap::Viridis.at(scale.fraction(v)),
        );
    }
    ply
}

/// `path` for the best view; `stem-k.ext` for the k-th best.
fn numbered(path: &Path, k: usize) -> std::path::PathBuf {
    if k == 1 {
        return path.to_path_buf();
    }
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let name = match path.extension() {
        Some(e) => format!("{stem}-{k}.{}", e.to_string_lossy()),
        None => format!("{stem}-{k}"),
    };
    path.with_file_name(name)
}

/// The viewpoint sphere at 1.5 bounding radii around the scene, vertices coloured by the
/// chosen per-view quantity.
fn sphere_ply(
    scene: &Scene3,
    job: &ViewpointJob<'_>,
    r: &ViewpointReport,
    colour: SphereColour,
) -> Ply {
    let (values, name) = match colour {
        SphereColour::Vmi => (&r.vmi, "VMI I(v;O), bits (least: best view)"),
        SphereColour::Ve => (
            &r.ve,
            "viewpoint entropy H(v), bits (most: best view by VE)",
        ),
        SphereColour::Instability => (
            &r.instability,
            "instability: mean JS divergence to the neighbouring viewpoints, bits",
        ),
        SphereColour::Saliency => (&r.viewpoint_saliency, "viewpoint saliency, bits"),
    };
    let (lo, hi) = range(values);
    let scale = Scale::Linear { lo, hi };
    let (centre, radius) = IdRaster::bounding_sphere(scene);
    let mut ply = Ply::in_frame(scene.frame());
    ply.comment(&format!(
        "sceneinfo viewpoints: the viewpoint sphere coloured by {name}"
    ));
    ply.comment(&format!("min: {lo}"));
    ply.comment(&format!("max: {hi}"));
    ply.comment("colour map: viridis, linear from min to max");
    let sphere = job.sphere();
    let ids: Vec<usize> = sphere
        .directions()
        .iter()
        .zip(values)
        .map(|(&d, &v)| {
            ply.vertex(
                centre + d * (1.5 * radius),
                ColourMap::Viridis.at(scale.fraction(v)),
            )
        })
        .collect();
    for t in sphere.triangles() {
        let idx = t.map(|k| ids.get(k as usize).copied().unwrap_or(0));
        let c = t.map(|k| values.get(k as usize).copied().unwrap_or(lo));
        let mean = (c[0] + c[1] + c[2]) / 3.0;
        ply.face(&idx, ColourMap::Viridis.at(scale.fraction(mean)));
    }
    ply
}

/// The mesh seen from viewpoint `v` (the job's projection, `size` pixels), each pixel
/// coloured by its polygon's saliency and shaded by how squarely the polygon faces the
/// viewer; background white.
fn saliency_png(
    job: &ViewpointJob<'_>,
    v: usize,
    saliency: &[f64],
    size: u32,
) -> sceneinfo::Result<Vec<u8>> {
    let scene = job.scene();
    let mut raster = IdRaster::new(size)?;
    let mut areas = vec![0.0; scene.n_patches()];
    let projection = job.projection(v)?;
    raster.project(scene, &projection, &mut areas)?;
    let view = job
        .sphere()
        .directions()
        .get(v)
        .copied()
        .unwrap_or(DVec3::Z);
    let (lo, hi) = range(saliency);
    let scale = Scale::Linear { lo, hi };
    let mut rgb = Vec::with_capacity(raster.ids().len() * 3);
    for &id in raster.ids() {
        let Some(p) = scene.patches().get(id as usize) else {
            rgb.extend([255, 255, 255]);
            continue;
        };
        let Rgb(r, g, b) = ColourMap::Viridis.at(scale.fraction(saliency[id as usize]));
        let shade = 0.35 + 0.65 * p.normal.dot(view).abs();
        let s = |c: u8| (f64::from(c) * shade).round().clamp(0.0, 255.0) as u8;
        rgb.extend([s(r), s(g), s(b)]);
    }
    crate::png::encode_rgb(size, size, &rgb).ok_or_else(|| {
        sceneinfo::ErrorKind::TooLarge {
            what: "picture",
            max: u64::from(sceneinfo::viewpoint::IdRaster::MAX_RESOLUTION),
        }
        .into()
    })
}
