//! View3D's input format (`.vs3`, geometry format `F 3`: vertices, then surfaces), read
//! into a 3D scene, so that View3D's users can run the same files through sceneinfo.
//!
//! The format, from the View3D 3.3 manual (`doc/view3d-manual.tex`, "Input File Format",
//! "View3D Format (F=3)"); each line begins with one character saying what it is:
//!
//! | line | meaning | read as |
//! |---|---|---|
//! | `! …`, `/ …` | comment (also after data on a line) | skipped |
//! | `T title` | title | skipped |
//! | `C name=value …` | controls (`eps`, `encl`, …) | skipped: sceneinfo's own options apply |
//! | `F 3` | geometry format | only `3` is read (`3a`, `2` refused) |
//! | `V n x y z` | vertex `n` | a point |
//! | `S n v1 v2 v3 v4 base cmb emit name` | radiating surface (`v4 = 0`: a triangle) | a face |
//! | `E …`, `e …`, `* …` | end of data | stops reading |
//!
//! Vertices are listed counter-clockwise seen from the front of the surface (the active
//! side), as in OBJ and sceneinfo: they are copied as they are. Surfaces with a non-zero
//! `cmb` are combined with surface `cmb` (View3D's way of giving a polygon of more than
//! four corners as convex pieces): the pieces of one combined surface become one patch,
//! the convex hull of their corners, provided the pieces are coplanar and their areas add
//! up to the hull's (their union is then that convex polygon); a non-convex union is
//! refused. Subsurfaces (`base ≠ 0`), masking, null and obstruction-only surfaces (`M`,
//! `N`, `O`) have no counterpart in a sceneinfo scene and are refused with the line that
//! holds them. The emissivity column is not used (surfaces are black, as View3D's
//! default `emit=0`). One patch per output surface of View3D, in its order.

use std::path::Path;

use anyhow::{Result, bail};
use sceneinfo::geom::DVec3;
use sceneinfo::io::LoadReport;
use sceneinfo::scene::{Scene3, Scene3Builder};

use crate::mesh::add_face;

/// Most vertices or surfaces a file may number (bounds the tables).
const MAX_NUMBER: usize = 1 << 26;

/// Relative agreement asked of a combined surface's piece areas and its hull's area.
const COMBINE_AREA_TOL: f64 = 1e-9;

/// One radiating surface: its corners, the surface it combines with (0: none), its line.
struct Surface {
    corners: Vec<DVec3>,
    combine: usize,
    line: usize,
}

/// Reads the `.vs3` file `bytes` from `path` (see the module documentation).
///
/// # Errors
/// `file:line: what` for a line that cannot be read or a construct sceneinfo has no
/// counterpart for; the scene builder's errors as the other mesh readers report them.
pub fn read(path: &Path, text: &str, report: &mut LoadReport) -> Result<Scene3> {
    let at = |line: usize, what: &str| anyhow::anyhow!("{}:{line}: {what}", path.display());
    let mut vertices: Vec<Option<DVec3>> = Vec::new();
    let mut surfaces: Vec<Option<Surface>> = Vec::new();
    let mut format_seen = false;
    // Bounded: the lines of the file
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        // A comment may follow the data on a line
        let data = raw.split(['!', '/']).next().unwrap_or("").trim();
        let mut tokens = data.split_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        let kind = keyword.chars().next().unwrap_or(' ').to_ascii_uppercase();
        let fields: Vec<&str> = tokens.collect();
        match kind {
            'T' | 'C' => {}
            'E' | '*' => break,
            'F' => {
                if fields.first().copied() != Some("3") {
                    return Err(at(
                        line,
                        &format!(
                            "geometry format F {} is not read (only F 3, vertices and surfaces)",
                            fields.first().copied().unwrap_or("")
                        ),
                    ));
                }
                format_seen = true;
            }
            'V' => {
                if fields.len() < 4 {
                    return Err(at(line, "a vertex needs a number and x y z"));
                }
                let n = number(fields[0]).ok_or_else(|| at(line, "bad vertex number"))?;
                let mut c = [0.0; 3];
                for (slot, field) in c.iter_mut().zip(&fields[1..4]) {
                    *slot = field
                        .parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| at(line, &format!("bad coordinate {field:?}")))?;
                }
                if vertices.len() <= n {
                    vertices.resize(n + 1, None);
                }
                vertices[n] = Some(DVec3::from(c));
            }
            'S' => {
                if fields.len() < 7 {
                    return Err(at(
                        line,
                        "a surface needs: number v1 v2 v3 v4 base cmb [emit name]",
                    ));
                }
                let field = |i: usize, what: &str| {
                    number_or_zero(fields[i]).ok_or_else(|| at(line, &format!("bad {what}")))
                };
                let n = number(fields[0]).ok_or_else(|| at(line, "bad surface number"))?;
                let (base, combine) = (field(5, "base")?, field(6, "cmb")?);
                if base != 0 {
                    return Err(at(
                        line,
                        "subsurfaces (base != 0) are not read: give the base surface's remaining \
                         part as its own surfaces",
                    ));
                }
                let mut corners = Vec::with_capacity(4);
                for i in 1..=4 {
                    let v = field(i, "vertex number")?;
                    if v == 0 && i == 4 {
                        break;
                    }
                    let p = vertices.get(v).copied().flatten().ok_or_else(|| {
                        at(
                            line,
                            &format!("vertex {v} is not defined before it is used"),
                        )
                    })?;
                    corners.push(p);
                }
                if combine != 0 && combine >= n {
                    return Err(at(
                        line,
                        "cmb must name an earlier surface (View3D: combine every piece with the \
                         lowest-numbered one)",
                    ));
                }
                if surfaces.len() <= n {
                    surfaces.resize_with(n + 1, || None);
                }
                if surfaces[n].is_some() {
                    return Err(at(line, &format!("surface {n} is given twice")));
                }
                surfaces[n] = Some(Surface {
                    corners,
                    combine,
                    line,
                });
            }
            'M' | 'N' | 'O' => {
                return Err(at(
                    line,
                    "masking, null and obstruction-only surfaces (M, N, O) are not read: a \
                     sceneinfo scene's every surface radiates (give obstructions as S surfaces)",
                ));
            }
            _ => return Err(at(line, &format!("unknown line kind {keyword:?}"))),
        }
    }
    if !format_seen {
        bail!("{}: no geometry line (F 3)", path.display());
    }
    // Combined surfaces: the pieces of each lowest-numbered surface
    let mut groups: Vec<Vec<usize>> = vec![Vec::new(); surfaces.len()];
    for (n, s) in surfaces.iter().enumerate() {
        if let Some(s) = s {
            let head = if s.combine == 0 { n } else { s.combine };
            match surfaces.get(head) {
                Some(Some(h)) if h.combine == 0 => groups[head].push(n),
                _ => {
                    return Err(at(
                        s.line,
                        &format!(
                            "cmb {head} is not a surface combined with no other (View3D: do \
                             not chain combinations)"
                        ),
                    ));
                }
            }
        }
    }
    let mut builder = Scene3Builder::default();
    for (head, pieces) in groups.iter().enumerate() {
        // Pieces combined into another surface belong to that one's group
        let Some(Some(first)) = surfaces.get(head).filter(|_| !pieces.is_empty()) else {
            continue;
        };
        let polygon = if pieces.len() == 1 {
            first.corners.clone()
        } else {
            let parts: Vec<&[DVec3]> = pieces
                .iter()
                .filter_map(|&p| surfaces[p].as_ref().map(|s| s.corners.as_slice()))
                .collect();
            union_of_pieces(&parts).ok_or_else(|| {
                at(
                    first.line,
                    &format!(
                        "the surfaces combined with surface {head} do not form one convex \
                         polygon (a sceneinfo patch is convex: give them as separate surfaces)"
                    ),
                )
            })?
        };
        add_face(
            &mut builder,
            &polygon,
            report,
            path,
            format_args!("line {}", first.line),
        )?;
    }
    crate::mesh::build(builder, report, path)
}

/// A positive surface or vertex number.
fn number(s: &str) -> Option<usize> {
    s.parse::<usize>()
        .ok()
        .filter(|&n| n > 0 && n <= MAX_NUMBER)
}

/// A number that may be 0 (`v4`, `base`, `cmb`).
fn number_or_zero(s: &str) -> Option<usize> {
    s.parse::<usize>().ok().filter(|&n| n <= MAX_NUMBER)
}

/// Twice the vector area of a polygon (Newell): its normal times twice its area.
fn vector_area(p: &[DVec3]) -> DVec3 {
    let mut n = DVec3::ZERO;
    for (k, &a) in p.iter().enumerate() {
        n += a.cross(p[(k + 1) % p.len()]);
    }
    n
}

/// The union of coplanar convex `pieces` facing one way when it is a convex polygon: the
/// convex hull of their corners (counter-clockwise about their common normal), provided
/// the pieces' areas add up to the hull's within [`COMBINE_AREA_TOL`] (pieces that do not
/// overlap and fill their hull). `None` otherwise.
fn union_of_pieces(pieces: &[&[DVec3]]) -> Option<Vec<DVec3>> {
    let normals: Vec<DVec3> = pieces.iter().map(|p| vector_area(p)).collect();
    let total = normals.iter().copied().fold(DVec3::ZERO, |a, b| a + b);
    let n = total.try_normalize()?;
    let area_sum: f64 = normals.iter().map(|v| v.length()).sum();
    // Facing one way
    if normals.iter().any(|v| v.dot(n) < 0.0) {
        return None;
    }
    let corners: Vec<DVec3> = pieces.iter().flat_map(|p| p.iter().copied()).collect();
    let origin = corners[0];
    let scale = corners
        .iter()
        .map(|c| (*c - origin).length())
        .fold(0.0, f64::max);
    // Coplanar
    if corners
        .iter()
        .any(|c| (*c - origin).dot(n).abs() > 1e-9 * scale.max(f64::MIN_POSITIVE))
    {
        return None;
    }
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let mut pts: Vec<(f64, f64, DVec3)> = corners
        .iter()
        .map(|&c| ((c - origin).dot(u), (c - origin).dot(v), c))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    pts.dedup_by(|a, b| (a.0 - b.0).hypot(a.1 - b.1) <= 1e-12 * scale);
    // Andrew's monotone chain, counter-clockwise in (u, v), that is about n = u × v
    let cross = |o: &(f64, f64, DVec3), a: &(f64, f64, DVec3), b: &(f64, f64, DVec3)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut hull: Vec<(f64, f64, DVec3)> = Vec::with_capacity(pts.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &(f64, f64, DVec3)>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for p in iter {
            while hull.len() >= start + 2
                && cross(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= 1e-12 * scale * scale
            {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    if hull.len() < 3 {
        return None;
    }
    let polygon: Vec<DVec3> = hull.iter().map(|h| h.2).collect();
    let hull_area = vector_area(&polygon).length();
    ((hull_area - area_sum).abs() <= COMBINE_AREA_TOL * hull_area).then_some(polygon)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_text(text: &str) -> Result<Scene3> {
        read(Path::new("t.vs3"), text, &mut LoadReport::default())
    }

    #[test]
    fn combined_pieces_become_one_convex_patch() {
        // A hexagon as a quad and a quad sharing an edge (as obj2vs3.py cuts it)
        let text = "T hex\nF 3\nV 1 0 0 0\nV 2 2 0 0\nV 3 3 1 0\nV 4 2 2 0\nV 5 0 2 0\nV 6 -1 1 0\n\
                    S 1 1 2 3 4 0 0 0.9 a\nS 2 1 4 5 6 0 1 0.9 a\nEnd of data\n";
        let scene = read_text(text).unwrap();
        assert_eq!(scene.n_patches(), 1);
        let area = scene.total_area();
        assert!((area - 6.0).abs() < 1e-12, "{area}");
        // An L made of two squares is not convex: refused with the line
        let text = "F 3\nV 1 0 0 0\nV 2 1 0 0\nV 3 1 1 0\nV 4 0 1 0\nV 5 2 0 0\nV 6 2 1 0\n\
                    V 7 1 2 0\nV 8 0 2 0\n\
                    S 1 1 2 3 4 0 0 0.9 a\nS 2 2 5 6 3 0 1 0.9 a\nS 3 4 3 7 8 0 1 0.9 a\n";
        let e = read_text(text).unwrap_err().to_string();
        assert!(e.starts_with("t.vs3:10: "), "{e}");
    }

    #[test]
    fn refusals_name_the_line() {
        for (text, line) in [
            ("F 3a\n", 1),
            ("F 3\nV 1 0 0 0\nS 1 1 2 3 0 0 0 0.9 a\n", 3),
            ("F 3\nV 1 0 0 x\n", 2),
            ("F 3\nO 1 1 2 3 0\n", 2),
            ("F 3\nQ 1\n", 2),
        ] {
            let e = read_text(text).unwrap_err().to_string();
            assert!(e.starts_with(&format!("t.vs3:{line}: ")), "{text:?}: {e}");
        }
        assert!(read_text("V 1 0 0 0\n").is_err());
    }

    /// A file written by the View3D anchor's `obj2vs3.py` (tests/data/vs3, from the OBJ
    /// beside it; a hexagon cut into two pieces joined by `cmb`) is the OBJ's scene: the
    /// same patches, in the same order, with the same corners.
    #[test]
    fn obj2vs3_output_is_the_obj_scene() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/vs3");
        let options = crate::LoadOptions::default();
        let load = |name: &str| match crate::load_file(&dir.join(name), &options).unwrap() {
            (sceneinfo::Scene::Solid(s), _) => s,
            (sceneinfo::Scene::Flat(_), _) => panic!("{name}: read as flatland"),
        };
        let (vs3, obj) = (load("room_with_plate.vs3"), load("room_with_plate.obj"));
        assert_eq!(vs3.n_patches(), 9);
        assert_eq!(vs3.n_patches(), obj.n_patches());
        for (a, b) in vs3.patches().iter().zip(obj.patches()) {
            let corners = |s: &Scene3, first: usize, count: usize| {
                let mut c: Vec<[f64; 3]> = s.points()[first..first + count]
                    .iter()
                    .map(|p| p.to_array())
                    .collect();
                c.sort_by(|x, y| x.partial_cmp(y).unwrap());
                c
            };
            assert_eq!(
                corners(&vs3, a.first, a.count),
                corners(&obj, b.first, b.count)
            );
        }
        assert!((vs3.total_area() - obj.total_area()).abs() < 1e-12);
    }
}
