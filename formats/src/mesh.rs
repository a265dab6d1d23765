//! The one door through which the mesh readers (glTF, PLY) add faces to a scene.
//!
//! Every face a reader finds goes through [`add_face`], so what is done to faces as files
//! draw them (skipping the degenerate ones today; triangulating concave or non-planar ones
//! later) is decided in one place for every format.

use std::fmt::Display;
use std::path::Path;

use anyhow::Result;
use sceneinfo::ErrorKind;
use sceneinfo::geom::DVec3;
use sceneinfo::io::{LoadReport, LoadWarningKind};
use sceneinfo::scene::{Scene3, Scene3Builder, Subdivision};

/// Most faces a reader reads from one file (skipped ones included) before it gives up: it
/// bounds the work on files whose faces are all skipped (a glTF mesh instanced many times,
/// degenerate triangles); kept faces are capped sooner by the scene's patch cap.
pub const MAX_FACES_READ: u64 = 1 << 28;

/// Adds the face through `vertices` (front side counter-clockwise, as in OBJ) to `builder`
/// as a file draws it ([`Scene3Builder::face_as_drawn`]: repeated vertices removed, nearly
/// planar faces flattened, concave or bent ones triangulated, zero-area ones dropped, all
/// counted in `report`), as the OBJ reader does. A face with fewer than three vertices is
/// skipped with a [`LoadWarningKind::DegenerateFace`] warning (glTF triangle strips hold
/// such triangles on purpose).
///
/// # Errors
/// `file: where: what` for a face the scene cannot take (non-finite or out-of-range
/// coordinates, too many vertices or patches) and past [`MAX_FACES_READ`] faces;
/// `location` says where in the file.
pub fn add_face(
    builder: &mut Scene3Builder,
    vertices: &[DVec3],
    report: &mut LoadReport,
    path: &Path,
    location: impl Display,
) -> Result<()> {
    if report.faces_read >= MAX_FACES_READ {
        anyhow::bail!(
            "{}: {location}: more than {MAX_FACES_READ} faces: refused",
            path.display()
        );
    }
    if vertices.len() < 3 {
        report.faces_read += 1;
        report.warn(None, LoadWarningKind::DegenerateFace);
        return Ok(());
    }
    builder
        .face_as_drawn(vertices, Subdivision::None, report, None)
        .map_err(|e| crate::located_at(path, location, e.kind()))
}

/// The scene `builder` holds, coincident faces resolved as the OBJ reader resolves them
/// ([`Scene3Builder::build_as_drawn`]); when no face was kept, the error says what was
/// skipped.
///
/// # Errors
/// `file: what` from [`Scene3Builder::build_as_drawn`] (no face, …).
pub fn build(builder: Scene3Builder, report: &mut LoadReport, path: &Path) -> Result<Scene3> {
    let skipped = (!report.warnings.is_empty()).then(|| report.messages(true).join("; "));
    builder
        .build_as_drawn(report, &[])
        .map_err(|e| match (e.kind(), &skipped) {
            (ErrorKind::EmptyScene, Some(skipped)) => {
                anyhow::anyhow!("{}: {} ({skipped})", path.display(), e.kind())
            }
            _ => crate::located(path, &e),
        })
}
