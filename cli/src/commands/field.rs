//! `sceneinfo field`: entropy and mutual-information fields at interior points of a flatland
//! scene (thesis §7.3; `sceneinfo::field`): at a point, over a grid (table, JSON, PNG map)
//! and along a camera path (its animation complexity).

use std::fmt::Write as _;
use std::io::Write;
use std::path::PathBuf;

use anyhow::{Result, bail};
use std::f64::consts::TAU;

use sceneinfo::field::{
    Field2, Field3, Field3Scratch, FieldGrid, FieldPath, FieldScratch, PointField,
};
use sceneinfo::geom::{DVec2, DVec3};
use sceneinfo_report::JsonObject;

use crate::output::{Loaded, job_refused, located, write_atomic};
use crate::svg::{ColourMap, Rgb};

/// Arguments of `field`.
#[derive(Debug, clap::Args)]
#[command(group(clap::ArgGroup::new("where").required(true).multiple(true)
    .args(["grid", "path", "at"])))]
pub struct FieldArgs {
    /// The scene: flatland (`.flat`; exact fields) or 3D (OBJ, glTF, PLY; rasterised, --at
    /// and --path only).
    pub file: PathBuf,
    /// Evaluate the field at the centres of a grid of N cells along the longer side of the
    /// scene's bounding box (square cells).
    #[arg(long, value_name = "N",
          value_parser = clap::value_parser!(u32).range(1..=sceneinfo::field::FieldGrid::MAX_SIDE as i64))]
    pub grid: Option<u32>,
    /// A camera path `x0,y0:x1,y1[:x2,y2…]` (world coordinates; `x,y,z` points in 3D): the
    /// field along it and its animation complexity ∫ I(x) ds.
    #[arg(long, value_name = "x0,y0:x1,y1", value_parser = parse_path)]
    pub path: Option<Polyline>,
    /// Samples per leg of --path (trapezoid rule).
    #[arg(long, value_name = "K", default_value_t = 256,
          value_parser = clap::value_parser!(u32).range(1..=65_536))]
    pub samples: u32,
    /// One point `x,y` (flatland) or `x,y,z` (3D): its measures and `p(j|x)` of the
    /// patches it sees.
    #[arg(long, value_name = "x,y[,z]", value_parser = parse_point)]
    pub at: Option<Coords>,
    /// 3D scenes: side of each cube-map face in pixels (the raster error of a patch's solid
    /// angle halves with each doubling).
    #[arg(long, value_name = "N", default_value_t = 256,
          value_parser = clap::value_parser!(u32).range(1..=i64::from(sceneinfo::viewpoint::IdRaster::MAX_RESOLUTION)))]
    pub resolution: u32,
    /// Which measure colours the --png map.
    #[arg(long, value_enum, default_value_t = FieldMeasure::I)]
    pub measure: FieldMeasure,
    /// Write the --grid map as a PNG (viridis from the least to the greatest value; grey
    /// where the measure is undefined; the surfaces in white).
    #[arg(long, value_name = "OUT.png", requires = "grid")]
    pub png: Option<PathBuf>,
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
}

/// `--measure` of `field`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum FieldMeasure {
    /// Point entropy H(x).
    H,
    /// Point mutual information I(x).
    I,
    /// Continuous point mutual information I^c(x).
    Ic,
    /// Discretisation error I^c(x) − I(x).
    De,
}

impl FieldMeasure {
    fn of(self, p: &PointField) -> Option<f64> {
        match self {
            Self::H => Some(p.h),
            Self::I => p.i,
            Self::Ic => p.i_c,
            Self::De => p.discretisation_error(),
        }
    }

    fn name(self) -> &'static str {
        match self {
            Self::H => "H(x)",
            Self::I => "I(x)",
            Self::Ic => "I^c(x)",
            Self::De => "I^c(x) - I(x)",
        }
    }
}

/// A point's coordinates as given: 2 (flatland) or 3 (3D) finite numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct Coords(pub Vec<f64>);

/// Parses `x,y` or `x,y,z` into finite coordinates.
pub fn parse_point(s: &str) -> Result<Coords, String> {
    let bad = || format!("'{s}' is not a point x,y or x,y,z (finite numbers)");
    let c: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|_| bad()))
        .collect::<Result<_, _>>()?;
    if (2..=3).contains(&c.len()) && c.iter().all(|v| v.is_finite()) {
        Ok(Coords(c))
    } else {
        Err(bad())
    }
}

/// The vertices of `--path`.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline(pub Vec<Vec<f64>>);

/// Parses `x0,y0:x1,y1[:…]` (at least two points, at most 10,000).
pub fn parse_path(s: &str) -> Result<Polyline, String> {
    let points: Vec<Vec<f64>> = s
        .split(':')
        .map(|p| parse_point(p).map(|c| c.0))
        .collect::<Result<_, _>>()?;
    if !(2..=10_000).contains(&points.len()) {
        return Err(format!(
            "'{s}' is not a path x0,y0:x1,y1[:…] of 2 to 10000 points"
        ));
    }
    Ok(Polyline(points))
}

pub fn run(args: &FieldArgs) -> Result<()> {
    let loaded = crate::output::load_scene(&args.file)?;
    loaded.print_warnings(&args.file, false);
    let at = |e: sceneinfo::Error| located(&args.file, &e);
    let dims = |c: &[f64], want: usize, what: &str| -> Result<()> {
        if c.len() == want {
            Ok(())
        } else {
            Err(job_refused(
                &args.file,
                format!("{what} needs {want} coordinates in a {want}D scene"),
            ))
        }
    };
    let mut report = Report::default();
    match &loaded.scene {
        Loaded::Flat(scene) => {
            let field = Field2::new(scene).map_err(at)?;
            report.header = format!(
                "{}: {} patches, {} surfaces{}",
                args.file.display(),
                scene.n_patches(),
                scene.surfaces().len(),
                if field.weights().last().is_some_and(|&w| w > 0.0) {
                    ", open (background state)"
                } else {
                    ""
                }
            );
            report.patches = scene.n_patches();
            report.background = field.weights().last().is_some_and(|&w| w > 0.0);
            if let Some(c) = &args.at {
                dims(&c.0, 2, "--at")?;
                let mut scratch = FieldScratch::default();
                let p = field
                    .point(DVec2::new(c.0[0], c.0[1]), &mut scratch)
                    .map_err(at)?;
                let probs = scratch.angles().iter().map(|a| a / TAU).collect();
                report.point = Some((c.0.clone(), p, probs));
            }
            if let Some(n) = args.grid {
                let g = field.grid_over_scene(n as usize).map_err(at)?;
                if let Some(out) = &args.png {
                    write_atomic(out, &picture(&field, &g, args.measure)?)?;
                }
                report.grid = Some(g);
            }
            if let Some(v) = &args.path {
                let mut vertices = Vec::new();
                for c in &v.0 {
                    dims(c, 2, "--path")?;
                    vertices.push(DVec2::new(c[0], c[1]));
                }
                report.path = Some(field.path(&vertices, args.samples as usize).map_err(at)?);
            }
        }
        Loaded::Solid(scene) => {
            if args.grid.is_some() {
                return Err(job_refused(
                    &args.file,
                    "--grid is flatland only (a 3D plane slice is not implemented); use --at or --path",
                ));
            }
            let field = Field3::new(scene);
            let mut scratch = Field3Scratch::new(args.resolution).map_err(at)?;
            report.header = format!(
                "{}: {} patches (3D, rasterised: cube faces of {}² pixels; I^c not computed in 3D)",
                args.file.display(),
                scene.n_patches(),
                args.resolution
            );
            report.patches = scene.n_patches();
            if let Some(c) = &args.at {
                dims(&c.0, 3, "--at")?;
                let x = DVec3::new(c.0[0], c.0[1], c.0[2]);
                let p = field.point(x, &mut scratch).map_err(at)?;
                let probs = scratch
                    .solid_angles()
                    .iter()
                    .map(|a| a / (2.0 * TAU))
                    .collect();
                report.point = Some((c.0.clone(), p, probs));
            }
            if let Some(v) = &args.path {
                let mut vertices = Vec::new();
                for c in &v.0 {
                    dims(c, 3, "--path")?;
                    vertices.push(DVec3::new(c[0], c[1], c[2]));
                }
                let path = field.path(&vertices, args.samples as usize, &mut scratch);
                report.path = Some(path.map_err(at)?);
            }
        }
    }
    report.print(&args.file, args.json)
}

/// What `field` prints.
#[derive(Default)]
struct Report {
    header: String,
    patches: usize,
    background: bool,
    /// The point, its measures, `p(j|x)` per patch then the background's.
    point: Option<(Vec<f64>, PointField, Vec<f64>)>,
    grid: Option<FieldGrid>,
    path: Option<FieldPath>,
}

impl Report {
    fn print(&self, file: &std::path::Path, json: bool) -> Result<()> {
        let mut out = std::io::stdout().lock();
        if json {
            let mut s = String::new();
            let mut o = JsonObject::new(&mut s)?;
            o.string("file", &file.display().to_string())?;
            o.integer("patches", self.patches as u64)?;
            o.boolean("background", self.background)?;
            if let Some((x, p, probs)) = &self.point {
                o.object("at", |o| {
                    o.numbers("x", x)?;
                    point_fields(o, p)?;
                    // p(j|x) per patch, then the background's
                    o.numbers("p", probs)
                })?;
            }
            if let Some(g) = &self.grid {
                o.object("grid", |o| grid_fields(o, g))?;
            }
            if let Some(p) = &self.path {
                o.object("path", |o| path_fields(o, p))?;
            }
            o.finish()?;
            writeln!(out, "{s}")?;
        } else {
            let mut s = String::new();
            writeln!(s, "{}", self.header)?;
            if let Some((x, p, probs)) = &self.point {
                point_table(&mut s, x, p, probs)?;
            }
            if let Some(g) = &self.grid {
                grid_table(&mut s, g)?;
            }
            if let Some(p) = &self.path {
                path_table(&mut s, p)?;
            }
            write!(out, "{s}")?;
        }
        out.flush()?;
        Ok(())
    }
}

fn point_fields<W: std::fmt::Write>(o: &mut JsonObject<'_, W>, p: &PointField) -> std::fmt::Result {
    o.number("h", p.h)?;
    o.number("i", p.i.unwrap_or(f64::NAN))?;
    o.number("i_c", p.i_c.unwrap_or(f64::NAN))?;
    o.number(
        "discretisation_error",
        p.discretisation_error().unwrap_or(f64::NAN),
    )?;
    o.number("p_background", p.background)?;
    o.integer("seen", p.seen as u64)
}

fn grid_fields<W: std::fmt::Write>(o: &mut JsonObject<'_, W>, g: &FieldGrid) -> std::fmt::Result {
    o.integer("nx", g.nx as u64)?;
    o.integer("ny", g.ny as u64)?;
    o.numbers("lo", &[g.lo.x, g.lo.y])?;
    o.numbers("hi", &[g.hi.x, g.hi.y])?;
    for m in [
        FieldMeasure::H,
        FieldMeasure::I,
        FieldMeasure::Ic,
        FieldMeasure::De,
    ] {
        let key = match m {
            FieldMeasure::H => "h",
            FieldMeasure::I => "i",
            FieldMeasure::Ic => "i_c",
            FieldMeasure::De => "discretisation_error",
        };
        let values: Vec<f64> = g
            .cells
            .iter()
            .map(|p| m.of(p).unwrap_or(f64::NAN))
            .collect();
        o.numbers(key, &values)?;
    }
    Ok(())
}

fn path_fields<W: std::fmt::Write>(o: &mut JsonObject<'_, W>, p: &FieldPath) -> std::fmt::Result {
    o.number("length", p.length)?;
    o.integer("samples", p.samples.len() as u64)?;
    o.number("animation_complexity", p.i_integral.unwrap_or(f64::NAN))?;
    o.number("mean_i", p.mean_i().unwrap_or(f64::NAN))?;
    o.number("h_integral", p.h_integral)?;
    o.number("mean_h", p.mean_h().unwrap_or(f64::NAN))?;
    o.number("i_c_integral", p.i_c_integral.unwrap_or(f64::NAN))?;
    o.numbers("s", &p.arc)?;
    let col = |f: &dyn Fn(&PointField) -> Option<f64>| -> Vec<f64> {
        p.samples.iter().map(|q| f(q).unwrap_or(f64::NAN)).collect()
    };
    o.numbers("h", &col(&|q| Some(q.h)))?;
    o.numbers("i", &col(&|q| q.i))?;
    o.numbers("i_c", &col(&|q| q.i_c))
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "undefined".to_string(), |v| format!("{v:.6}"))
}

/// Rows of the patch list printed in full; beyond, the largest this many.
const LISTED: usize = 40;

fn point_table(s: &mut String, x: &[f64], p: &PointField, probs: &[f64]) -> std::fmt::Result {
    let coords: Vec<String> = x.iter().map(ToString::to_string).collect();
    writeln!(s, "\npoint ({})", coords.join(", "))?;
    writeln!(s, "  H(x)            {:.6} bits", p.h)?;
    writeln!(s, "  I(x)            {}", opt(p.i))?;
    writeln!(s, "  I^c(x)          {}", opt(p.i_c))?;
    writeln!(s, "  I^c(x) - I(x)   {}", opt(p.discretisation_error()))?;
    writeln!(s, "  p(background)   {:.6}", p.background)?;
    writeln!(s, "  patches seen    {}", p.seen)?;
    let last = probs.len().saturating_sub(1);
    let mut rows: Vec<usize> = (0..probs.len()).filter(|&j| probs[j] > 0.0).collect();
    if rows.len() > LISTED {
        writeln!(s, "  the {LISTED} largest:")?;
        rows.sort_by(|&a, &b| probs[b].total_cmp(&probs[a]).then(a.cmp(&b)));
        rows.truncate(LISTED);
    }
    writeln!(s, "  patch   p(j|x)")?;
    for j in rows {
        let name = if j == last {
            "bg".to_string()
        } else {
            j.to_string()
        };
        writeln!(s, "  {name:>5}   {:.6}", probs[j])?;
    }
    Ok(())
}

fn grid_table(s: &mut String, g: &FieldGrid) -> std::fmt::Result {
    let undefined = g.cells.iter().filter(|p| p.i.is_none()).count();
    writeln!(
        s,
        "\ngrid {} x {} over ({}, {})..({}, {}): {} cells, {} outside (I undefined)",
        g.nx,
        g.ny,
        g.lo.x,
        g.lo.y,
        g.hi.x,
        g.hi.y,
        g.cells.len(),
        undefined
    )?;
    writeln!(s, "  measure          min        mean       max")?;
    for m in [
        FieldMeasure::H,
        FieldMeasure::I,
        FieldMeasure::Ic,
        FieldMeasure::De,
    ] {
        let v: Vec<f64> = g.cells.iter().filter_map(|p| m.of(p)).collect();
        if v.is_empty() {
            writeln!(s, "  {:<14}   undefined", m.name())?;
            continue;
        }
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        writeln!(s, "  {:<14} {lo:>9.4}  {mean:>9.4}  {hi:>9.4}", m.name())?;
    }
    Ok(())
}

fn path_table(s: &mut String, p: &FieldPath) -> std::fmt::Result {
    writeln!(
        s,
        "\npath: length {:.6}, {} samples",
        p.length,
        p.samples.len()
    )?;
    writeln!(
        s,
        "  animation complexity  C = ∫ I(x) ds   {}",
        opt(p.i_integral)
    )?;
    writeln!(
        s,
        "  mean I along the path  C / length    {}",
        opt(p.mean_i())
    )?;
    writeln!(
        s,
        "  ∫ H(x) ds                             {:.6}",
        p.h_integral
    )?;
    writeln!(
        s,
        "  mean H                                {}",
        opt(p.mean_h())
    )?;
    writeln!(
        s,
        "  ∫ I^c(x) ds                           {}",
        opt(p.i_c_integral)
    )?;
    Ok(())
}

/// The grid as a PNG: `k × k` pixels a cell (about 512 pixels along the longer side), rows
/// from the top (greatest y), surfaces drawn over it.
fn picture(field: &Field2<'_>, g: &FieldGrid, measure: FieldMeasure) -> Result<Vec<u8>> {
    let k = (512 / g.nx.max(g.ny)).max(1);
    let (w, h) = (g.nx * k, g.ny * k);
    let values: Vec<Option<f64>> = g.cells.iter().map(|p| measure.of(p)).collect();
    let (lo, hi) = values
        .iter()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    let mut rgb = vec![0u8; 3 * w * h];
    let mut put = |px: usize, py: usize, c: Rgb| {
        if px < w && py < h {
            let at = 3 * (py * w + px);
            rgb[at..at + 3].copy_from_slice(&[c.0, c.1, c.2]);
        }
    };
    for r in 0..g.ny {
        for c in 0..g.nx {
            let colour = match values[r * g.nx + c] {
                Some(v) if hi > lo => ColourMap::Viridis.at((v - lo) / (hi - lo)),
                Some(_) => ColourMap::Viridis.at(0.5),
                None => Rgb(0x80, 0x80, 0x80),
            };
            let top = (g.ny - 1 - r) * k;
            for dy in 0..k {
                for dx in 0..k {
                    put(c * k + dx, top + dy, colour);
                }
            }
        }
    }
    // The surfaces, world → pixels
    let scene = field.scene();
    let size = g.hi - g.lo;
    let to_px = |p: DVec2| {
        let q = scene.frame().to_world_2d(p) - g.lo;
        let fx = if size.x > 0.0 { q.x / size.x } else { 0.5 };
        let fy = if size.y > 0.0 { q.y / size.y } else { 0.5 };
        (fx * w as f64, (1.0 - fy) * h as f64)
    };
    for surf in scene.surfaces() {
        let (a, b) = (to_px(surf.segment.a), to_px(surf.segment.b));
        let steps = (2.0 * (b.0 - a.0).abs().max((b.1 - a.1).abs()))
            .ceil()
            .clamp(1.0, 1e5) as usize;
        for m in 0..=steps {
            let t = m as f64 / steps as f64;
            let (x, y) = (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t);
            let (x, y) = (
                x.floor().clamp(0.0, (w - 1) as f64),
                y.floor().clamp(0.0, (h - 1) as f64),
            );
            put(x as usize, y as usize, Rgb(0xff, 0xff, 0xff));
        }
    }
    match crate::png::encode_rgb(w as u32, h as u32, &rgb) {
        Some(png) => Ok(png),
        None => bail!("field: empty picture"),
    }
}
