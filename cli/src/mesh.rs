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
use sceneinfo::scene::{Scene, SceneBuilder, Subdivision};

/// Most faces a reader reads from one file (skipped ones included) before it gives up: it
/// bounds the work on files whose faces are all skipped (a glTF mesh instanced many times,
/// degenerate triangles); kept faces are capped sooner by the scene's patch cap.
pub const MAX_FACES_READ: u64 = 1 << 28;

/// Adds the face through `vertices` (front side counter-clockwise, as in OBJ) to `builder`
/// and counts it in `report`. A face with fewer than three vertices or no area is skipped
/// with a [`LoadWarningKind::DegenerateFace`] warning (glTF triangle strips hold such
/// triangles on purpose).
///
/// # Errors
/// `file: where: what` for a face the scene cannot take (not planar, not convex, too many
/// patches, …) and past [`MAX_FACES_READ`] faces; `location` says where in the file.
pub fn add_face(
    builder: &mut SceneBuilder,
    vertices: &[DVec3],
    report: &mut LoadReport,
    path: &Path,
    location: impl Display,
) -> Result<()> {
    report.faces_read = report.faces_read.saturating_add(1);
    if report.faces_read > MAX_FACES_READ {
        anyhow::bail!(
            "{}: {location}: more than {MAX_FACES_READ} faces: refused",
            path.display()
        );
    }
    if vertices.len() < 3 {
        report.warn(None, LoadWarningKind::DegenerateFace);
        return Ok(());
    }
    match builder.polygon(vertices, Subdivision::None) {
        Ok(_) => Ok(()),
        Err(e) if matches!(e.kind(), ErrorKind::DegenerateFace) => {
            report.warn(None, LoadWarningKind::DegenerateFace);
            Ok(())
        }
        Err(e) => Err(anyhow::anyhow!(
            "{}: {location}: {}",
            path.display(),
            e.kind()
        )),
    }
}

/// The scene `builder` holds; when no face was kept, the error says what was skipped.
///
/// # Errors
/// `file: what` from [`SceneBuilder::build`] (no face, coincident faces, …).
pub fn build(builder: &SceneBuilder, report: &LoadReport, path: &Path) -> Result<Scene> {
    builder.build().map_err(|e| {
        if matches!(e.kind(), ErrorKind::EmptyScene) && !report.warnings.is_empty() {
            anyhow::anyhow!(
                "{}: {} ({})",
                path.display(),
                e.kind(),
                report.messages(true).join("; ")
            )
        } else {
            crate::output::located(path, &e)
        }
    })
}
