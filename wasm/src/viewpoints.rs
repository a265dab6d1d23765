//! `viewpoints`: the viewpoint channel of a mesh given as OBJ text
//! ([`sceneinfo::viewpoint`]), as the JSON `sceneinfo viewpoints --json` prints.

use wasm_bindgen::prelude::*;

use crate::{count, into_error};

/// The viewpoint channel of the mesh `objText` (faces not subdivided, materials ignored):
/// `views` viewpoints on an icosphere at 3 bounding radii (12, 42, 162, 642, 2562 or
/// 10242), each rasterised at `resolution × resolution` pixels, `p(v)` uniform, and the
/// `best` best views.
///
/// Returns the JSON object of [`sceneinfo_report::viewpoints_obj_json`]: `i_vo`,
/// `h_o`, `h_o_given_v`, `best`, `selection`, `representative`, per-view `vmi`, `ve`,
/// `instability`, per-polygon `saliency`, `polygonal_mi`, … — byte for byte what
/// `sceneinfo viewpoints FILE.obj --views V --resolution N --best K --json` prints for the
/// same file (rows are independent of threads, and the arithmetic is the same on wasm32).
///
/// # Errors
///
/// Throws a JavaScript `Error` with the core's message for OBJ text that does not parse, a
/// view count that is not an icosphere's, a resolution of 0 or above the cap, or counts
/// that are not whole numbers.
#[wasm_bindgen]
pub fn viewpoints(
    #[wasm_bindgen(js_name = objText)] obj_text: &str,
    views: f64,
    resolution: f64,
    best: f64,
) -> Result<String, JsError> {
    let views = usize::try_from(count("views", views).map_err(into_error)?).unwrap_or(usize::MAX);
    let resolution =
        u32::try_from(count("resolution", resolution).map_err(into_error)?).unwrap_or(u32::MAX);
    let best = usize::try_from(count("best", best).map_err(into_error)?).unwrap_or(usize::MAX);
    sceneinfo_report::viewpoints_obj_json(obj_text, views, resolution, best).map_err(into_error)
}
