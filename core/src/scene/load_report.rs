//! What a loader did to a file to make a scene of it: counts and located warnings.
//!
//! Real files (OBJ as exporters write it, glTF, PLY) hold things a [`Scene3`](crate::scene::Scene3)
//! cannot: concave or slightly non-planar polygons, duplicated faces, statements and material
//! parameters sceneinfo does not use. The loaders repair or skip what a renderer would draw
//! anyway and say so here, instead of refusing the file. Warnings of one kind are gathered
//! into one entry with the first line where it happened and how many times.

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt::{self, Write};

use crate::error::Token;

/// One kind of repair or skip, with the data that identifies its class (two warnings that
/// compare equal are counted in one entry).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum LoadWarningKind {
    /// An OBJ statement of the specification (or a common extension of it, like `t`) that
    /// carries nothing sceneinfo uses (free-form curves and surfaces, `lod`, `bevel`, …):
    /// skipped.
    SkippedStatement {
        /// The statement's keyword.
        keyword: Token,
    },
    /// An OBJ statement sceneinfo does not know (neither in the specification nor a common
    /// extension): skipped, as renderers' loaders do.
    UnknownStatement {
        /// The statement's keyword.
        keyword: Token,
    },
    /// An `mtllib` library the caller could not provide (empty: an `mtllib` without a
    /// name); faces using its materials get the default material.
    MissingMaterialLibrary {
        /// The library's name as written.
        library: Token,
    },
    /// A `usemtl` name no library defines (empty: a `usemtl` without a name); its faces get
    /// the default material.
    UnknownMaterial {
        /// The material's name.
        name: Token,
    },
    /// A reflectance above [`Material::MAX_REFLECTANCE`](crate::scene::Material::MAX_REFLECTANCE) (`Kd 1`,
    /// common in real files; ρ must be below 1 for B = E + ρFB to converge) clamped to it.
    /// The value and line are the first met in the library; the entry counts them all.
    ReflectanceClamped {
        /// The material library.
        library: Token,
        /// Its 1-based line with the first clamped value.
        line: u32,
        /// The first clamped value.
        value: f64,
    },
    /// No material used emits (no `Ke`), but some have an ambient colour `Ka` > 0 and no
    /// `Ke`: old-style lamps, which emit only when `Ka` is read as the emittance (option
    /// `emit_from_ka`).
    AmbientOnlyLamps {
        /// The first such material.
        material: Token,
        /// How many such materials are used.
        materials: u64,
    },
    /// The file's content is of another format than its extension says; it was read as
    /// its content says.
    FormatByContent {
        /// The file's extension.
        extension: Token,
        /// The format read (`"PLY"`, `"glTF"`, `"GLB"`, `"OBJ"`, `"flat"`).
        format: &'static str,
    },
    /// A face with fewer than three vertices or no area: skipped.
    DegenerateFace,
    /// glTF primitives that draw no surface (points, lines): skipped.
    NonSurfacePrimitive {
        /// The primitive's mode (`"POINTS"`, `"LINES"`, …).
        mode: &'static str,
    },
    /// A glTF base colour factor above
    /// [`Material::MAX_REFLECTANCE`](crate::scene::Material::MAX_REFLECTANCE) (white, 1)
    /// clamped to it.
    BaseColorClamped,
    /// Material data sceneinfo does not read (textures, vertex or face colours): skipped,
    /// the constant factors used instead.
    IgnoredMaterialData {
        /// What was ignored, e.g. `"base colour texture"`.
        what: &'static str,
    },
    /// Consecutive repeated vertices of a face (an edge at most `10⁻¹²` of the face's size)
    /// removed.
    RepeatedVertices,
    /// A convex face off its plane by more than the strict tolerance but within the drawn
    /// one, projected onto its Newell plane
    /// ([`Scene3Builder::face_as_drawn`](crate::scene::Scene3Builder::face_as_drawn)).
    FaceFlattened,
    /// A concave, non-planar or partly degenerate face cut into triangles, each its own face.
    FaceTriangulated,
    /// A zero-area piece of a face, or a wholly degenerate face, dropped.
    PieceDropped,
    /// A face repeating an earlier one (same vertices up to rotation, same facing): dropped.
    DuplicateFace {
        /// The earlier face's line (of the first such pair).
        other_line: Option<u32>,
    },
    /// A face wholly covered by earlier coincident faces facing the same way: dropped.
    CoveredFace {
        /// The line of an earlier face covering it (of the first such face).
        other_line: Option<u32>,
    },
    /// A face partly covered by earlier coincident faces facing the same way: the covered
    /// part cut away, the rest kept as convex pieces.
    OverlapClipped {
        /// The line of an earlier face overlapping it (of the first such face).
        other_line: Option<u32>,
    },
}

impl LoadWarningKind {
    /// Whether this warning concerns materials only (reflectance, emittance, libraries):
    /// commands that measure visibility ignore materials and do not print these.
    #[must_use]
    pub fn is_material(&self) -> bool {
        match self {
            Self::SkippedStatement { .. }
            | Self::UnknownStatement { .. }
            | Self::FormatByContent { .. }
            | Self::DegenerateFace
            | Self::NonSurfacePrimitive { .. }
            | Self::RepeatedVertices
            | Self::FaceFlattened
            | Self::FaceTriangulated
            | Self::PieceDropped
            | Self::DuplicateFace { .. }
            | Self::CoveredFace { .. }
            | Self::OverlapClipped { .. } => false,
            Self::MissingMaterialLibrary { .. }
            | Self::UnknownMaterial { .. }
            | Self::ReflectanceClamped { .. }
            | Self::AmbientOnlyLamps { .. }
            | Self::BaseColorClamped
            | Self::IgnoredMaterialData { .. } => true,
        }
    }
}

impl fmt::Display for LoadWarningKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::SkippedStatement { keyword } => write!(
                f,
                "skipped '{}' statements (nothing sceneinfo uses)",
                keyword
            ),
            Self::UnknownStatement { keyword } => write!(
                f,
                "skipped unknown '{}' statements (not an OBJ statement sceneinfo knows)",
                keyword
            ),
            Self::MissingMaterialLibrary { library } if library.is_empty() => {
                write!(f, "'mtllib' without a file name: skipped")
            }
            Self::MissingMaterialLibrary { library } => write!(
                f,
                "material library '{}' not found: its materials get the default \
                 (reflectance 0, emittance 0)",
                library
            ),
            Self::UnknownMaterial { name } if name.is_empty() => write!(
                f,
                "'usemtl' without a name: the faces that follow get the default material \
                 (reflectance 0, emittance 0)"
            ),
            Self::UnknownMaterial { name } => write!(
                f,
                "material '{}' is not defined by any mtllib: its faces get the default \
                 (reflectance 0, emittance 0)",
                name
            ),
            Self::ReflectanceClamped {
                library,
                line,
                value,
            } => write!(
                f,
                "material library '{}' line {line}: reflectance {value} clamped to {} \
                 (it must be below 1)",
                library,
                crate::scene::Material::MAX_REFLECTANCE
            ),
            Self::AmbientOnlyLamps {
                material,
                materials,
            } => {
                write!(
                    f,
                    "no material emits (no Ke > 0), but material '{}' ",
                    material
                )?;
                if *materials > 1 {
                    write!(f, "and {} more have", materials - 1)?;
                } else {
                    write!(f, "has")?;
                }
                write!(
                    f,
                    " an ambient Ka > 0 and no Ke: old-style lamps emit only when Ka is read \
                     as the emittance (emit_from_ka)"
                )
            }
            Self::FormatByContent { extension, format } => write!(
                f,
                "the extension says '.{}' but the content is {format}: read as {format}",
                extension
            ),
            Self::DegenerateFace => {
                write!(f, "skipped faces with fewer than 3 vertices or no area")
            }
            Self::NonSurfacePrimitive { mode } => {
                write!(f, "skipped {mode} primitives (they draw no surface)")
            }
            Self::BaseColorClamped => write!(
                f,
                "base colour factor above the largest reflectance (white, 1) clamped to {}",
                crate::scene::Material::MAX_REFLECTANCE
            ),
            Self::IgnoredMaterialData { what } => write!(f, "ignored {what}"),
            Self::RepeatedVertices => write!(f, "removed repeated vertices of a face"),
            Self::FaceFlattened => write!(f, "flattened a slightly non-planar face onto its plane"),
            Self::FaceTriangulated => write!(f, "cut a concave or non-planar face into triangles"),
            Self::PieceDropped => write!(f, "dropped a face or piece of zero area"),
            Self::DuplicateFace { other_line } => {
                write!(f, "dropped a duplicate face")?;
                of_line(f, *other_line)
            }
            Self::CoveredFace { other_line } => {
                write!(f, "dropped a face covered by coincident faces")?;
                of_line(f, *other_line)
            }
            Self::OverlapClipped { other_line } => {
                write!(f, "cut away the part of a face covered by coincident faces")?;
                of_line(f, *other_line)
            }
        }
    }
}

/// ` (line N)` naming the other face of a pair, when known.
fn of_line(f: &mut fmt::Formatter<'_>, line: Option<u32>) -> fmt::Result {
    match line {
        Some(l) => write!(f, " (of line {l})"),
        None => Ok(()),
    }
}

/// A gathered warning: its kind, the first 1-based line where it happened (if the format
/// has lines) and how many times.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadWarning {
    /// What happened.
    pub kind: LoadWarningKind,
    /// The first line where it happened.
    pub first_line: Option<u32>,
    /// How many times it happened.
    pub count: u64,
}

impl fmt::Display for LoadWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.first_line {
            write!(f, "line {line}: ")?;
        }
        write!(f, "{}", self.kind)?;
        if self.count > 1 {
            write!(f, " ({} times)", self.count)?;
        }
        Ok(())
    }
}

/// What a loader did: face counts and the warnings, in the order first met.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LoadReport {
    /// Polygons read from the file, as written.
    pub faces_read: u64,
    /// Consecutive repeated vertices removed from faces.
    pub repeated_vertices: u64,
    /// Convex faces flattened onto their Newell plane.
    pub faces_flattened: u64,
    /// Largest distance of a vertex from its face's Newell plane, relative to the face's
    /// size, over the faces flattened or triangulated (0 if none).
    pub max_off_plane: f64,
    /// Faces cut into triangles.
    pub faces_triangulated: u64,
    /// Triangles those faces gave (kept ones).
    pub triangles_added: u64,
    /// Zero-area pieces and wholly degenerate faces dropped.
    pub pieces_dropped: u64,
    /// Faces dropped as duplicates of earlier ones.
    pub duplicates_dropped: u64,
    /// Faces dropped as wholly covered by earlier coincident ones.
    pub covered_dropped: u64,
    /// Faces partly covered by earlier coincident ones, cut down to their uncovered part.
    pub overlaps_clipped: u64,
    /// Convex pieces the uncovered parts of those faces gave.
    pub clip_pieces: u64,
    /// Warnings, one entry per class, in the order first met.
    pub warnings: Vec<LoadWarning>,
}

impl LoadReport {
    /// Records one occurrence of `kind` at `line`: a new entry, or one more of an equal
    /// kind already recorded.
    pub fn warn(&mut self, line: Option<u32>, kind: LoadWarningKind) {
        if let Some(w) = self.warnings.iter_mut().find(|w| w.kind == kind) {
            w.count = w.count.saturating_add(1);
        } else {
            self.warnings.push(LoadWarning {
                kind,
                first_line: line,
                count: 1,
            });
        }
    }

    /// Records one occurrence of `kind` at `line`, gathered with any earlier warning of the
    /// same variant whatever its data: the entry keeps the first occurrence's data and line
    /// (for pairs of faces, where one entry per pair would flood the report).
    pub fn warn_class(&mut self, line: Option<u32>, kind: LoadWarningKind) {
        let class = core::mem::discriminant(&kind);
        if let Some(w) = self
            .warnings
            .iter_mut()
            .find(|w| core::mem::discriminant(&w.kind) == class)
        {
            w.count = w.count.saturating_add(1);
        } else {
            self.warnings.push(LoadWarning {
                kind,
                first_line: line,
                count: 1,
            });
        }
    }

    /// The warnings a command prints: all of them, or without the material ones when
    /// `materials_used` is false (visibility commands).
    pub fn warnings_for(&self, materials_used: bool) -> impl Iterator<Item = &LoadWarning> {
        self.warnings
            .iter()
            .filter(move |w| materials_used || !w.kind.is_material())
    }

    /// The warnings as messages (see [`Self::warnings_for`]).
    #[must_use]
    pub fn messages(&self, materials_used: bool) -> Vec<String> {
        self.warnings_for(materials_used)
            .map(|w| {
                let mut s = String::new();
                let _ = write!(s, "{w}");
                s
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pair_warnings_gather_by_class_keeping_the_first_pair() {
        let mut r = LoadReport::default();
        for (line, other) in [(5, 1), (9, 2), (12, 3)] {
            r.warn_class(
                Some(line),
                LoadWarningKind::DuplicateFace {
                    other_line: Some(other),
                },
            );
        }
        r.warn_class(Some(20), LoadWarningKind::CoveredFace { other_line: None });
        assert_eq!(
            r.messages(false),
            [
                "line 5: dropped a duplicate face (of line 1) (3 times)",
                "line 20: dropped a face covered by coincident faces",
            ]
        );
        assert!(r.warnings.iter().all(|w| !w.kind.is_material()));
    }
}
