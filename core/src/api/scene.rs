//! [`Scene`]: one scene type over flatland and 3D, read from text or built from arrays.

use alloc::boxed::Box;
use alloc::string::String;
use alloc::vec;
use alloc::vec::Vec;

use crate::error::{Error, ErrorKind, Result};
use crate::geom::{DVec2, DVec3};
use crate::io::{LoadReport, ObjOptions, parse_flat, parse_obj};
use crate::scene::{Material, Scene2, Scene3, Subdivision};
use crate::tally::LineTracer;
use crate::trace::estimate_2d::Tracer2;
use crate::trace::estimate_3d::Tracer3;

/// A scene: flatland segments ([`Scene2`]) or 3D planar convex patches ([`Scene3`]).
///
/// Read one from text with [`Scene::from_text`] (or bytes, [`Scene::from_bytes`]), build one
/// from arrays ([`Scene::from_segments`], [`Scene::from_triangles`],
/// [`Scene::from_polygons`]), or wrap a [`Scene2`] / [`Scene3`] built otherwise (a PLY or
/// glTF reader, the presets) with `Scene::from`.
#[derive(Clone, Debug, PartialEq)]
pub enum Scene {
    /// A flatland scene: segments cut into patches (the `.flat` format).
    Flat(Scene2),
    /// A 3D scene: planar convex faces cut into patches (OBJ, PLY, glTF).
    Solid(Scene3),
}

impl From<Scene2> for Scene {
    fn from(s: Scene2) -> Self {
        Scene::Flat(s)
    }
}

impl From<Scene3> for Scene {
    fn from(s: Scene3) -> Self {
        Scene::Solid(s)
    }
}

/// The text formats the core reads ([`crate::io`]). PLY and glTF are read by front ends,
/// which build a [`Scene3`] and wrap it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum SceneFormat {
    /// The flatland format (`.flat`, [`crate::io::parse_flat`]).
    Flat,
    /// Wavefront OBJ with MTL libraries ([`crate::io::parse_obj`]), read with these options.
    Obj(ObjOptions),
}

impl Scene {
    /// Reads a scene from `text` in `format`. An OBJ's `mtllib` names are looked up through
    /// `mtl` (`None`: not found, a warning and the default material), as
    /// [`crate::io::parse_obj`] does; a flatland file ignores `mtl`. The [`LoadReport`] says
    /// what the loader skipped or repaired (empty for flatland).
    ///
    /// # Errors
    /// The parser's errors, with their 1-based line.
    pub fn from_text(
        text: &str,
        format: SceneFormat,
        mtl: impl Fn(&str) -> Option<String>,
    ) -> Result<(Scene, LoadReport)> {
        match format {
            SceneFormat::Flat => Ok((Scene::Flat(parse_flat(text)?), LoadReport::default())),
            SceneFormat::Obj(options) => {
                let (scene, report) = parse_obj(text, &options, mtl)?;
                Ok((Scene::Solid(scene), report))
            }
        }
    }

    /// [`Scene::from_text`] of `bytes`, which must be UTF-8.
    ///
    /// # Errors
    /// [`ErrorKind::InvalidUtf8`] at the line of the first invalid byte (lines end at LF,
    /// CRLF or a lone CR, as the parsers count them); then those of [`Scene::from_text`].
    pub fn from_bytes(
        bytes: &[u8],
        format: SceneFormat,
        mtl: impl Fn(&str) -> Option<String>,
    ) -> Result<(Scene, LoadReport)> {
        match core::str::from_utf8(bytes) {
            Ok(text) => Self::from_text(text, format, mtl),
            Err(e) => {
                let before = &bytes[..e.valid_up_to()];
                // Line breaks before the bad byte: every LF, and every CR not before an LF
                let breaks = before
                    .iter()
                    .enumerate()
                    .filter(|&(k, &b)| {
                        b == b'\n' || (b == b'\r' && bytes.get(k + 1) != Some(&b'\n'))
                    })
                    .count();
                let line = u32::try_from(breaks).map_or(u32::MAX, |b| b.saturating_add(1));
                Err(Error::at_line(ErrorKind::InvalidUtf8, line))
            }
        }
    }

    /// A flatland scene of one patch per segment `[x0, y0, x1, y1]` (each its own surface,
    /// facing its left side: normal = left perpendicular of `b − a`), with `materials[k]`
    /// for segment `k` (default [`Material::BLACK`]).
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] when `materials` is not one per segment; the
    /// builder's errors ([`crate::scene::Scene2Builder::segment`],
    /// [`crate::scene::Scene2Builder::build`]) with the 1-based row of the segment as their
    /// line.
    pub fn from_segments(segments: &[[f64; 4]], materials: Option<&[Material]>) -> Result<Scene> {
        check_materials(materials, segments.len())?;
        let mut builder = Scene2::builder();
        for (k, s) in segments.iter().enumerate() {
            let row = row_of(k);
            builder.material(materials.map_or(Material::BLACK, |m| m[k]));
            builder
                .segment(DVec2::new(s[0], s[1]), DVec2::new(s[2], s[3]), 1)
                .map_err(|e| e.with_line(row))?;
        }
        Ok(Scene::Flat(builder.build()?))
    }

    /// A 3D scene of one patch per triangle of `vertices` (indices into `vertices`, front
    /// side counter-clockwise by the right-hand rule, as in OBJ), with `materials[k]` for
    /// triangle `k` (default [`Material::BLACK`]).
    ///
    /// # Errors
    /// As [`Scene::from_polygons`].
    pub fn from_triangles(
        vertices: &[[f64; 3]],
        triangles: &[[u32; 3]],
        materials: Option<&[Material]>,
    ) -> Result<Scene> {
        check_materials(materials, triangles.len())?;
        let mut builder = Scene3::builder();
        let mut face = Vec::with_capacity(3);
        for (k, t) in triangles.iter().enumerate() {
            add_face(&mut builder, vertices, t, materials, k, &mut face)?;
        }
        Ok(Scene::Solid(builder.finish()?))
    }

    /// A 3D scene of one patch per polygon: polygon `k` has the vertices
    /// `indices[offsets[k] .. offsets[k + 1]]` (so `offsets` has one entry more than there
    /// are polygons, starting at 0), planar and convex, front side counter-clockwise by the
    /// right-hand rule; `materials[k]` is its material (default [`Material::BLACK`]).
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] when `materials` is not one per polygon;
    /// [`ErrorKind::BadParameter`] (`"offsets"`) when the offsets do not start at 0, decrease
    /// or pass the end of `indices`; [`ErrorKind::VertexIndex`] for an index past the
    /// vertices; the builder's errors ([`crate::scene::Scene3Builder::polygon`],
    /// [`crate::scene::Scene3Builder::build`]). Errors of one polygon carry its 1-based row
    /// as their line.
    pub fn from_polygons(
        vertices: &[[f64; 3]],
        indices: &[u32],
        offsets: &[u32],
        materials: Option<&[Material]>,
    ) -> Result<Scene> {
        let n = offsets.len().saturating_sub(1);
        check_materials(materials, n)?;
        let bad = |value: u32| -> Error {
            ErrorKind::BadParameter {
                name: "offsets",
                value: f64::from(value),
            }
            .into()
        };
        if offsets.first().is_some_and(|&o| o != 0) {
            return Err(bad(offsets[0]));
        }
        let mut builder = Scene3::builder();
        let mut face = Vec::new();
        for (k, w) in offsets.windows(2).enumerate() {
            let (a, b) = (w[0] as usize, w[1] as usize);
            let Some(polygon) = indices.get(a..b) else {
                return Err(bad(w[1]).with_line(row_of(k)));
            };
            add_face(&mut builder, vertices, polygon, materials, k, &mut face)?;
        }
        Ok(Scene::Solid(builder.finish()?))
    }

    /// The exact form factors [`Measurement::exact`](crate::Measurement::exact) measures:
    /// flatland ones with occlusion (`formfactor::exact_2d`), or unoccluded 3D ones (the
    /// contour integral, 2.16; `formfactor::exact_3d`).
    ///
    /// # Errors
    /// Those of the exact form factors; [`ErrorKind::MayBeOccluded`] when some 3D polygon
    /// may hide part of another ([`Measurement::exact_within`](crate::Measurement::exact_within)
    /// computes those, with occlusion, to a tolerance).
    pub fn exact_form_factors(&self) -> Result<crate::formfactor::FormFactors> {
        match self {
            Scene::Flat(s) => crate::formfactor::exact_2d::form_factors(s),
            Scene::Solid(s) => crate::formfactor::exact_3d::scene_form_factors(s),
        }
    }

    /// Whether this is a flatland scene.
    #[must_use]
    pub fn is_flat(&self) -> bool {
        matches!(self, Scene::Flat(_))
    }

    /// Number of patches (the states of the channel, the background aside).
    #[must_use]
    pub fn n_patches(&self) -> usize {
        match self {
            Scene::Flat(s) => s.n_patches(),
            Scene::Solid(s) => s.n_patches(),
        }
    }

    /// Relative sizes `a_i = A_i / A_T` of the patches (lengths in flatland, areas in 3D):
    /// the channel's input distribution (3.3).
    #[must_use]
    pub fn patch_sizes(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.n_patches()];
        // `out` has one entry per patch, so neither call can fail
        let _ = match self {
            Scene::Flat(s) => s.relative_lengths_into(&mut out),
            Scene::Solid(s) => s.relative_areas_into(&mut out),
        };
        out
    }

    /// The material of every patch, in patch order (the radiosity system's `ρ_i`, `E_i`,
    /// 2.6).
    #[must_use]
    pub fn patch_materials(&self) -> Vec<Material> {
        match self {
            Scene::Flat(s) => s.patch_materials(),
            Scene::Solid(s) => s.patch_materials(),
        }
    }

    /// The line tracer of this scene ([`Tracer2`] or [`Tracer3`]): what a line job casts
    /// through.
    ///
    /// # Errors
    /// The tracer constructors' errors (a scene too large for the acceleration structure).
    pub fn tracer(&self) -> Result<SceneTracer> {
        Ok(SceneTracer(match self {
            Scene::Flat(s) => Box::new(Tracer2::new(s)?),
            Scene::Solid(s) => Box::new(Tracer3::new(s)?),
        }))
    }
}

/// The line tracer of a [`Scene`] ([`Scene::tracer`]): a [`Tracer2`] or a [`Tracer3`]
/// behind one [`LineTracer`].
pub struct SceneTracer(Box<dyn LineTracer + Send + Sync>);

impl core::fmt::Debug for SceneTracer {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("SceneTracer")
            .field("n_patches", &self.0.n_patches())
            .finish_non_exhaustive()
    }
}

impl SceneTracer {
    /// The tracer of a flatland scene alone. [`Scene::tracer`] can return either kind, so a
    /// caller that uses it links the 3D tracer too; the browser lab, which only ever traces
    /// flatland, starts from this one to keep its module small.
    ///
    /// # Errors
    /// [`Tracer2::new`]'s.
    pub fn flat(scene: &Scene2) -> Result<Self> {
        Ok(Self(Box::new(Tracer2::new(scene)?)))
    }

    /// The tracer as a [`LineTracer`] that can be shared between threads.
    #[must_use]
    pub fn as_dyn(&self) -> &(dyn LineTracer + Sync) {
        &*self.0
    }
}

/// The 1-based row of item `k`, as an error's line.
fn row_of(k: usize) -> u32 {
    u32::try_from(k).map_or(u32::MAX, |k| k.saturating_add(1))
}

/// Refuses materials that are not one per item.
fn check_materials(materials: Option<&[Material]>, n: usize) -> Result<()> {
    match materials {
        Some(m) if m.len() != n => Err(ErrorKind::DimensionMismatch {
            expected: n,
            found: m.len(),
        }
        .into()),
        _ => Ok(()),
    }
}

/// Adds the face of `vertices[indices]` (row `k`) to `builder`, unsubdivided.
fn add_face(
    builder: &mut crate::scene::Scene3Builder,
    vertices: &[[f64; 3]],
    indices: &[u32],
    materials: Option<&[Material]>,
    k: usize,
    face: &mut Vec<DVec3>,
) -> Result<()> {
    let row = row_of(k);
    face.clear();
    for &i in indices {
        let Some(v) = vertices.get(i as usize) else {
            return Err(Error::at_line(
                ErrorKind::VertexIndex {
                    index: u64::from(i),
                    count: vertices.len(),
                },
                row,
            ));
        };
        face.push(DVec3::new(v[0], v[1], v[2]));
    }
    builder.material(materials.map_or(Material::BLACK, |m| m[k]));
    builder
        .polygon(face, Subdivision::None)
        .map_err(|e| e.with_line(row))?;
    Ok(())
}
