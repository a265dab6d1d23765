//! `sceneinfo reproduce`: the thesis' tables, ours beside theirs.
//!
//! Chapter 3: Tables 3.4 and 3.5 (exact form factors). Chapter 4: Tables 4.10, 4.11 and 4.12
//! and the flatland catalogue of §4.5.2 (global lines; `--lines` per scene, fixed seed).
//! Chapter 5 (the radiosity channel) lives in [`chapter5`].
//! Chapter 6 ([`refinement_flat`]): the single cuts of §6.1, and in flatland Fig. 6.12,
//! Tables 6.1 and 6.2, Fig. 6.19; in 3D ([`chapter6_hierarchy`]) Figs. 6.6 and 6.9, the
//! oracles of hierarchical radiosity compared on the Cornell box; by the thesis' own protocol
//! (hierarchical Monte Carlo radiosity, `--chapter-6-mc`) in [`chapter6_mc`].

use std::fmt::Write as _;
use std::io::Write;
use std::time::Instant;

use anyhow::{Result, anyhow};
use sceneinfo::continuous::closed_form;
use sceneinfo::formfactor::quadrature::{ContinuousQuadrature, QuadratureOptions};
use sceneinfo::scene::{CatalogueEntry, Scene2, Scene3};
use sceneinfo::trace::estimate_2d::{LineEstimate, LineMethod, Tracer2};
use sceneinfo::trace::estimate_3d::Tracer3;
use sceneinfo_report::JsonObject;
use sceneinfo_report::thesis::{
    PLATONIC_REFERENCE, POLYGON_PER_SIDE, POLYGON_SIDES, TABLE_3_3, TABLE_3_4_H_S, TABLE_3_5_I_S,
    TABLE_3_8, TABLE_4_1, TABLE_4_2, TABLE_4_3_FEW_LINES, TABLE_4_10_I_S_CONTINUOUS, TABLE_4_11,
    TABLE_4_12,
};

use crate::args::ReproduceArgs;

mod chapter5;
mod chapter6_hierarchy;
mod chapter6_mc;
mod chapter6_room;
mod pictured3d;
mod refinement_flat;

/// One row of a reproduced table: a label, our values, the thesis' values (NaN = none).
struct Row {
    label: String,
    cells: Vec<Cell>,
}

/// One compared number.
struct Cell {
    column: &'static str,
    ours: f64,
    /// Standard error of ours (0 for exact values).
    stderr: f64,
    thesis: Option<f64>,
}

/// A reproduced table.
struct Table {
    key: &'static str,
    title: String,
    rows: Vec<Row>,
}

fn cell(column: &'static str, ours: f64, stderr: f64, thesis: Option<f64>) -> Cell {
    Cell {
        column,
        ours,
        stderr,
        thesis,
    }
}

/// Everything a Monte Carlo table needs to know about the run.
struct Runner {
    lines: u64,
    seed: u64,
    threads: usize,
}

impl Runner {
    fn estimate(&self, scene: &Scene2, lines: u64) -> Result<LineEstimate> {
        let tracer = Tracer2::new(scene).map_err(|e| anyhow!("{e}"))?;
        let tally = crate::lines::run(&tracer, LineMethod::Global, self.seed, lines, self.threads);
        crate::interrupt::stop_if_requested()?;
        tally.finish(&tracer).map_err(|e| anyhow!("{e}"))
    }

    /// `(I_S^c, standard error)` of a scene.
    fn continuous(&self, scene: &Scene2) -> Result<(f64, f64)> {
        let e = self.estimate(scene, self.lines)?;
        Ok((e.continuous.value, e.continuous.stderr))
    }
}

pub fn run(args: &ReproduceArgs, threads: usize) -> Result<()> {
    let start = Instant::now();
    let runner = Runner {
        lines: args.lines,
        seed: args.seed,
        threads,
    };
    sceneinfo::LineJob::check_lines(runner.lines).map_err(|e| anyhow!("{e}"))?;
    let mut tables = if args.chapter_6_mc {
        chapter6_mc::tables(&runner, args)?
    } else if args.chapter_5_only {
        chapter5::tables(&runner, args.full)?
    } else {
        chapter_3()?
    };
    if !args.chapter_3_only && !args.chapter_5_only && !args.chapter_6_mc {
        tables.push(table_4_10(&runner)?);
        tables.push(table_4_11(&runner)?);
        tables.push(table_4_12(&runner)?);
        tables.push(catalogue_table(&runner)?);
        tables.push(table_3_8(&runner, args.full)?);
        tables.push(table_4_1(&runner)?);
        tables.push(table_4_2(&runner)?);
        tables.push(pictured3d::table_4_4(&runner, args.full)?);
        tables.push(pictured3d::table_4_5()?);
        tables.push(pictured3d::table_4_6(&runner, args.full)?);
        tables.push(pictured3d::table_4_7(&runner, args.full)?);
        if args.full {
            tables.push(table_3_3(&runner)?);
        }
        tables.extend(chapter5::tables(&runner, args.full)?);
        tables.push(refinement_flat::section_6_1()?);
        tables.push(refinement_flat::table_6_1()?);
        tables.extend(refinement_flat::table_6_2(&runner)?);
        tables.push(chapter6_hierarchy::figures_6_6_and_6_9(&runner)?);
    }
    let seconds = start.elapsed().as_secs_f64();
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", json(&tables, &runner, seconds)?)?;
    } else {
        for t in &tables {
            write!(out, "{}", text(t))?;
        }
        writeln!(
            out,
            "Monte Carlo: {} global lines per scene, seed {}; ± is one standard error.",
            runner.lines, runner.seed
        )?;
        writeln!(out, "computed in {seconds:.1} s")?;
    }
    out.flush()?;
    Ok(())
}

/// Tables 3.4 and 3.5: `H_S` and `I_S` of regular polygons with exact form factors.
fn chapter_3() -> Result<Vec<Table>> {
    let mut h_rows = Vec::new();
    let mut i_rows = Vec::new();
    for (r, &sides) in POLYGON_SIDES.iter().enumerate() {
        let mut h = Vec::new();
        let mut i = Vec::new();
        for (c, &k) in POLYGON_PER_SIDE.iter().enumerate() {
            let m =
                exact_measures(&Scene2::regular_polygon(sides, k).map_err(|e| anyhow!("{e}"))?)?;
            let col = ["10/side", "30/side", "50/side"][c];
            h.push(cell(col, m.h_s, 0.0, Some(TABLE_3_4_H_S[r][c])));
            i.push(cell(col, m.i_s, 0.0, Some(TABLE_3_5_I_S[r][c])));
        }
        h_rows.push(Row {
            label: format!("{sides} sides"),
            cells: h,
        });
        i_rows.push(Row {
            label: format!("{sides} sides"),
            cells: i,
        });
    }
    Ok(vec![
        Table {
            key: "table_3_4",
            title: "Table 3.4: H_S of regular polygons (exact form factors)".into(),
            rows: h_rows,
        },
        Table {
            key: "table_3_5",
            title: "Table 3.5: I_S of regular polygons (exact form factors)".into(),
            rows: i_rows,
        },
    ])
}

fn exact_measures(scene: &Scene2) -> Result<sceneinfo::channel::Measures> {
    Ok(sceneinfo_report::measure_flat(scene)
        .map_err(|e| anyhow!("{e}"))?
        .measures)
}

/// Table 4.10: `I_S^c` of regular polygons (one patch per side: `I_S^c` does not depend on
/// the discretisation).
fn table_4_10(runner: &Runner) -> Result<Table> {
    let mut rows = Vec::new();
    for (r, &sides) in POLYGON_SIDES.iter().enumerate() {
        let scene = Scene2::regular_polygon(sides, 1).map_err(|e| anyhow!("{e}"))?;
        let (v, e) = runner.continuous(&scene)?;
        rows.push(Row {
            label: format!("{sides} sides"),
            cells: vec![cell("I_S^c", v, e, Some(TABLE_4_10_I_S_CONTINUOUS[r]))],
        });
    }
    Ok(Table {
        key: "table_4_10",
        title: "Table 4.10: I_S^c of regular polygons".into(),
        rows,
    })
}

/// Table 4.11: closed forms, our global-line estimate, and the thesis' two columns.
fn table_4_11(runner: &Runner) -> Result<Table> {
    let shapes: [(f64, usize); 4] = [
        (closed_form::Enclosure::Circle.i_s_continuous(), 512),
        (closed_form::Enclosure::RegularHexagon.i_s_continuous(), 6),
        (closed_form::Enclosure::Square.i_s_continuous(), 4),
        (
            closed_form::Enclosure::EquilateralTriangle.i_s_continuous(),
            3,
        ),
    ];
    let mut rows = Vec::new();
    for ((name, exact, mc), (ours_exact, sides)) in TABLE_4_11.iter().zip(shapes) {
        let scene = Scene2::regular_polygon(sides, 1).map_err(|e| anyhow!("{e}"))?;
        let (v, e) = runner.continuous(&scene)?;
        let label = if sides == 512 {
            format!("{name} (as a 512-gon)")
        } else {
            (*name).to_string()
        };
        rows.push(Row {
            label,
            cells: vec![
                cell("exact", ours_exact, 0.0, Some(*exact)),
                cell("MC", v, e, Some(*mc)),
            ],
        });
    }
    Ok(Table {
        key: "table_4_11",
        title: "Table 4.11: exact I_S^c (closed forms) and Monte Carlo".into(),
        rows,
    })
}

/// Table 4.12: Proposition 2 on the last steps of the rotating square and the pentagonal
/// star.
fn table_4_12(runner: &Runner) -> Result<Table> {
    let last = sceneinfo::scene::CatalogueEntry::SINGULARITY_STEPS - 1;
    let per_side = 10;
    let cases = [
        (
            Scene2::rotating_square_subscene(per_side),
            Scene2::rotating_square(last, per_side),
        ),
        (
            Scene2::pentagonal_star_subscene(per_side),
            Scene2::pentagonal_star(last, per_side),
        ),
    ];
    let mut rows = Vec::new();
    for ((name, sub_thesis, n, whole_thesis), (sub, whole)) in TABLE_4_12.iter().zip(cases) {
        let sub = sub.map_err(|e| anyhow!("{e}"))?;
        let whole = whole.map_err(|e| anyhow!("{e}"))?;
        let (vs, es) = runner.continuous(&sub)?;
        let (vw, ew) = runner.continuous(&whole)?;
        let log_n = f64::from(*n).log2();
        rows.push(Row {
            label: (*name).to_string(),
            cells: vec![
                cell("I^c subscene", vs, es, Some(*sub_thesis)),
                cell("+ log2 N", vs + log_n, es, Some(sub_thesis + log_n)),
                cell("I_S^c", vw, ew, Some(*whole_thesis)),
            ],
        });
    }
    Ok(Table {
        key: "table_4_12",
        title: "Table 4.12: Proposition 2, I_S^c(scene) = I^c(subscene) + log2 N".into(),
        rows,
    })
}

/// The catalogue of §4.5.2 (and Fig. 3.12): `I_S^c` of every scene, with the thesis' value
/// where it prints one.
fn catalogue_table(runner: &Runner) -> Result<Table> {
    let mut rows = Vec::new();
    for entry in CatalogueEntry::all() {
        let scene =
            Scene2::catalogue(entry.name, 10).map_err(|e| anyhow!("{}: {e}", entry.name))?;
        let thesis_value = sceneinfo_report::thesis::catalogue_value(entry.name);
        let mut cells = Vec::new();
        if entry.name.starts_with("64-squares") {
            // The thesis' value for these is the discrete I_S from 10⁶ global lines.
            let est = runner.estimate(&scene, 1_000_000)?;
            let i_s = est
                .form_factors
                .channel()
                .map_err(|e| anyhow!("{e}"))?
                .i_s();
            let exact = exact_measures(&scene)?.i_s;
            cells.push(cell("I_S (1e6 lines)", i_s, 0.0, thesis_value));
            cells.push(cell("I_S exact", exact, 0.0, None));
            cells.push(cell(
                "I_S^c",
                est.continuous.value,
                est.continuous.stderr,
                None,
            ));
        } else {
            let (v, e) = runner.continuous(&scene)?;
            cells.push(cell("I_S^c", v, e, thesis_value));
        }
        rows.push(Row {
            label: format!("{} ({}: {})", entry.name, entry.figure, entry.description),
            cells,
        });
    }
    Ok(Table {
        key: "catalogue",
        title: "§4.5.2 and Fig. 3.12: the flatland catalogue (I_S^c; thesis values where printed)"
            .into(),
        rows,
    })
}

impl Runner {
    /// `I_S^c` of a 3D scene (no form factors: small patches may stay unsampled).
    fn continuous_3d(&self, scene: &Scene3) -> Result<sceneinfo::continuous::ContinuousEstimate> {
        let tracer = Tracer3::new(scene).map_err(|e| anyhow!("{e}"))?;
        let tally = crate::lines::run(
            &tracer,
            LineMethod::Global,
            self.seed,
            self.lines,
            self.threads,
        );
        crate::interrupt::stop_if_requested()?;
        Ok(tally.continuous())
    }

    fn estimate_3d(&self, scene: &Scene3, lines: u64) -> Result<LineEstimate> {
        let tracer = Tracer3::new(scene).map_err(|e| anyhow!("{e}"))?;
        let tally = crate::lines::run(&tracer, LineMethod::Global, self.seed, lines, self.threads);
        crate::interrupt::stop_if_requested()?;
        tally.finish(&tracer).map_err(|e| anyhow!("{e}"))
    }
}

/// Exact measures of an unoccluded 3D scene.
fn exact_3d(scene: &Scene3) -> Result<sceneinfo::channel::Measures> {
    let ff = crate::output::exact_3d_form_factors(std::path::Path::new("<preset>"), scene)?;
    Ok(ff.channel().map_err(|e| anyhow!("{e}"))?.measures())
}

/// Tables 3.2 and 3.8: the empty cube with 600, 2400 (and with `--full` 5400) patches —
/// exact form factors beside the thesis' 10⁹-line values, the `E(MSE)` ratios, and with
/// `--full` our global-line estimate with the thesis' 10⁷ lines beside its 10⁷-line row.
fn table_3_8(runner: &Runner, full: bool) -> Result<Table> {
    let grids: &[(u32, usize)] = if full {
        &[(10, 600), (20, 2400), (30, 5400)]
    } else {
        &[(10, 600), (20, 2400)]
    };
    let mut rows = Vec::new();
    let mut e_mse_600 = None;
    for &(grid, n) in grids {
        let cube = Scene3::cube(grid).map_err(|e| anyhow!("{e}"))?;
        let m = exact_3d(&cube)?;
        let row9 = TABLE_3_8.iter().find(|r| r.0 == n && r.1 == 1e9).copied();
        let row7 = TABLE_3_8.iter().find(|r| r.0 == n && r.1 == 1e7).copied();
        let mut cells = vec![
            cell("H_S exact", m.h_s, 0.0, row9.map(|r| r.2)),
            cell("I_S exact", m.i_s, 0.0, row9.map(|r| r.3)),
        ];
        match e_mse_600 {
            None => e_mse_600 = Some(m.e_mse),
            Some(base) => {
                let thesis = row9.map(|r| r.4 / TABLE_3_8[2].4);
                cells.push(cell("E(MSE) ratio to 600", m.e_mse / base, 0.0, thesis));
            }
        }
        if let Some(few) = TABLE_4_3_FEW_LINES.iter().find(|r| r.0 == n) {
            let e = runner.estimate_3d(&cube, 100_000)?;
            let mc = e
                .form_factors
                .channel()
                .map_err(|e| anyhow!("{e}"))?
                .measures();
            cells.push(cell("H_S 1e5 lines", mc.h_s, 0.0, Some(few.1)));
            cells.push(cell("I_S 1e5 lines", mc.i_s, 0.0, Some(few.2)));
        }
        if full {
            let e = runner.estimate_3d(&cube, 10_000_000)?;
            let mc = e
                .form_factors
                .channel()
                .map_err(|e| anyhow!("{e}"))?
                .measures();
            cells.push(cell("H_S 1e7 lines", mc.h_s, 0.0, row7.map(|r| r.2)));
            cells.push(cell("I_S 1e7 lines", mc.i_s, 0.0, row7.map(|r| r.3)));
        }
        rows.push(Row {
            label: format!("cube {n} patches"),
            cells,
        });
    }
    if let Some(base) = e_mse_600 {
        rows.push(Row {
            label: "E(MSE) factor thesis/ours (600)".into(),
            cells: vec![cell("factor", TABLE_3_8[2].4 / base, 0.0, None)],
        });
    }
    Ok(Table {
        key: "table_3_8",
        title: "Tables 3.2, 3.8 and 4.3: the empty cube (exact form factors, 1e5-line estimates; --full adds 5400 patches and 1e7-line estimates). The thesis' line counts behave like 0.93 times ours (9.3e4 of our lines reproduce its 1e5 rows)".into(),
        rows,
    })
}

/// Table 4.1: `I_S^c` of the platonic solids and the Cornell box, beside the thesis and, for
/// the regular solids, the independent references the issue tracker quotes.
fn table_4_1(runner: &Runner) -> Result<Table> {
    let mut rows = Vec::new();
    for (name, thesis) in TABLE_4_1 {
        let (scene, preset) = match name {
            "sphere" => {
                // The exact spherical-patches model: independence, I_S = I_S^c = 0.
                let ff = sceneinfo::FormFactors::spherical_patches(&[1.0; 64])
                    .map_err(|e| anyhow!("{e}"))?;
                let i_s = ff.channel().map_err(|e| anyhow!("{e}"))?.i_s();
                rows.push(Row {
                    label: "sphere (exact spherical-patches model, 64 patches)".into(),
                    cells: vec![cell("I_S", i_s, 0.0, Some(thesis))],
                });
                continue;
            }
            "Cornell box" => (Scene3::preset("cornell-lifted", 1), "cornell-lifted"),
            other => (Scene3::preset(other, 1), other),
        };
        let scene = scene.map_err(|e| anyhow!("{e}"))?;
        let c = runner
            .estimate_3d(&scene, runner.lines.max(1_000_000))?
            .continuous;
        let mut cells = vec![cell("I_S^c", c.value, c.stderr, Some(thesis))];
        if let Some((_, reference, _)) = PLATONIC_REFERENCE.iter().find(|r| r.0 == name) {
            // Our deterministic reference: quadrature of (4.6), error estimate ≤ 1e-5.
            let q = ContinuousQuadrature::of_scene(&scene, QuadratureOptions::STANDARD)
                .map_err(|e| anyhow!("{name}: {e}"))?;
            cells.push(cell("quadrature", q.value, 0.0, Some(thesis)));
            cells.push(cell("quoted reference", *reference, 0.0, None));
        }
        rows.push(Row {
            label: format!("{name} ({preset})"),
            cells,
        });
    }
    Ok(Table {
        key: "table_4_1",
        title: "Table 4.1: I_S^c of the platonic solids and the Cornell box: global lines, our quadrature of (4.6) (error below 1e-5), the issue tracker's quoted references".into(),
        rows,
    })
}

/// Table 4.2: `I_S^c` of the rooms with tables and chairs. Our furniture is invented (the
/// thesis gives pictures only), so only the trend is comparable.
fn table_4_2(runner: &Runner) -> Result<Table> {
    let mut rows = Vec::new();
    for (name, thesis) in TABLE_4_2 {
        let scene = Scene3::preset(name, 1).map_err(|e| anyhow!("{e}"))?;
        let c = runner.continuous_3d(&scene)?;
        rows.push(Row {
            label: format!("{name} ({} patches)", scene.n_patches()),
            cells: vec![cell("I_S^c", c.value, c.stderr, Some(thesis))],
        });
    }
    Ok(Table {
        key: "table_4_2",
        title:
            "Table 4.2: rooms with tables and chairs (our furniture is invented: compare trends)"
                .into(),
        rows,
    })
}

/// Table 3.3 (`--full`): the cube rooms with 10⁷ global lines, discrete measures from the
/// Monte Carlo form factors as in the thesis.
fn table_3_3(runner: &Runner) -> Result<Table> {
    let mut rows = Vec::new();
    for (name, figure, h_s, i_s, h_norm) in TABLE_3_3 {
        let scene = Scene3::preset(name, 10).map_err(|e| anyhow!("{e}"))?;
        let e = runner.estimate_3d(&scene, 10_000_000)?;
        let m = e
            .form_factors
            .channel()
            .map_err(|e| anyhow!("{e}"))?
            .measures();
        rows.push(Row {
            label: format!(
                "{name} ({figure}, {} patches, H_P {:.3})",
                scene.n_patches(),
                m.h_p
            ),
            cells: vec![
                cell("H_S", m.h_s, 0.0, Some(h_s)),
                cell("I_S", m.i_s, 0.0, Some(i_s)),
                cell("H_S/H_P", m.h_s_norm, 0.0, Some(h_norm)),
            ],
        });
    }
    Ok(Table {
        key: "table_3_3",
        title: "Tables 3.1 and 3.3: cube rooms with small cubes, 1e7 global lines (Table 3.1's Fig. 3.3b, a second clustering, is not built)".into(),
        rows,
    })
}

fn text(t: &Table) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{}", t.title);
    let width = t
        .rows
        .iter()
        .map(|r| r.label.chars().count())
        .max()
        .unwrap_or(0)
        .min(60);
    for row in &t.rows {
        let label: String = row.label.chars().take(60).collect();
        let _ = write!(s, "  {label:<width$}");
        for c in &row.cells {
            let ours = if c.stderr > 0.0 {
                format!("{:.4}±{:.4}", c.ours, c.stderr)
            } else {
                format!("{:.4}", c.ours)
            };
            match c.thesis {
                Some(th) => {
                    let _ = write!(
                        s,
                        " | {}: {ours} thesis {th:.3} ({:+.4})",
                        c.column,
                        c.ours - th
                    );
                }
                None => {
                    let _ = write!(s, " | {}: {ours}", c.column);
                }
            }
        }
        let _ = writeln!(s);
    }
    let worst = t
        .rows
        .iter()
        .flat_map(|r| r.cells.iter())
        .filter_map(|c| c.thesis.map(|th| (c.ours - th).abs()))
        .fold(0.0, f64::max);
    let _ = writeln!(s, "  largest |ours - thesis|: {worst:.4}\n");
    s
}

fn json(tables: &[Table], runner: &Runner, seconds: f64) -> Result<String> {
    let mut s = String::new();
    let mut o = JsonObject::new(&mut s)?;
    o.integer("lines", runner.lines)?;
    o.integer("seed", runner.seed)?;
    for t in tables {
        o.object(t.key, |o| {
            o.string("title", &t.title)?;
            for row in &t.rows {
                o.object(&row.label, |o| {
                    for c in &row.cells {
                        o.object(c.column, |o| {
                            o.number("ours", c.ours)?;
                            if c.stderr > 0.0 {
                                o.number("stderr", c.stderr)?;
                            }
                            if let Some(th) = c.thesis {
                                o.number("thesis", th)?;
                                o.number("diff", c.ours - th)?;
                            }
                            Ok(())
                        })?;
                    }
                    Ok(())
                })?;
            }
            Ok(())
        })?;
    }
    o.number("seconds", seconds)?;
    o.finish()?;
    Ok(s)
}
