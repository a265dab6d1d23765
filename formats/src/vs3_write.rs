//! A 3D scene written as View3D's input (`.vs3`, geometry format `F 3`), so that a scene
//! sceneinfo reads (OBJ, glTF, PLY, a preset) can be run through NIST View3D and the two
//! results compared entry by entry (`formfactors --out F.vf3` writes sceneinfo's result in
//! View3D's output format; `view3d_out` reads View3D's).
//!
//! The format is the one [`vs3_scene`](crate::vs3_scene) reads, from the View3D 3.3
//! manual (`doc/view3d-manual.tex`, "View3D Format (F=3)"):
//!
//! ```text
//! T title
//! C encl=0 emit=0 out=1 eps=1e-4 …        controls (below)
//! F 3
//! V n x y z                               each distinct corner once, numbered from 1
//! S n v1 v2 v3 v4 base cmb emit name      a radiating surface; v4 = 0 for a triangle
//! End of data
//! ```
//!
//! - **Shapes.** View3D takes triangles and convex quadrilaterals only. A patch of more
//!   than four corners (a sceneinfo patch is convex) is cut into a fan of quadrilaterals
//!   sharing its first corner, the last piece a triangle when the count is odd, and the
//!   pieces after the first name the first in the `cmb` column: View3D combines every
//!   higher-numbered piece with the lowest-numbered one, so it reports one row and column
//!   per patch, in the scene's patch order (the manual, "Combining surfaces"). Corners on a
//!   straight edge (collinear with their neighbours to [`COLLINEAR_REL`] of the patch's
//!   size) are left out first: View3D's convexity test would refuse the quad they make.
//! - **Orientation.** Corners counter-clockwise seen from the front, as in sceneinfo and
//!   OBJ: copied as they are, in world coordinates.
//! - **Controls.** `encl=0` (raw factors, not renormalised), `emit=0` (black surfaces:
//!   plain view factors), `out=1` (binary `f32` output: the text output's six decimals are
//!   too coarse for small patches), `eps` the adaptive tolerance View3D integrates to
//!   (its `epsAdap`; the caller's, View3D's default being `1e-4`). Every surface is also an
//!   obstruction in View3D, as every patch is in sceneinfo.
//!
//! Reading the written file back with `vs3_scene` gives the same patches (the fan pieces
//! joined again), which the tests check.

use std::collections::BTreeMap;
use std::fmt::Write;

use sceneinfo::geom::DVec3;
use sceneinfo::scene::Scene3;

/// A corner is left out when the parallelogram of its two edges has less area than
/// `COLLINEAR_REL` times the square of the patch's largest corner distance.
pub const COLLINEAR_REL: f64 = 1e-9;

/// What the `C` line of a written file asks of View3D.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vs3Controls {
    /// View3D's convergence tolerance `eps` (`epsAdap`); its default is `1e-4`, and it
    /// warns below `1e-6`.
    pub eps: f64,
    /// `encl=1` renormalises every row to sum to 1 (an enclosure); `false` writes `encl=0`.
    pub enclosure: bool,
}

impl Default for Vs3Controls {
    fn default() -> Self {
        Self {
            eps: 1e-4,
            enclosure: false,
        }
    }
}

/// The number of vertex `v` in `number` (bit for bit: equal coordinates, one vertex); a new
/// one is numbered after the others, in order of first use, and its `V` record appended to
/// `out`.
fn vertex_number(number: &mut BTreeMap<[u64; 3], usize>, out: &mut String, v: DVec3) -> usize {
    let next = number.len() + 1;
    *number
        .entry(v.to_array().map(f64::to_bits))
        .or_insert_with(|| {
            let _ = writeln!(out, "V {next} {:?} {:?} {:?}", v.x, v.y, v.z);
            next
        })
}

/// The `.vs3` text of `scene` (module docs), titled `title` (one line; line breaks become
/// spaces).
#[must_use]
pub fn write(scene: &Scene3, title: &str, controls: Vs3Controls) -> String {
    let mut out = String::new();
    let title: String = title
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let _ = writeln!(out, "T {title} ({} patches)", scene.n_patches());
    let _ = writeln!(
        out,
        "C encl={} emit=0 out=1 eps={:e}",
        u8::from(controls.enclosure),
        controls.eps
    );
    out.push_str("F 3\n!  #   x   y   z\n");
    // Corners in world coordinates, each distinct one once, numbered in order of first use
    let mut number: BTreeMap<[u64; 3], usize> = BTreeMap::new();
    let mut patches: Vec<Vec<usize>> = Vec::with_capacity(scene.n_patches());
    for i in 0..scene.n_patches() {
        let corners: Vec<DVec3> = scene
            .patch_vertices(i)
            .iter()
            .map(|&v| scene.frame().to_world(v))
            .collect();
        let kept = without_collinear(&corners);
        let ids = kept
            .into_iter()
            .map(|v| vertex_number(&mut number, &mut out, v))
            .collect();
        patches.push(ids);
    }
    out.push_str("!  #   v1 v2 v3 v4 base cmb emit name\n");
    let mut surface = 0usize;
    for (i, ids) in patches.iter().enumerate() {
        let mut first = 0;
        for piece in fan_pieces(ids) {
            surface += 1;
            let v4 = piece.get(3).copied().unwrap_or(0);
            let _ = writeln!(
                out,
                "S {surface} {} {} {} {v4} 0 {first} 0.9 p{}",
                piece[0],
                piece[1],
                piece[2],
                i + 1
            );
            if first == 0 {
                first = surface;
            }
        }
    }
    out.push_str("End of data\n");
    out
}

/// A `.vs3` file `text` from `path` written again as its records (`F 3`): each surface
/// record (`S`, `M`, `N`, `O`) with its number, corners, base, `cmb`, emittance and name as
/// read (a `F 3a` surface's corners placed as `vs3_scene` places them), its vertices
/// numbered in order of first use, the file's controls (`controls`: other values), title
/// kept. Unlike [`write()`], which writes a scene's patches (a cut base as its pieces, an
/// obstruction-only surface as a radiating one), this keeps what the file says: read back
/// it gives the same output surfaces, patches and view factors (`scene convert FILE.vs3
/// -o OUT.vs3`).
///
/// # Errors
/// What reading the file refuses (`vs3_scene::read_with_layout`'s).
pub fn write_records(
    path: &std::path::Path,
    text: &str,
    controls: Option<crate::vs3_controls::Vs3FileControls>,
) -> anyhow::Result<String> {
    // Refused as reading refuses it
    crate::vs3_scene::read_with_layout(path, text, &mut sceneinfo::io::LoadReport::default())?;
    let (records, file_controls) = crate::vs3_parse::parse(path, text)?;
    let controls = controls.unwrap_or(file_controls);
    let title = text
        .lines()
        .rfind(|l| l.trim_start().starts_with(['T', 't']))
        .map_or("", |l| l.trim_start()[1..].trim());
    let mut out = String::new();
    let _ = writeln!(out, "T {title}");
    let _ = writeln!(out, "C {}", controls.line_text());
    out.push_str("F 3\n!  #   x   y   z\n");
    let mut number: BTreeMap<[u64; 3], usize> = BTreeMap::new();
    let mut ids: Vec<Vec<usize>> = Vec::with_capacity(records.len());
    for r in &records {
        let these = r
            .corners
            .iter()
            .map(|&v| vertex_number(&mut number, &mut out, v))
            .collect();
        ids.push(these);
    }
    out.push_str("!  #   v1 v2 v3 v4 base cmb emit name\n");
    for (r, these) in records.iter().zip(&ids) {
        let v4 = these.get(3).copied().unwrap_or(0);
        // Without an emittance the line has no name either (the name follows it)
        let tail = r
            .emissivity
            .map_or_else(String::new, |e| format!(" {e:?} {}", r.name));
        let _ = writeln!(
            out,
            "{} {} {} {} {} {v4} {} {}{}",
            r.kind.letter(),
            r.number,
            these[0],
            these[1],
            these[2],
            r.base,
            r.combine,
            tail.trim_end()
        );
    }
    out.push_str("End of data\n");
    Ok(out)
}

/// `corners` without those collinear with their two neighbours (module docs); at least the
/// three corners of the largest triangle are kept, so a valid patch stays a polygon.
fn without_collinear(corners: &[DVec3]) -> Vec<DVec3> {
    let origin = corners.first().copied().unwrap_or(DVec3::ZERO);
    let size = corners
        .iter()
        .map(|c| (*c - origin).length_squared())
        .fold(0.0, f64::max);
    let mut kept: Vec<DVec3> = corners.to_vec();
    // Bounded: each pass removes one corner or stops
    while kept.len() > 3 {
        let n = kept.len();
        let flat = (0..n).find(|&k| {
            let (a, b, c) = (kept[(k + n - 1) % n], kept[k], kept[(k + 1) % n]);
            (b - a).cross(c - b).length() <= COLLINEAR_REL * size
        });
        match flat {
            Some(k) => {
                kept.remove(k);
            }
            None => break,
        }
    }
    kept
}

/// A convex polygon's corners `ids` as a fan of quadrilaterals sharing `ids[0]` (the last
/// piece a triangle when needed); a triangle or quadrilateral is its own one piece.
fn fan_pieces(ids: &[usize]) -> Vec<Vec<usize>> {
    if ids.len() <= 4 {
        return vec![ids.to_vec()];
    }
    let mut pieces = Vec::new();
    let mut k = 1;
    // Bounded: k grows by 2 each piece
    while k + 1 < ids.len() {
        let end = (k + 3).min(ids.len());
        let mut piece = vec![ids[0]];
        piece.extend_from_slice(&ids[k..end]);
        k += piece.len() - 2;
        pieces.push(piece);
    }
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneinfo::io::LoadReport;
    use std::path::Path;

    fn round_trip(scene: &Scene3) -> Scene3 {
        let text = write(scene, "test", Vs3Controls::default());
        crate::vs3_scene::read(Path::new("t.vs3"), &text, &mut LoadReport::default())
            .unwrap_or_else(|e| panic!("{e:#}\n{text}"))
    }

    #[test]
    fn fans_cover_every_corner_once_between_neighbours() {
        assert_eq!(fan_pieces(&[1, 2, 3]), [vec![1, 2, 3]]);
        assert_eq!(fan_pieces(&[1, 2, 3, 4]), [vec![1, 2, 3, 4]]);
        assert_eq!(
            fan_pieces(&[1, 2, 3, 4, 5]),
            [vec![1, 2, 3, 4], vec![1, 4, 5]]
        );
        assert_eq!(
            fan_pieces(&[1, 2, 3, 4, 5, 6]),
            [vec![1, 2, 3, 4], vec![1, 4, 5, 6]]
        );
        assert_eq!(
            fan_pieces(&[1, 2, 3, 4, 5, 6, 7]),
            [vec![1, 2, 3, 4], vec![1, 4, 5, 6], vec![1, 6, 7]]
        );
    }

    #[test]
    fn collinear_corners_are_left_out() {
        let square_with_midpoint = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.5, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let kept = without_collinear(&square_with_midpoint);
        assert_eq!(kept.len(), 4);
        assert!(!kept.contains(&DVec3::new(0.5, 0.0, 0.0)));
    }

    /// Every preset with pentagons (the dodecahedron), boxes (the Cornell box) and a grid:
    /// the file read back has the same patches, areas and unoccluded form factors.
    #[test]
    fn presets_read_back_as_the_same_patches() {
        for (name, grid) in [("dodecahedron", 1), ("cornell", 2), ("cube", 3)] {
            let scene = Scene3::preset(name, grid).unwrap();
            let back = round_trip(&scene);
            assert_eq!(back.n_patches(), scene.n_patches(), "{name}");
            for i in 0..scene.n_patches() {
                let (a, b) = (scene.patches()[i].area, back.patches()[i].area);
                let (a, b) = (
                    scene.frame().area_to_world(a),
                    back.frame().area_to_world(b),
                );
                assert!(
                    (a - b).abs() <= 1e-12 * a,
                    "{name} patch {i}: {a} against {b}"
                );
                let c = |s: &Scene3| s.frame().to_world(s.patches()[i].centroid);
                let (ca, cb) = (c(&scene), c(&back));
                assert!(
                    ca.distance(cb) < 1e-12,
                    "{name} patch {i}: {ca} against {cb}"
                );
            }
        }
    }

    /// Every committed `.vs3` file (View3D's samples in both geometry formats, the surface
    /// kinds: subsurfaces, masks, null and obstruction-only surfaces, the controls'
    /// files) written again as its records and read back: the same output surfaces
    /// (numbers, names, areas, emittances, masks), the same patches corner for corner
    /// (so the same view factors), the same controls.
    #[test]
    fn vs3_records_read_back_as_the_same_file() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/vs3");
        let mut files = Vec::new();
        for dir in ["view3d-examples", "surface-kinds", "controls", "."] {
            for e in std::fs::read_dir(root.join(dir)).unwrap() {
                let p = e.unwrap().path();
                if p.extension().is_some_and(|x| x == "vs3") {
                    files.push(p);
                }
            }
        }
        assert!(files.len() >= 15, "{files:?}");
        let mut read = 0;
        for p in files {
            let text = std::fs::read_to_string(&p).unwrap();
            let mut report = LoadReport::default();
            // col without row is refused, as View3D refuses it
            let Ok((scene, layout)) = crate::vs3_scene::read_with_layout(&p, &text, &mut report)
            else {
                assert!(write_records(&p, &text, None).is_err());
                continue;
            };
            let written = write_records(&p, &text, None).unwrap();
            let (back, back_layout) =
                crate::vs3_scene::read_with_layout(Path::new("w.vs3"), &written, &mut report)
                    .unwrap_or_else(|e| panic!("{}: {e:#}\n{written}", p.display()));
            let key = |l: &crate::vs3_scene::Vs3Layout| -> Vec<_> {
                l.surfaces()
                    .iter()
                    .map(|s| (s.number, s.name.clone(), s.area, s.emissivity, s.mask_of))
                    .collect()
            };
            assert_eq!(key(&layout), key(&back_layout), "{}", p.display());
            let (mut c0, mut c1) = (*layout.controls(), *back_layout.controls());
            (c0.line, c0.row_line, c1.line, c1.row_line) = (0, 0, 0, 0);
            assert_eq!(c0, c1, "{}", p.display());
            assert_eq!(scene.n_patches(), back.n_patches(), "{}", p.display());
            for i in 0..scene.n_patches() {
                assert_eq!(
                    scene.patch_vertices(i),
                    back.patch_vertices(i),
                    "{} patch {i}",
                    p.display()
                );
            }
            read += 1;
        }
        assert!(read >= 14);
    }

    #[test]
    fn the_header_says_what_view3d_is_asked() {
        let scene = Scene3::preset("tetrahedron", 1).unwrap();
        let text = write(
            &scene,
            "a\ntitle",
            Vs3Controls {
                eps: 1e-6,
                enclosure: true,
            },
        );
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some("T a title (4 patches)"));
        assert_eq!(lines.next(), Some("C encl=1 emit=0 out=1 eps=1e-6"));
        assert_eq!(lines.next(), Some("F 3"));
        assert_eq!(text.lines().filter(|l| l.starts_with("S ")).count(), 4);
        assert!(text.ends_with("End of data\n"));
    }
}
