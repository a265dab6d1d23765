//! `sceneinfo reproduce`: the thesis' tables, ours beside theirs.
//!
//! Chapter 3: Tables 3.4 and 3.5 (exact form factors). Chapter 4: Tables 4.10, 4.11 and 4.12
//! and the flatland catalogue of §4.5.2 (global lines; `--lines` per scene, fixed seed).

use std::fmt::Write as _;
use std::io::Write;
use std::time::Instant;

use anyhow::{Result, anyhow};
use sceneinfo::continuous::closed_form;
use sceneinfo::formfactor::estimate_2d::{FlatEstimate, FlatTracer, LineMethod};
use sceneinfo::report::JsonObject;
use sceneinfo::scene::{FlatScene, catalogue, catalogue_scene};
use sceneinfo::thesis::{
    POLYGON_PER_SIDE, POLYGON_SIDES, TABLE_3_4_H_S, TABLE_3_5_I_S, TABLE_4_10_I_S_CONTINUOUS,
    TABLE_4_11, TABLE_4_12,
};

use crate::args::ReproduceArgs;

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
    fn estimate(&self, scene: &FlatScene, lines: u64) -> Result<FlatEstimate> {
        let tracer = FlatTracer::new(scene).map_err(|e| anyhow!("{e}"))?;
        let tally = crate::lines::run(&tracer, LineMethod::Global, self.seed, lines, self.threads);
        tally.finish(&tracer).map_err(|e| anyhow!("{e}"))
    }

    /// `(I_S^c, standard error)` of a scene.
    fn continuous(&self, scene: &FlatScene) -> Result<(f64, f64)> {
        let e = self.estimate(scene, self.lines)?;
        Ok((e.continuous.value, e.continuous.stderr))
    }
}

pub fn run(args: &ReproduceArgs) -> Result<()> {
    let start = Instant::now();
    let runner = Runner {
        lines: args.lines,
        seed: args.seed,
        threads: args.threads.unwrap_or_else(|| {
            std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
        }),
    };
    if runner.lines == 0 {
        return Err(anyhow!("{}", sceneinfo::ErrorKind::NoLines));
    }
    let mut tables = chapter_3()?;
    if !args.chapter_3_only {
        tables.push(table_4_10(&runner)?);
        tables.push(table_4_11(&runner)?);
        tables.push(table_4_12(&runner)?);
        tables.push(catalogue_table(&runner)?);
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
                exact_measures(&FlatScene::regular_polygon(sides, k).map_err(|e| anyhow!("{e}"))?)?;
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

fn exact_measures(scene: &FlatScene) -> Result<sceneinfo::channel::Measures> {
    Ok(sceneinfo::report::measure_flat(scene)
        .map_err(|e| anyhow!("{e}"))?
        .measures)
}

/// Table 4.10: `I_S^c` of regular polygons (one patch per side: `I_S^c` does not depend on
/// the discretisation).
fn table_4_10(runner: &Runner) -> Result<Table> {
    let mut rows = Vec::new();
    for (r, &sides) in POLYGON_SIDES.iter().enumerate() {
        let scene = FlatScene::regular_polygon(sides, 1).map_err(|e| anyhow!("{e}"))?;
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
        (closed_form::circle(), 512),
        (closed_form::regular_hexagon(), 6),
        (closed_form::square(), 4),
        (closed_form::equilateral_triangle(), 3),
    ];
    let mut rows = Vec::new();
    for ((name, exact, mc), (ours_exact, sides)) in TABLE_4_11.iter().zip(shapes) {
        let scene = FlatScene::regular_polygon(sides, 1).map_err(|e| anyhow!("{e}"))?;
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
    let last = sceneinfo::scene::SINGULARITY_STEPS - 1;
    let per_side = 10;
    let cases = [
        (
            FlatScene::rotating_square_subscene(per_side),
            FlatScene::rotating_square(last, per_side),
        ),
        (
            FlatScene::pentagonal_star_subscene(per_side),
            FlatScene::pentagonal_star(last, per_side),
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
    for entry in catalogue() {
        let scene = catalogue_scene(entry.name, 10).map_err(|e| anyhow!("{}: {e}", entry.name))?;
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
            cells.push(cell("I_S (1e6 lines)", i_s, 0.0, entry.thesis));
            cells.push(cell("I_S exact", exact, 0.0, None));
            cells.push(cell(
                "I_S^c",
                est.continuous.value,
                est.continuous.stderr,
                None,
            ));
        } else {
            let (v, e) = runner.continuous(&scene)?;
            cells.push(cell("I_S^c", v, e, entry.thesis));
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
