//! Faces as drawn: the lenient entry the loaders use, which repairs what real files hold
//! (repeated vertices, slightly non-planar or concave polygons) instead of refusing it.
//!
//! # Rule ([`Scene3Builder::face_as_drawn`])
//!
//! With `d` the face's size (the diagonal of its bounding box, as in
//! [`Scene3Builder::polygon`]):
//!
//! 1. consecutive repeated vertices (an edge at most [`REPEATED_VERTEX_TOLERANCE`]` · d`,
//!    the last vertex against the first included) are removed;
//! 2. a face planar within [`PLANARITY_TOLERANCE`]` · d` and convex is added by
//!    [`Scene3Builder::polygon`] unchanged — the same scene, bit for bit, as the strict
//!    builder gives;
//! 3. a convex face planar within [`DRAWN_PLANARITY_TOLERANCE`]` · d` is projected onto its
//!    Newell plane through its vertex mean (the plane [`geom::plane_deviation`] measures
//!    from) and added as one face (`faces_flattened`, `max_off_plane`);
//! 4. anything else — concave, further off its plane, a polygon with straight or
//!    doubled-back vertices the strict checks refuse — is triangulated
//!    ([`crate::scene::triangulate`]: the flattest diagonal of a quad, ear clipping in the
//!    Newell plane otherwise) and each triangle added as its own face, cut by the same
//!    subdivision (`faces_triangulated`, `triangles_added`);
//!    A self-intersecting quad (a bow tie) is cut at its crossing into its two lobes
//!    instead ([`crate::scene::triangulate::bow_tie_lobes`]), each a triangle facing the
//!    way its winding says (a renderer draws both);
//! 5. triangles of zero area (at most `10⁻¹² d²`, or an edge at most `10⁻¹² d`, as the
//!    strict builder's degeneracy test), flipped against the face's normal (only from a
//!    self-intersecting polygon), and faces left with fewer than three vertices are dropped
//!    with a warning (`pieces_dropped`).
//!
//! Errors stay errors where nothing sensible can be drawn: a vertex count outside
//! `3..=`[`MAX_FACE_VERTICES`](super::MAX_FACE_VERTICES), non-finite or out-of-range coordinates, a bad subdivision,
//! too many patches.
//!
//! `10⁻³` for the drawn tolerance: exporters' round-off and hand-made boxes stay within it
//! (Blender's Suzanne is `2.6 · 10⁻⁴` off its plane, a Cornell box quad `0.005` in a
//! 550-unit box about `6 · 10⁻⁶`); moving a vertex by a thousandth of the face's size
//! changes its form factors by about as much, below what the Monte Carlo estimates
//! resolve. A face bent further is meant as two triangles, and cut so.

use alloc::vec::Vec;

use super::{
    CONVEXITY_TOLERANCE, DEGENERACY_TOLERANCE, MAX_PATCHES_3D, PLANARITY_TOLERANCE, Scene3Builder,
    Subdivision, check_face_input, scale_face,
};
use crate::error::{ErrorKind, Result};
use crate::geom::{self, DVec3};
use crate::scene::triangulate::{bow_tie_lobes, triangulate};
use crate::scene::{LoadReport, LoadWarningKind};

/// Largest distance of a vertex from a face's Newell plane, relative to its size, for the
/// face to be flattened rather than triangulated (module docs).
pub(crate) const DRAWN_PLANARITY_TOLERANCE: f64 = 1e-3;

/// Longest edge, relative to a face's size, whose end repeats its start (module docs).
pub(crate) const REPEATED_VERTEX_TOLERANCE: f64 = 1e-12;

/// What [`Scene3Builder::add_triangles`] needs of the face its triangles come from.
#[derive(Clone, Copy)]
struct Pieces {
    /// The face's size (bounding-box diagonal), for the degeneracy tolerance.
    size: f64,
    /// The face's largest vertex distance from its plane, relative to its size.
    off_plane: f64,
    /// The face's normal, when every triangle must face its way.
    facing: Option<DVec3>,
}

impl Scene3Builder {
    /// Adds the polygon through `vertices` as drawn in a file: repaired, flattened or
    /// triangulated by the rule of the module docs, what was done recorded in `report`
    /// (counts, and warnings at `line`). Counts the face in `report.faces_read`.
    ///
    /// A face [`Self::polygon`] accepts is added exactly as it adds it.
    ///
    /// # Errors
    /// [`ErrorKind::FaceVertexCount`], [`ErrorKind::NonFiniteNumber`],
    /// [`ErrorKind::CoordinateRange`], [`ErrorKind::BadSubdivision`],
    /// [`ErrorKind::TooManyPatches`] (checked before any piece of the face is added). On
    /// error the builder is unchanged.
    pub fn face_as_drawn(
        &mut self,
        vertices: &[DVec3],
        s: Subdivision,
        report: &mut LoadReport,
        line: Option<u32>,
    ) -> Result<()> {
        check_face_input(vertices)?;
        let exponent = self.exponent_for(vertices);
        let scaled = scale_face(vertices, exponent)?;
        let before = self.faces.len();
        self.add_as_drawn(&scaled, s, report, line)?;
        // Only a face that was kept sets the units (a dropped 10³⁰⁰ sliver must not)
        if self.faces.len() > before {
            self.working_exponent = Some(exponent);
        }
        Ok(())
    }

    /// [`Self::face_as_drawn`] for vertices already in working coordinates.
    pub(super) fn add_as_drawn(
        &mut self,
        vertices: &[DVec3],
        s: Subdivision,
        report: &mut LoadReport,
        line: Option<u32>,
    ) -> Result<()> {
        check_face_input(vertices)?;
        s.validate()?;
        let n = vertices.len();
        report.faces_read = report.faces_read.saturating_add(1);
        let size = geom::bounds_diagonal(vertices);
        // 1. Consecutive repeated vertices (a copy only when there are some)
        let tiny = REPEATED_VERTEX_TOLERANCE * size;
        let repeated = |a: DVec3, b: DVec3| (b - a).length() <= tiny;
        let has_repeats = (0..n).any(|k| repeated(vertices[k], vertices[(k + 1) % n]));
        let cleaned: Vec<DVec3>;
        let v: &[DVec3] = if has_repeats {
            let mut kept: Vec<DVec3> = Vec::with_capacity(n);
            for &p in vertices {
                if kept.last().is_none_or(|&q| !repeated(q, p)) {
                    kept.push(p);
                }
            }
            while kept.len() > 1 && repeated(kept[kept.len() - 1], kept[0]) {
                kept.pop();
            }
            report.repeated_vertices = report
                .repeated_vertices
                .saturating_add((n - kept.len()) as u64);
            report.warn(line, LoadWarningKind::RepeatedVertices);
            cleaned = kept;
            &cleaned
        } else {
            vertices
        };
        if v.len() < 3 || !(size > 0.0) {
            self.drop_pieces(report, line, 1);
            return Ok(());
        }
        // 2.–3. Planar (or nearly) and convex: one face
        let vector_area = geom::polygon_normal(v);
        let twice_area = vector_area.length();
        let mut off_plane = 0.0;
        if twice_area > DEGENERACY_TOLERANCE * size * size {
            let normal = vector_area / twice_area;
            let deviation = geom::plane_deviation(v, normal);
            off_plane = deviation / size;
            if geom::is_convex(v, normal, CONVEXITY_TOLERANCE) {
                if deviation <= PLANARITY_TOLERANCE * size {
                    match self.add_polygon(v, s) {
                        Ok(_) => return Ok(()),
                        Err(e) if !repairable(e.kind()) => return Err(e),
                        Err(_) => {}
                    }
                } else if deviation <= DRAWN_PLANARITY_TOLERANCE * size {
                    let mean = v.iter().copied().sum::<DVec3>() / v.len() as f64;
                    let flat: Vec<DVec3> = v
                        .iter()
                        .map(|&p| p - normal * (p - mean).dot(normal))
                        .collect();
                    match self.add_polygon(&flat, s) {
                        Ok(_) => {
                            report.faces_flattened = report.faces_flattened.saturating_add(1);
                            report.max_off_plane = report.max_off_plane.max(off_plane);
                            report.warn(line, LoadWarningKind::FaceFlattened);
                            return Ok(());
                        }
                        Err(e) if !repairable(e.kind()) => return Err(e),
                        Err(_) => {}
                    }
                }
            }
        }
        // 4. A bow tie: its two lobes, each facing the way its winding says
        if let Some(lobes) = bow_tie_lobes(v) {
            let pieces = Pieces {
                size,
                off_plane,
                facing: None,
            };
            return self.add_triangles(&lobes, pieces, s, report, line);
        }
        // 4. Triangles, each facing the way the face does
        let mut triangles: Vec<[usize; 3]> = Vec::with_capacity(v.len());
        let Some(normal) = triangulate(v, &mut triangles) else {
            self.drop_pieces(report, line, 1);
            return Ok(());
        };
        let triangles: Vec<[DVec3; 3]> = triangles.iter().map(|t| t.map(|k| v[k])).collect();
        let pieces = Pieces {
            size,
            off_plane,
            facing: Some(normal),
        };
        self.add_triangles(&triangles, pieces, s, report, line)
    }

    /// Adds the triangles a face was cut into, checked against the patch cap before any is
    /// added; (5.) zero-area ones, and those turned against `pieces.facing` when given (only
    /// from a self-intersecting polygon), are dropped. Counts a triangulated face if any
    /// triangle was added, else the face as one dropped piece.
    fn add_triangles(
        &mut self,
        triangles: &[[DVec3; 3]],
        pieces: Pieces,
        s: Subdivision,
        report: &mut LoadReport,
        line: Option<u32>,
    ) -> Result<()> {
        let per_triangle = s.patch_count(3, 3);
        let total = (self.patches.len() as u64)
            .saturating_add(per_triangle.saturating_mul(triangles.len() as u64));
        if total > MAX_PATCHES_3D as u64 {
            return Err(ErrorKind::TooManyPatches {
                max: MAX_PATCHES_3D as u64,
            }
            .into());
        }
        let size = pieces.size;
        let (mut added, mut dropped) = (0u64, 0u64);
        for t in triangles {
            let [a, b, c] = *t;
            let vector_area = (b - a).cross(c - a);
            let short = [b - a, c - b, a - c]
                .iter()
                .any(|e| e.length() <= DEGENERACY_TOLERANCE * size);
            let flipped = pieces.facing.is_some_and(|n| !(vector_area.dot(n) > 0.0));
            if short || !(vector_area.length() > DEGENERACY_TOLERANCE * size * size) || flipped {
                dropped += 1;
                continue;
            }
            match self.add_polygon(t, s) {
                Ok(_) => added += 1,
                Err(e) if !repairable(e.kind()) => return Err(e),
                Err(_) => dropped += 1,
            }
        }
        if added > 0 {
            report.faces_triangulated = report.faces_triangulated.saturating_add(1);
            report.triangles_added = report.triangles_added.saturating_add(added);
            report.max_off_plane = report.max_off_plane.max(pieces.off_plane);
            report.warn(line, LoadWarningKind::FaceTriangulated);
        } else {
            // Nothing drawable: the face as a whole is the dropped piece
            dropped = 1;
        }
        self.drop_pieces(report, line, dropped);
        Ok(())
    }

    /// Counts `count` dropped pieces (none: nothing recorded).
    fn drop_pieces(&self, report: &mut LoadReport, line: Option<u32>, count: u64) {
        if count > 0 {
            report.pieces_dropped = report.pieces_dropped.saturating_add(count);
            report.warn(line, LoadWarningKind::PieceDropped);
        }
    }
}

/// Whether a strict refusal of one face is geometry the lenient rule repairs (by cutting
/// into triangles, or dropping), rather than an error of the input as a whole.
fn repairable(kind: &ErrorKind) -> bool {
    matches!(
        kind,
        ErrorKind::DegenerateFace | ErrorKind::NonPlanarFace { .. } | ErrorKind::NonConvexFace
    )
}

#[cfg(test)]
mod tests;
