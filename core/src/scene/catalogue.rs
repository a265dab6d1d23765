//! The catalogue of the thesis' flatland scenes: every scene of §3.3, §4.5 and §6.5 that
//! the thesis draws, as a preset constructor on [`Scene2`], plus a by-name index.
//!
//! The thesis' figures were drawings whose coordinates are lost. Each constructor documents
//! the geometry chosen here to reproduce its figure faithfully — same topology, same trend,
//! and, where the thesis prints a value, free parameters (an apex, a cut, a gap) set so that
//! quadrature of (4.12) or exact form factors give that value. The printed values are not
//! here: they are the thesis' data, `sceneinfo_report::thesis::CATALOGUE` (where `reproduce`,
//! the wasm lab and the tests of the geometries read them).
//! All enclosures run counter-clockwise (facing inwards) and all objects clockwise (facing
//! outwards), so every scene is closed: its form-factor rows sum to 1.
//!
//! `per_side` is the number of patches on one side of the enclosure (the reference side);
//! sides of other lengths get a proportional number of patches, at least one, unless a
//! constructor says otherwise. [`catalogue`] lists every scene by name and
//! [`catalogue_scene`] builds one from its name.

mod enclosures;
mod objects;

pub(crate) use objects::SINGULARITY_STEPS;

use crate::error::{ErrorKind, Result, token};
use crate::geom::{DVec2, distance, signed_area};
use crate::scene::{MAX_PATCHES_PER_SURFACE, Scene2, Scene2Builder};

/// One named scene of the catalogue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CatalogueEntry {
    /// The name `catalogue_scene` accepts, e.g. `"koch-2"`.
    pub name: &'static str,
    /// Where the thesis shows the scene, e.g. `"Fig. 4.12c"`.
    pub figure: &'static str,
    /// One line describing the scene.
    pub description: &'static str,
}

macro_rules! entry {
    ($name:literal, $figure:literal, $description:literal) => {
        CatalogueEntry {
            name: $name,
            figure: $figure,
            description: $description,
        }
    };
}

static CATALOGUE: &[CatalogueEntry] = &[
    entry!("star-0", "Fig. 4.11a", "regular 24-gon"),
    entry!("star-1", "Fig. 4.11b", "12-pointed star, inner radius 0.8"),
    entry!("star-2", "Fig. 4.11c", "12-pointed star, inner radius 0.6"),
    entry!("star-3", "Fig. 4.11d", "12-pointed star, inner radius 0.4"),
    entry!(
        "koch-0",
        "Fig. 4.12a",
        "Von Koch snowflake, level 0 (equilateral triangle)"
    ),
    entry!(
        "koch-1",
        "Fig. 4.12b",
        "Von Koch snowflake, level 1 (12 edges)"
    ),
    entry!(
        "koch-2",
        "Fig. 4.12c",
        "Von Koch snowflake, level 2 (48 edges)"
    ),
    entry!(
        "koch-3",
        "Fig. 4.12d",
        "Von Koch snowflake, level 3 (192 edges)"
    ),
    entry!(
        "koch-4",
        "Fig. 4.12e",
        "Von Koch snowflake, level 4 (768 edges)"
    ),
    entry!("triangle-0", "Fig. 4.13a", "equilateral triangle"),
    entry!(
        "triangle-1",
        "Fig. 4.13b",
        "triangle, apex a third of the way to (1.26, 0.4)"
    ),
    entry!(
        "triangle-2",
        "Fig. 4.13c",
        "triangle, apex two thirds of the way to (1.26, 0.4)"
    ),
    entry!(
        "triangle-3",
        "Fig. 4.13d",
        "obtuse triangle with apex (1.26, 0.4) over a unit base"
    ),
    entry!("l-room-0", "Fig. 4.14a", "square room"),
    entry!(
        "l-room-1",
        "Fig. 4.14b",
        "L-shaped room: unit square minus a 0.25 corner square"
    ),
    entry!(
        "l-room-2",
        "Fig. 4.14c",
        "L-shaped room: unit square minus a 0.5 corner square"
    ),
    entry!(
        "l-room-3",
        "Fig. 4.14d",
        "L-shaped room: unit square minus a 0.555 corner square"
    ),
    entry!(
        "three-objects-0",
        "Fig. 4.15a",
        "square room, square + triangle + rectangle at scale 0.25"
    ),
    entry!(
        "three-objects-1",
        "Fig. 4.15b",
        "square room, three objects at scale 0.4"
    ),
    entry!(
        "three-objects-2",
        "Fig. 4.15c",
        "square room, three objects at scale 0.55"
    ),
    entry!(
        "three-objects-3",
        "Fig. 4.15d",
        "square room, three objects at scale 0.7"
    ),
    entry!(
        "three-objects-4",
        "Fig. 4.15e",
        "square room, three objects at scale 0.85"
    ),
    entry!(
        "three-objects-5",
        "Fig. 4.15f",
        "square room, three objects at scale 1"
    ),
    entry!(
        "16-squares-0",
        "Fig. 4.16a",
        "16 squares almost touching each other at the centre"
    ),
    entry!(
        "16-squares-1",
        "Fig. 4.16b",
        "16 squares expanding, step 1 of 8"
    ),
    entry!(
        "16-squares-2",
        "Fig. 4.16c",
        "16 squares expanding, step 2 of 8"
    ),
    entry!(
        "16-squares-3",
        "Fig. 4.16d",
        "16 squares expanding, step 3 of 8"
    ),
    entry!(
        "16-squares-4",
        "Fig. 4.16e",
        "16 squares expanding, step 4 of 8 (middle)"
    ),
    entry!(
        "16-squares-5",
        "Fig. 4.16f",
        "16 squares expanding, step 5 of 8"
    ),
    entry!(
        "16-squares-6",
        "Fig. 4.16g",
        "16 squares expanding, step 6 of 8"
    ),
    entry!(
        "16-squares-7",
        "Fig. 4.16h",
        "16 squares expanding, step 7 of 8"
    ),
    entry!(
        "16-squares-8",
        "Fig. 4.16i",
        "16 squares almost touching the walls"
    ),
    entry!("pentagonal-star-0", "Fig. 4.18a", "empty regular pentagon"),
    entry!(
        "pentagonal-star-1",
        "Fig. 4.18b",
        "pentagon with a pentagram at scale 1/8"
    ),
    entry!(
        "pentagonal-star-2",
        "Fig. 4.18c",
        "pentagon with a pentagram at scale 2/8"
    ),
    entry!(
        "pentagonal-star-3",
        "Fig. 4.18d",
        "pentagon with a pentagram at scale 3/8"
    ),
    entry!(
        "pentagonal-star-4",
        "Fig. 4.18e",
        "pentagon with a pentagram at scale 4/8"
    ),
    entry!(
        "pentagonal-star-5",
        "Fig. 4.18f",
        "pentagon with a pentagram at scale 5/8"
    ),
    entry!(
        "pentagonal-star-6",
        "Fig. 4.18g",
        "pentagon with a pentagram at scale 6/8"
    ),
    entry!(
        "pentagonal-star-7",
        "Fig. 4.18h",
        "pentagon with a pentagram at scale 7/8"
    ),
    entry!(
        "pentagonal-star-8",
        "Fig. 4.18i",
        "pentagram points 0.01% from the pentagon's vertices"
    ),
    entry!(
        "pentagonal-star-subscene",
        "Table 4.12",
        "golden triangle between a pentagon side and the pentagram"
    ),
    entry!(
        "rotating-square-0",
        "Fig. 4.19a",
        "square room, interior square with parallel sides"
    ),
    entry!(
        "rotating-square-1",
        "Fig. 4.19b",
        "square room, interior square rotated 5.625°"
    ),
    entry!(
        "rotating-square-2",
        "Fig. 4.19c",
        "square room, interior square rotated 11.25°"
    ),
    entry!(
        "rotating-square-3",
        "Fig. 4.19d",
        "square room, interior square rotated 16.875°"
    ),
    entry!(
        "rotating-square-4",
        "Fig. 4.19e",
        "square room, interior square rotated 22.5°"
    ),
    entry!(
        "rotating-square-5",
        "Fig. 4.19f",
        "square room, interior square rotated 28.125°"
    ),
    entry!(
        "rotating-square-6",
        "Fig. 4.19g",
        "square room, interior square rotated 33.75°"
    ),
    entry!(
        "rotating-square-7",
        "Fig. 4.19h",
        "square room, interior square rotated 39.375°"
    ),
    entry!(
        "rotating-square-8",
        "Fig. 4.19i",
        "interior square at 45°, vertices 0.01% from the wall midpoints"
    ),
    entry!(
        "rotating-square-subscene",
        "Table 4.12",
        "right isosceles triangle: a room corner cut by the rotated square"
    ),
    entry!(
        "square-to-corner-0",
        "Fig. 4.20a",
        "square room, interior square of half size at the centre"
    ),
    entry!(
        "square-to-corner-1",
        "Fig. 4.20b",
        "interior square advancing into a corner, step 1 of 8"
    ),
    entry!(
        "square-to-corner-2",
        "Fig. 4.20c",
        "interior square advancing into a corner, step 2 of 8"
    ),
    entry!(
        "square-to-corner-3",
        "Fig. 4.20d",
        "interior square advancing into a corner, step 3 of 8"
    ),
    entry!(
        "square-to-corner-4",
        "Fig. 4.20e",
        "interior square advancing into a corner, step 4 of 8"
    ),
    entry!(
        "square-to-corner-5",
        "Fig. 4.20f",
        "interior square advancing into a corner, step 5 of 8"
    ),
    entry!(
        "square-to-corner-6",
        "Fig. 4.20g",
        "interior square advancing into a corner, step 6 of 8"
    ),
    entry!(
        "square-to-corner-7",
        "Fig. 4.20h",
        "interior square advancing into a corner, step 7 of 8"
    ),
    entry!(
        "square-to-corner-8",
        "Fig. 4.20i",
        "interior square 1.6% of the room side from the corner walls"
    ),
    entry!("rect-1", "Fig. 4.22", "square (rectangle 1 × 1)"),
    entry!("rect-2", "Fig. 4.22", "rectangle 1 × 2"),
    entry!("rect-4", "Fig. 4.22", "rectangle 1 × 4"),
    entry!("rect-8", "Fig. 4.22", "rectangle 1 × 8"),
    entry!("rect-16", "Fig. 4.22", "rectangle 1 × 16"),
    entry!(
        "64-squares-a",
        "Fig. 3.12a",
        "64 squares in an 8 × 8 block with gaps 0.15 (most correlated)"
    ),
    entry!(
        "64-squares-b",
        "Fig. 3.12b",
        "64 squares in an 8 × 8 block with gaps 0.5"
    ),
    entry!(
        "64-squares-c",
        "Fig. 3.12c",
        "64 squares in an 8 × 8 block with gaps 0.85 (most random)"
    ),
    entry!(
        "refinement-1",
        "Fig. 6.15",
        "scene I: rectangular room with two boxes, 26 patches"
    ),
    entry!(
        "refinement-2",
        "Fig. 6.16",
        "scene II: square room with boxes near the walls, 26 patches"
    ),
];

/// [`CatalogueEntry::all`].
pub(crate) fn catalogue() -> &'static [CatalogueEntry] {
    CATALOGUE
}

/// [`Scene2::catalogue`].
pub(crate) fn catalogue_scene(name: &str, per_side: u64) -> Result<Scene2> {
    let unknown = || ErrorKind::UnknownPreset(token(name)).into();
    let step = |prefix: &str| -> Option<usize> { name.strip_prefix(prefix)?.parse().ok() };
    match name {
        "pentagonal-star-subscene" => return Scene2::pentagonal_star_subscene(per_side),
        "rotating-square-subscene" => return Scene2::rotating_square_subscene(per_side),
        "64-squares-a" => return Scene2::sixty_four_squares(0),
        "64-squares-b" => return Scene2::sixty_four_squares(1),
        "64-squares-c" => return Scene2::sixty_four_squares(2),
        "refinement-1" => return Scene2::refinement_scene_one(),
        "refinement-2" => return Scene2::refinement_scene_two(),
        _ => {}
    }
    if let Some(k) = name.strip_prefix("rect-") {
        let k: f64 = k.parse().map_err(|_| unknown())?;
        return Scene2::rectangle_aspect(k, per_side);
    }
    type Family = fn(usize, u64) -> Result<Scene2>;
    let families: [(&str, Family); 9] = [
        ("star-", Scene2::star_sequence),
        ("koch-", Scene2::von_koch),
        ("triangle-", Scene2::triangle_sequence),
        ("l-room-", Scene2::l_room_sequence),
        ("three-objects-", Scene2::three_objects),
        ("16-squares-", Scene2::sixteen_squares),
        ("pentagonal-star-", Scene2::pentagonal_star),
        ("rotating-square-", Scene2::rotating_square),
        ("square-to-corner-", Scene2::square_to_corner),
    ];
    for (prefix, build) in families {
        if let Some(k) = step(prefix) {
            // Only listed steps: an out-of-range step is an unknown name here.
            if CATALOGUE.iter().any(|e| e.name == name) {
                return build(k, per_side);
            }
        }
    }
    Err(unknown())
}

/// `Err(TooLarge)` unless `step < count`.
fn check_step(what: &'static str, step: usize, count: usize) -> Result<()> {
    if step < count {
        Ok(())
    } else {
        Err(ErrorKind::TooLarge {
            what,
            max: count as u64 - 1,
        }
        .into())
    }
}

/// `Err(PatchCount)` unless `1 ≤ per_side ≤` [`MAX_PATCHES_PER_SURFACE`] (the constructors
/// that derive other counts from `per_side` check it up front, as their derived counts are
/// never 0).
fn check_per_side(per_side: u64) -> Result<()> {
    if (1..=MAX_PATCHES_PER_SURFACE).contains(&per_side) {
        Ok(())
    } else {
        Err(ErrorKind::PatchCount {
            given: per_side,
            max: MAX_PATCHES_PER_SURFACE,
        }
        .into())
    }
}

/// Patches for a side of `length` when a side of `reference` length gets `per_side`:
/// `round(per_side · length / reference)`, at least 1.
fn proportional(length: f64, reference: f64, per_side: u64) -> u64 {
    let n = per_side as f64 * length / reference + 0.5;
    // `as` saturates; the builder rejects counts above its cap.
    (n as u64).max(1)
}

/// Adds the closed polygon through `vertices`, oriented to face inwards (counter-clockwise)
/// if `inwards`, outwards (clockwise) otherwise, each side cut into `patches(length)`.
fn add_polygon(
    b: &mut Scene2Builder,
    vertices: &[DVec2],
    inwards: bool,
    patches: impl Fn(f64) -> u64,
) -> Result<()> {
    let ccw = signed_area(vertices) > 0.0;
    let n = vertices.len();
    for k in 0..n {
        let (mut a, mut c) = (vertices[k], vertices[(k + 1) % n]);
        if ccw != inwards {
            core::mem::swap(&mut a, &mut c);
        }
        b.segment(a, c, patches(distance(a, c)))?;
    }
    Ok(())
}

#[cfg(all(test, feature = "std"))]
mod tests;

impl CatalogueEntry {
    /// Number of steps of the sequences of Figs. 4.16 and 4.18–4.20 (scenes a–i).
    pub const SINGULARITY_STEPS: usize = SINGULARITY_STEPS;

    /// Every scene of the catalogue, by name, in thesis order. Names of the form `rect-<k>`
    /// other than those listed are accepted too (any `k` [`Scene2::rectangle_aspect`]
    /// accepts).
    ///
    /// The families, each constructor documenting its geometry:
    ///
    /// | family | constructor | steps | thesis |
    /// |---|---|---|---|
    /// | 24-gon → 12-pointed stars | [`Scene2::star_sequence`] | 0–3 | Fig. 4.11 |
    /// | Von Koch snowflake | [`Scene2::von_koch`] | 0–4 | Fig. 4.12 |
    /// | equilateral → obtuse triangle | [`Scene2::triangle_sequence`] | 0–3 | Fig. 4.13 |
    /// | square → L-shaped rooms | [`Scene2::l_room_sequence`] | 0–3 | Fig. 4.14 |
    /// | three growing objects | [`Scene2::three_objects`] | 0–5 | Fig. 4.15 |
    /// | 16 squares expanding | [`Scene2::sixteen_squares`] | 0–8 | Figs. 4.16–4.17 |
    /// | growing pentagram | [`Scene2::pentagonal_star`] (+ `_subscene`) | 0–8 | Fig. 4.18, Table 4.12 |
    /// | rotating square | [`Scene2::rotating_square`] (+ `_subscene`) | 0–8 | Fig. 4.19, Table 4.12 |
    /// | square into a corner | [`Scene2::square_to_corner`] | 0–8 | Fig. 4.20 |
    /// | rectangle `1 × k` | [`Scene2::rectangle_aspect`] | `k > 0` | Fig. 4.22 |
    /// | 64 squares | [`Scene2::sixty_four_squares`] | a–c | Fig. 3.12, Tables 3.6, 3.9 |
    /// | refinement scenes I, II | [`Scene2::refinement_scene_one`], [`Scene2::refinement_scene_two`] | — | Figs. 6.15–6.18, Table 6.2 |
    ///
    /// `per_side` is the number of patches on one side of the enclosure; other sides get a
    /// proportional number (at least one) unless the constructor says otherwise.
    #[must_use]
    pub fn all() -> &'static [CatalogueEntry] {
        catalogue()
    }
}

impl Scene2 {
    /// The catalogue scene called `name`, its reference side cut into `per_side` patches.
    ///
    /// `per_side` is ignored by the scenes with a fixed discretisation: `64-squares-*` (80 + 256
    /// patches, as in the thesis) and `refinement-*` (26 patches).
    ///
    /// # Errors
    /// [`ErrorKind::UnknownPreset`] for a name not in `catalogue` (nor `rect-<k>`), and the
    /// errors of the constructor (e.g. for `per_side = 0`).
    pub fn catalogue(name: &str, per_side: u64) -> Result<Scene2> {
        catalogue_scene(name, per_side)
    }
}
