//! Coincident faces as drawn: duplicates dropped, overlaps cut away, so that area drawn
//! twice is counted once ([`Scene3Builder::build_as_drawn`]).
//!
//! # Rule
//!
//! Coincident faces are those [`super::super::coincident`] finds: in one plane, facing the
//! same way, overlapping deeper than its tolerance `τ = 10⁻¹² R` (`R` the largest coordinate
//! magnitude). For every face `j`, in input order, with earlier coincident faces `I`:
//!
//! - if some `i ∈ I` has the same vertices up to a cyclic rotation (each within `τ` per
//!   coordinate), `j` is a **duplicate** and dropped (`duplicates_dropped`, a warning naming
//!   both lines);
//! - otherwise `j` keeps what no face of `I` covers: `j − ∪ I`, as convex pieces. A convex
//!   polygon minus a convex polygon `c` is cut edge by edge of `c`: the part of the current
//!   remainder outside the edge's line (within `τ` counts as on it) is a piece, the part
//!   inside goes on; what is left at the end lies inside `c` and is dropped. If no piece
//!   of positive area is left, `j` is **covered** and dropped (`covered_dropped`); else its
//!   pieces replace it, each a face cut by `j`'s subdivision (`overlaps_clipped`,
//!   `clip_pieces`).
//!
//! The earlier faces are taken as drawn, not as clipped or dropped themselves: the union
//! of the earlier faces equals the union of what was kept of them, so `j − ∪ I` is the same
//! either way, and the order of faces decides only which copy keeps the area.
//!
//! Opposite-facing coincident faces (a two-sided wall) and faces that only touch are not
//! coincident and stay as they are.
//!
//! # What remains an error
//!
//! - more than [`MAX_COINCIDENT_PAIRS`](super::super::coincident::MAX_COINCIDENT_PAIRS)
//!   coincident pairs, or more than [`MAX_CLIP_PIECES`] pieces of one face
//!   ([`ErrorKind::TooLarge`]): `k` copies of one face make `k²/2` pairs, so such a file is
//!   a stack of copies the rule would spend quadratic time on, not a drawing;
//! - a piece the strict check still finds coincident after the cut (rounding beyond `τ`):
//!   [`ErrorKind::CoincidentSurfaces`] with the indices of the faces as added.

use alloc::vec::Vec;

use super::{Scene3, Scene3Builder};
use crate::error::{ErrorKind, Result};
use crate::geom::{self, DVec3};
use crate::scene::coincident::{coincident_face_pairs, face_tolerance};
use crate::scene::{LoadReport, LoadWarningKind};

/// Most convex pieces one face may be cut into by the faces it overlaps.
pub(crate) const MAX_CLIP_PIECES: usize = 4096;

/// What happens to a face coincident with earlier ones.
enum Fate {
    /// Dropped as a duplicate of the face given.
    Duplicate(usize),
    /// Dropped as covered (the first covering face given).
    Covered(usize),
    /// Replaced by these pieces (the first overlapping face given).
    Clipped(usize, Vec<Vec<DVec3>>),
}

impl Scene3Builder {
    /// The finished scene, with coincident faces resolved by the rule of the module docs
    /// and recorded in `report`; `face_lines[k]` is the line of face `k` (for the
    /// warnings). Without coincident faces, the scene [`Self::build`] gives. Consumes the
    /// builder (no copy of its vectors).
    ///
    /// # Errors
    /// [`ErrorKind::EmptyScene`] if no face was added; those of the module docs.
    pub fn build_as_drawn(self, report: &mut LoadReport, face_lines: &[u32]) -> Result<Scene3> {
        if self.faces.is_empty() {
            return Err(ErrorKind::EmptyScene.into());
        }
        let (pairs, tol) = {
            let list = self.face_list();
            (coincident_face_pairs(&list)?, face_tolerance(&list))
        };
        if pairs.is_empty() {
            // The search just made is the strict build's
            return self.into_scene();
        }
        let line = |k: usize| face_lines.get(k).copied();
        // The fate of each later face of a pair, in input order
        let mut fates: Vec<(usize, Fate)> = Vec::new();
        let mut at = 0;
        while at < pairs.len() {
            let j = pairs[at].1;
            let end = at + pairs[at..].partition_point(|p| p.1 == j);
            let earlier: Vec<usize> = pairs[at..end].iter().map(|p| p.0).collect();
            at = end;
            let vj = self.face_vertices(j);
            if let Some(&i) = earlier
                .iter()
                .find(|&&i| same_polygon(self.face_vertices(i), vj, tol))
            {
                fates.push((j, Fate::Duplicate(i)));
                continue;
            }
            let mut pieces: Vec<Vec<DVec3>> = alloc::vec![vj.to_vec()];
            for &i in &earlier {
                let (ci, ni) = (self.face_vertices(i), self.faces[i].normal);
                let mut next = Vec::new();
                for p in &pieces {
                    difference(p, ci, ni, tol, &mut next);
                }
                if next.len() > MAX_CLIP_PIECES {
                    return Err(ErrorKind::TooLarge {
                        what: "pieces of one face cut by coincident faces",
                        max: MAX_CLIP_PIECES as u64,
                    }
                    .into());
                }
                pieces = next;
            }
            let first = earlier[0];
            fates.push((
                j,
                if pieces.is_empty() {
                    Fate::Covered(first)
                } else {
                    Fate::Clipped(first, pieces)
                },
            ));
        }
        // The faces again, in order, as their fates say
        let mut b = Scene3Builder {
            working_exponent: self.working_exponent,
            ..Scene3Builder::default()
        };
        let mut origin: Vec<usize> = Vec::with_capacity(self.faces.len());
        let mut scratch = LoadReport::default();
        let mut fates = fates.into_iter().peekable();
        for (k, f) in self.faces.iter().enumerate() {
            b.material(self.materials[f.material]);
            b.object(&self.objects[f.object]);
            let s = self.subdivisions[k];
            let fate = fates.next_if(|x| x.0 == k).map(|x| x.1);
            let before = b.faces.len();
            match fate {
                None => {
                    b.add_polygon(self.face_vertices(k), s)?;
                }
                Some(Fate::Duplicate(i)) => {
                    report.duplicates_dropped = report.duplicates_dropped.saturating_add(1);
                    report.warn_class(
                        line(k),
                        LoadWarningKind::DuplicateFace {
                            other_line: line(i),
                        },
                    );
                }
                Some(Fate::Covered(i)) => {
                    report.covered_dropped = report.covered_dropped.saturating_add(1);
                    report.warn_class(
                        line(k),
                        LoadWarningKind::CoveredFace {
                            other_line: line(i),
                        },
                    );
                }
                Some(Fate::Clipped(i, pieces)) => {
                    for p in &pieces {
                        // Pieces are convex and in the face's plane; what rounding made
                        // degenerate is dropped, and slivers are triangulated.
                        b.add_as_drawn(p, s, &mut scratch, line(k))?;
                    }
                    report.overlaps_clipped = report.overlaps_clipped.saturating_add(1);
                    report.clip_pieces = report
                        .clip_pieces
                        .saturating_add((b.faces.len() - before) as u64);
                    report.warn_class(
                        line(k),
                        LoadWarningKind::OverlapClipped {
                            other_line: line(i),
                        },
                    );
                }
            }
            origin.resize(b.faces.len(), k);
        }
        if scratch.pieces_dropped > 0 {
            report.pieces_dropped = report.pieces_dropped.saturating_add(scratch.pieces_dropped);
        }
        // The strict check of the result, its faces named by their index as added
        b.finish().map_err(|e| match *e.kind() {
            ErrorKind::CoincidentSurfaces { first, second } => ErrorKind::CoincidentSurfaces {
                first: origin.get(first).copied().unwrap_or(first),
                second: origin.get(second).copied().unwrap_or(second),
            }
            .into(),
            _ => e,
        })
    }

    /// The vertices of face `k` as added.
    fn face_vertices(&self, k: usize) -> &[DVec3] {
        let f = &self.faces[k];
        &self.points[f.first..f.first + f.count]
    }
}

/// Whether `a` and `b` are the same polygon: equal vertex counts and, for some cyclic
/// rotation, every vertex within `tol` per coordinate of its partner.
fn same_polygon(a: &[DVec3], b: &[DVec3], tol: f64) -> bool {
    let n = a.len();
    n == b.len()
        && (0..n).any(|r| (0..n).all(|k| (a[k] - b[(k + r) % n]).abs().max_element() <= tol))
}

/// Appends to `out` the convex pieces of `p − c` (module docs): `c` convex and
/// counter-clockwise about its unit normal `n`, `p` convex in the same plane. Pieces of no
/// area (at most `10⁻¹²` of the square of `p`'s size) are left out.
fn difference(p: &[DVec3], c: &[DVec3], n: DVec3, tol: f64, out: &mut Vec<Vec<DVec3>>) {
    let size = geom::bounds_diagonal(p);
    let min_twice_area = 2e-12 * size * size;
    let mut rest: Vec<DVec3> = p.to_vec();
    let m = c.len();
    for k in 0..m {
        let (a, b) = (c[k], c[(k + 1) % m]);
        // Unit normal of the edge's line, pointing into c
        let Some(inward) = n.cross(b - a).try_normalize() else {
            continue;
        };
        let (outside, inside) = split(&rest, a, inward, tol);
        if geom::polygon_normal(&outside).length() > min_twice_area {
            out.push(outside);
        }
        rest = inside;
        if geom::polygon_normal(&rest).length() <= min_twice_area {
            return;
        }
    }
}

/// The parts of the convex polygon `p` on either side of the line through `a` with unit
/// normal `m` (Sutherland–Hodgman): `(s ≤ 0, s ≥ 0)` with `s = m · (x − a)`, distances
/// within `tol` counted as zero.
fn split(p: &[DVec3], a: DVec3, m: DVec3, tol: f64) -> (Vec<DVec3>, Vec<DVec3>) {
    let side = |x: DVec3| {
        let s = m.dot(x - a);
        if s.abs() <= tol { 0.0 } else { s }
    };
    let (mut neg, mut pos) = (Vec::new(), Vec::new());
    let n = p.len();
    for k in 0..n {
        let (x, y) = (p[k], p[(k + 1) % n]);
        let (sx, sy) = (side(x), side(y));
        if sx <= 0.0 {
            neg.push(x);
        }
        if sx >= 0.0 {
            pos.push(x);
        }
        if (sx < 0.0 && sy > 0.0) || (sx > 0.0 && sy < 0.0) {
            let cut = x + (y - x) * (sx / (sx - sy));
            neg.push(cut);
            pos.push(cut);
        }
    }
    (neg, pos)
}

#[cfg(test)]
mod tests;
