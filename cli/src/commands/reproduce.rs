//! `sceneinfo reproduce`: the thesis' tables, ours beside theirs.

use std::fmt::Write as _;
use std::io::Write;
use std::time::Instant;

use anyhow::{Result, anyhow};
use sceneinfo::report::JsonObject;
use sceneinfo::scene::FlatScene;
use sceneinfo::thesis::{POLYGON_PER_SIDE, POLYGON_SIDES, TABLE_3_4_H_S, TABLE_3_5_I_S};

use crate::args::ReproduceArgs;

/// One recomputed table: rows of (label, ours, theirs).
struct Table {
    key: &'static str,
    title: &'static str,
    rows: Vec<(usize, [f64; 3], [f64; 3])>,
}

pub fn run(args: &ReproduceArgs) -> Result<()> {
    let start = Instant::now();
    // Tables 3.4 and 3.5 come from the same 30 scenes.
    let mut h_rows = Vec::new();
    let mut i_rows = Vec::new();
    for (r, &sides) in POLYGON_SIDES.iter().enumerate() {
        let mut h = [0.0; 3];
        let mut i = [0.0; 3];
        for (c, &k) in POLYGON_PER_SIDE.iter().enumerate() {
            let scene = FlatScene::regular_polygon(sides, k).map_err(|e| anyhow!("{e}"))?;
            let report = sceneinfo::report::measure_flat(&scene).map_err(|e| anyhow!("{e}"))?;
            h[c] = report.measures.h_s;
            i[c] = report.measures.i_s;
        }
        h_rows.push((sides, h, TABLE_3_4_H_S[r]));
        i_rows.push((sides, i, TABLE_3_5_I_S[r]));
    }
    let tables = [
        Table {
            key: "table_3_4",
            title: "Table 3.4: H_S of regular polygons (exact form factors)",
            rows: h_rows,
        },
        Table {
            key: "table_3_5",
            title: "Table 3.5: I_S of regular polygons (exact form factors)",
            rows: i_rows,
        },
    ];
    let seconds = start.elapsed().as_secs_f64();
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(out, "{}", json(&tables, seconds)?)?;
    } else {
        for t in &tables {
            write!(out, "{}", text(t))?;
        }
        let worst = tables
            .iter()
            .flat_map(|t| t.rows.iter())
            .flat_map(|(_, ours, theirs)| (0..3).map(move |c| (ours[c] - theirs[c]).abs()))
            .fold(0.0, f64::max);
        writeln!(
            out,
            "largest |ours - thesis| over both tables: {worst:.5} (thesis prints 3 decimals: ±0.0005 is rounding)"
        )?;
        writeln!(out, "computed in {seconds:.2} s")?;
    }
    out.flush()?;
    Ok(())
}

fn text(t: &Table) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{}", t.title);
    let _ = write!(s, "sides");
    for k in POLYGON_PER_SIDE {
        let _ = write!(s, " | {:>2} per side: ours   thesis    diff", k);
    }
    let _ = writeln!(s);
    for (sides, ours, theirs) in &t.rows {
        let _ = write!(s, "{sides:>5}");
        for c in 0..3 {
            let _ = write!(
                s,
                " |            {:>6.4}  {:>6.3} {:>+8.5}",
                ours[c],
                theirs[c],
                ours[c] - theirs[c]
            );
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s);
    s
}

fn json(tables: &[Table], seconds: f64) -> Result<String> {
    let mut s = String::new();
    let mut o = JsonObject::new(&mut s)?;
    for t in tables {
        o.object(t.key, |o| {
            o.string("title", t.title)?;
            for (sides, ours, theirs) in &t.rows {
                let key = format!("sides_{sides}");
                o.object(&key, |o| {
                    for (c, k) in POLYGON_PER_SIDE.iter().enumerate() {
                        o.object(&format!("per_side_{k}"), |o| {
                            o.number("ours", ours[c])?;
                            o.number("thesis", theirs[c])?;
                            o.number("diff", ours[c] - theirs[c])
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
