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
        let mut ids = Vec::with_capacity(kept.len());
        for v in kept {
            let next = number.len() + 1;
            let id = *number
                .entry(v.to_array().map(f64::to_bits))
                .or_insert_with(|| {
                    let _ = writeln!(out, "V {next} {:?} {:?} {:?}", v.x, v.y, v.z);
                    next
                });
            ids.push(id);
        }
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
