//! What a scene loader skipped or repaired ([`LoadReport`]), as JSON fields.

use core::fmt::{self, Write};

use sceneinfo::io::LoadReport;

use crate::json::JsonObject;

/// Writes the report's fields (`faces_read`, …) into a JSON object;
/// `materials_used` as in [`LoadReport::warnings_for`]; the repair counts (`faces_flattened`,
/// `max_off_plane`, `faces_triangulated`, …) only when not zero, and `load_warnings` only
/// when there is one, so a file that needed nothing prints what it always did.
///
/// # Errors
/// Whatever the underlying writer returns.
pub fn write_load_report<W: Write>(
    o: &mut JsonObject<'_, W>,
    report: &LoadReport,
    materials_used: bool,
) -> fmt::Result {
    o.integer("faces_read", report.faces_read)?;
    let counts = [
        ("repeated_vertices", report.repeated_vertices),
        ("faces_flattened", report.faces_flattened),
        ("faces_triangulated", report.faces_triangulated),
        ("triangles_added", report.triangles_added),
        ("pieces_dropped", report.pieces_dropped),
        ("duplicates_dropped", report.duplicates_dropped),
        ("covered_dropped", report.covered_dropped),
        ("overlaps_clipped", report.overlaps_clipped),
        ("clip_pieces", report.clip_pieces),
    ];
    for (key, v) in counts {
        if v > 0 {
            o.integer(key, v)?;
        }
    }
    if report.max_off_plane > 0.0 {
        o.number("max_off_plane", report.max_off_plane)?;
    }
    if report.warnings_for(materials_used).next().is_some() {
        o.displays("load_warnings", report.warnings_for(materials_used))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneinfo::io::LoadWarningKind;

    fn json(r: &LoadReport) -> String {
        let mut s = String::new();
        let mut o = JsonObject::new(&mut s).unwrap();
        write_load_report(&mut o, r, true).unwrap();
        o.finish().unwrap();
        s
    }

    #[test]
    fn repair_counts_are_written_only_when_something_was_repaired() {
        let mut r = LoadReport {
            faces_read: 3,
            ..LoadReport::default()
        };
        assert_eq!(json(&r), r#"{"faces_read":3}"#);
        r.faces_triangulated = 1;
        r.triangles_added = 4;
        r.max_off_plane = 0.5;
        r.warn(Some(7), LoadWarningKind::FaceTriangulated);
        assert_eq!(
            json(&r),
            r#"{"faces_read":3,"faces_triangulated":1,"triangles_added":4,"max_off_plane":0.5,"load_warnings":["line 7: cut a concave or non-planar face into triangles"]}"#
        );
    }
}
