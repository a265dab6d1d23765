//! The thesis' 3D scenes as preset constructors on [`Scene3`], plus a by-name index.
//!
//! | family | constructor | thesis |
//! |---|---|---|
//! | unit cube enclosure, `k × k` patches a face | [`Scene3::cube`] | Fig. 3.5, Tables 3.2, 3.8, 4.1, 4.3 |
//! | platonic solids | [`Scene3::platonic`], [`Scene3::tetrahedron`], [`Scene3::octahedron`], [`Scene3::dodecahedron`], [`Scene3::icosahedron`] | Table 4.1 |
//! | tessellated sphere | [`Scene3::sphere`] | Table 4.1 |
//! | tetrahedron meshes | [`Scene3::tetrahedron_mesh`] | Fig. 4.3, Tables 4.5, 5.3 |
//! | Cornell box, blocks on or lifted from the floor | [`Scene3::cornell_box`] | Fig. 2.1a, Tables 4.1, 4.6 |
//! | cube room with `m³` small cubes, random or clustered | [`Scene3::cube_room_with_cubes`] | Figs. 3.3, 3.7, 3.8, Tables 3.1, 3.3, 4.4 |
//! | 64 cubes expanding from the centre to the walls | [`Scene3::sixty_four_cubes`] | Figs. 4.5, 4.6, Tables 4.7, 4.8 |
//! | room with tables and chairs | [`Scene3::table_and_chairs_room`] | Fig. 4.2, Table 4.2 |
//! | city block, `m × m` buildings on streets (open: no sky) | `Scene3::city_block` | none (issue 23) |
//!
//! The thesis' 3D figures are renderings whose coordinates are lost (the Cornell box excepted:
//! its geometry is published). Each constructor documents the geometry chosen here, and where
//! a thesis number pins a free parameter down (the cube side of the cube rooms, fixed by
//! `H_P`), how.
//!
//! Conventions of every preset:
//!
//! - **Closed.** Every scene is a union of closed surfaces (each edge of a face, split at the
//!   vertices of other faces lying on it, is shared with exactly one other face, traversed the
//!   other way), so every line leaving a patch meets another and form-factor rows sum to 1
//!   (the city block excepted: it is open to the sky).
//! - **Orientation.** The enclosure faces inwards: the object named [`ENCLOSURE`] (plus
//!   `"light"` in the Cornell box) holds the faces whose front side sees the room's interior.
//!   Every other object is a closed surface facing outwards, away from its own centre.
//! - **Gaps.** Objects never touch each other or the walls unless a constructor says so
//!   (the Cornell box's blocks standing on the floor); near contacts keep a documented gap.
//! - **Materials.** Diffuse; enclosures [`ENCLOSURE_MATERIAL`], objects [`OBJECT_MATERIAL`],
//!   no emitter, unless a constructor says otherwise (the Cornell box and the tetrahedron
//!   meshes carry lights).

mod city;
mod cornell;
mod cubes;
mod furniture;
mod solids;

pub(crate) use cubes::PRESET_SEED;
pub(crate) use cubes::SIXTY_FOUR_CUBES_STEPS;

use alloc::vec::Vec;

use crate::error::{ErrorKind, Result, token};
use crate::geom::{self, DVec3};
use crate::scene::{MAX_PATCHES_3D, Material, Scene3, Scene3Builder, Subdivision};

/// Name of the object holding a preset's enclosure (the room, or the inside of a solid).
pub(crate) const ENCLOSURE: &str = "enclosure";

/// The enclosures' material: ρ = 0.73 in every channel, no emission.
pub(crate) const ENCLOSURE_MATERIAL: Material = Material {
    reflectance: [0.73; 3],
    emittance: [0.0; 3],
};

/// The objects' material: ρ = 0.5 in every channel, no emission.
pub(crate) const OBJECT_MATERIAL: Material = Material {
    reflectance: [0.5; 3],
    emittance: [0.0; 3],
};

/// One named scene of the 3D preset index.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Preset3Entry {
    /// The name `preset_3d` accepts, e.g. `"cornell-lifted"`.
    pub name: &'static str,
    /// Where the thesis shows or uses the scene, e.g. `"Fig. 4.2c, Table 4.2"`.
    pub figure: &'static str,
    /// One line describing the scene.
    pub description: &'static str,
}

macro_rules! entry {
    ($name:literal, $figure:literal, $description:literal) => {
        Preset3Entry {
            name: $name,
            figure: $figure,
            description: $description,
        }
    };
}

static PRESETS_3D: &[Preset3Entry] = &[
    entry!(
        "cube",
        "Fig. 3.5, Tables 3.2, 3.8, 4.1, 4.3",
        "unit cube enclosure, each face grid × grid patches (600 at grid 10)"
    ),
    entry!(
        "tetrahedron",
        "Table 4.1",
        "regular tetrahedron in the unit sphere, 4 patches"
    ),
    entry!(
        "octahedron",
        "Table 4.1",
        "regular octahedron in the unit sphere, 8 patches"
    ),
    entry!(
        "dodecahedron",
        "Table 4.1",
        "regular dodecahedron in the unit sphere, 12 pentagonal patches"
    ),
    entry!(
        "icosahedron",
        "Table 4.1",
        "regular icosahedron in the unit sphere, 20 patches"
    ),
    entry!(
        "cornell",
        "Fig. 2.1a, Tables 4.1, 4.6",
        "Cornell box (published geometry), blocks on the floor, closed by a black front wall"
    ),
    entry!(
        "cornell-lifted",
        "Table 4.1 (footnote), Table 4.6",
        "Cornell box with both blocks lifted 0.2% of the room height from the floor"
    ),
    entry!(
        "cornell-thesis",
        "Figs. 4.4, 5.2I, Tables 4.6, 5.2, 5.5",
        "lifted Cornell box meshed as the thesis: grid = level 0-4, 19/121/481/1924/7696 patches"
    ),
    entry!(
        "cubes-27-random",
        "Fig. 3.7a, Table 3.3",
        "unit cube room (600 patches) with 27 cubes of side 0.05 at random"
    ),
    entry!(
        "cubes-27-clustered",
        "Fig. 3.7b, Table 3.3",
        "unit cube room (600 patches) with 27 cubes of side 0.05 packed in a 3 × 3 × 3 block"
    ),
    entry!(
        "cubes-64-random",
        "Fig. 3.8a, Table 3.3",
        "unit cube room (600 patches) with 64 cubes of side 0.05 at random"
    ),
    entry!(
        "cubes-64-clustered",
        "Fig. 3.8b, Table 3.3",
        "unit cube room (600 patches) with 64 cubes of side 0.05 packed in a 4 × 4 × 4 block"
    ),
    entry!(
        "cubes-512-random",
        "Fig. 3.3a, Tables 3.1, 3.3, 4.4",
        "unit cube room (600 patches) with 512 cubes of side 0.05 at random"
    ),
    entry!(
        "cubes-512-clustered",
        "Fig. 3.3c, Tables 3.1, 3.3",
        "unit cube room (600 patches) with 512 cubes of side 0.05 packed in an 8 × 8 × 8 block"
    ),
    entry!(
        "city-block",
        "issue 23 (not in the thesis)",
        "open city block: 8 × 8 box buildings 15-45 m tall on 20-m streets, 10,000 patches"
    ),
    entry!(
        "64-cubes-0",
        "Fig. 4.5a, Table 4.7",
        "64 cubes almost touching each other at the centre; cubes finer (1536 + 384 patches)"
    ),
    entry!(
        "64-cubes-1",
        "Fig. 4.5",
        "64 cubes expanding, step 1 of 8; cubes finer"
    ),
    entry!(
        "64-cubes-2",
        "Fig. 4.5",
        "64 cubes expanding, step 2 of 8; cubes finer"
    ),
    entry!(
        "64-cubes-3",
        "Fig. 4.5",
        "64 cubes expanding, step 3 of 8; cubes finer"
    ),
    entry!(
        "64-cubes-4",
        "Fig. 4.5",
        "64 cubes expanding, step 4 of 8 (middle); cubes finer"
    ),
    entry!(
        "64-cubes-5",
        "Fig. 4.5",
        "64 cubes expanding, step 5 of 8; cubes finer"
    ),
    entry!(
        "64-cubes-6",
        "Fig. 4.5",
        "64 cubes expanding, step 6 of 8; cubes finer"
    ),
    entry!(
        "64-cubes-7",
        "Fig. 4.5",
        "64 cubes expanding, step 7 of 8; cubes finer"
    ),
    entry!(
        "64-cubes-8",
        "Fig. 4.5f, Table 4.7",
        "64 cubes almost touching the walls; cubes finer"
    ),
    entry!(
        "64-cubes-0-fine",
        "Fig. 4.6a, Table 4.8",
        "64 cubes almost touching each other at the centre; walls finer (1536 + 384 patches)"
    ),
    entry!(
        "64-cubes-1-fine",
        "Fig. 4.6",
        "64 cubes expanding, step 1 of 8; walls finer"
    ),
    entry!(
        "64-cubes-2-fine",
        "Fig. 4.6",
        "64 cubes expanding, step 2 of 8; walls finer"
    ),
    entry!(
        "64-cubes-3-fine",
        "Fig. 4.6",
        "64 cubes expanding, step 3 of 8; walls finer"
    ),
    entry!(
        "64-cubes-4-fine",
        "Fig. 4.6",
        "64 cubes expanding, step 4 of 8 (middle); walls finer"
    ),
    entry!(
        "64-cubes-5-fine",
        "Fig. 4.6",
        "64 cubes expanding, step 5 of 8; walls finer"
    ),
    entry!(
        "64-cubes-6-fine",
        "Fig. 4.6",
        "64 cubes expanding, step 6 of 8; walls finer"
    ),
    entry!(
        "64-cubes-7-fine",
        "Fig. 4.6",
        "64 cubes expanding, step 7 of 8; walls finer"
    ),
    entry!(
        "64-cubes-8-fine",
        "Fig. 4.6f, Table 4.8",
        "64 cubes almost touching the walls; walls finer"
    ),
    entry!(
        "table-chairs-a",
        "Fig. 4.2a, Table 4.2",
        "10 × 10 × 3 room, one table with four chairs in the middle"
    ),
    entry!(
        "table-chairs-b",
        "Fig. 4.2b, Table 4.2",
        "10 × 10 × 3 room, 2 × 2 tables with chairs in the middle"
    ),
    entry!(
        "table-chairs-c",
        "Fig. 4.2c, Table 4.2",
        "10 × 10 × 3 room, 4 × 4 tables with chairs in the middle"
    ),
    entry!(
        "table-chairs-d",
        "Fig. 4.2d, Table 4.2",
        "10 × 10 × 3 room, 16 tables with chairs in a ring against the walls"
    ),
    entry!(
        "table-chairs-e",
        "Fig. 4.2e, Table 4.2",
        "10 × 10 × 3 room, 16 tables with chairs packed into a corner"
    ),
    entry!(
        "table-chairs-f",
        "Fig. 4.2f, Table 4.2",
        "10 × 10 × 3 room, 16 tables with chairs spread evenly from wall to wall"
    ),
    entry!(
        "sphere-1",
        "Table 4.1 (sphere)",
        "icosphere of level 1 in the unit sphere, 80 patches"
    ),
    entry!(
        "sphere-2",
        "Table 4.1 (sphere)",
        "icosphere of level 2 in the unit sphere, 320 patches"
    ),
    entry!(
        "sphere-3",
        "Table 4.1 (sphere)",
        "icosphere of level 3 in the unit sphere, 1280 patches"
    ),
    entry!(
        "sphere-4",
        "Table 4.1 (sphere)",
        "icosphere of level 4 in the unit sphere, 5120 patches"
    ),
    entry!(
        "tetra-mesh-0",
        "Fig. 4.3a, Tables 4.5, 5.3",
        "coloured tetrahedron with a light, 4 patches"
    ),
    entry!(
        "tetra-mesh-1",
        "Fig. 4.3, Tables 4.5, 5.3",
        "coloured tetrahedron, each face cut into 4 triangles (16 patches)"
    ),
    entry!(
        "tetra-mesh-2",
        "Fig. 4.3, Tables 4.5, 5.3",
        "coloured tetrahedron, each face cut into 16 triangles (64 patches)"
    ),
    entry!(
        "tetra-mesh-3",
        "Fig. 4.3, Tables 4.5, 5.3",
        "coloured tetrahedron, each face cut into 64 triangles (256 patches)"
    ),
];

/// [`Preset3Entry::all`].
pub(crate) fn presets_3d() -> &'static [Preset3Entry] {
    PRESETS_3D
}

/// [`Scene3::preset`].
pub(crate) fn preset_3d(name: &str, grid: u32) -> Result<Scene3> {
    let unknown = || -> crate::Error { ErrorKind::UnknownPreset(token(name)).into() };
    match name {
        "cube" => return Scene3::cube(grid),
        "tetrahedron" => return Scene3::tetrahedron(),
        "octahedron" => return Scene3::octahedron(),
        "dodecahedron" => return Scene3::dodecahedron(),
        "icosahedron" => return Scene3::icosahedron(),
        "cornell" => return Scene3::cornell_box(false, grid),
        "cornell-lifted" => return Scene3::cornell_box(true, grid),
        "cornell-thesis" => return Scene3::cornell_box_thesis(grid),
        "city-block" => return Scene3::city_block(city::MAX_CITY_BLOCKS, PRESET_SEED),
        _ => {}
    }
    if !PRESETS_3D.iter().any(|e| e.name == name) {
        return Err(unknown());
    }
    // The listed families: the name's suffix is a valid parameter by construction.
    if let Some(rest) = name.strip_prefix("cubes-") {
        let (m, how) = rest.split_once('-').ok_or_else(unknown)?;
        let m = match m {
            "27" => 3,
            "64" => 4,
            _ => 8,
        };
        return Scene3::cube_room_with_cubes(m, how == "clustered", PRESET_SEED);
    }
    if let Some(rest) = name.strip_prefix("64-cubes-") {
        let (step, fine) = match rest.strip_suffix("-fine") {
            Some(step) => (step, true),
            None => (rest, false),
        };
        let step: usize = step.parse().map_err(|_| unknown())?;
        return Scene3::sixty_four_cubes(step, fine);
    }
    if let Some(letter) = name.strip_prefix("table-chairs-") {
        let letter = letter.chars().next().ok_or_else(unknown)?;
        return Scene3::table_and_chairs_room(letter);
    }
    if let Some(level) = name.strip_prefix("sphere-") {
        return Scene3::sphere(level.parse().map_err(|_| unknown())?);
    }
    if let Some(level) = name.strip_prefix("tetra-mesh-") {
        return Scene3::tetrahedron_mesh(level.parse().map_err(|_| unknown())?);
    }
    Err(unknown())
}

// ---- shared builders ------------------------------------------------------------------------

/// Adds the planar convex polygon through `vertices`, its vertex order reversed if needed so
/// that its normal points along `facing` (the side its front must see).
fn add_facing(
    b: &mut Scene3Builder,
    vertices: &[DVec3],
    facing: DVec3,
    s: Subdivision,
) -> Result<()> {
    if geom::polygon_normal(vertices).dot(facing) >= 0.0 {
        b.polygon(vertices, s)?;
    } else {
        let mut reversed: Vec<DVec3> = vertices.to_vec();
        reversed.reverse();
        b.polygon(&reversed, s)?;
    }
    Ok(())
}

/// Mean of the vertices: a point inside a convex polygon or polyhedron.
fn vertex_mean(vertices: &[DVec3]) -> DVec3 {
    vertices.iter().copied().sum::<DVec3>() / vertices.len().max(1) as f64
}

/// The six faces of the box `[lo, hi]`, each as four corners (unoriented).
fn box_faces(lo: DVec3, hi: DVec3) -> [[DVec3; 4]; 6] {
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let (a, b) = (lo, hi);
    [
        [
            p(a.x, a.y, a.z),
            p(b.x, a.y, a.z),
            p(b.x, b.y, a.z),
            p(a.x, b.y, a.z),
        ],
        [
            p(a.x, a.y, b.z),
            p(b.x, a.y, b.z),
            p(b.x, b.y, b.z),
            p(a.x, b.y, b.z),
        ],
        [
            p(a.x, a.y, a.z),
            p(b.x, a.y, a.z),
            p(b.x, a.y, b.z),
            p(a.x, a.y, b.z),
        ],
        [
            p(a.x, b.y, a.z),
            p(b.x, b.y, a.z),
            p(b.x, b.y, b.z),
            p(a.x, b.y, b.z),
        ],
        [
            p(a.x, a.y, a.z),
            p(a.x, b.y, a.z),
            p(a.x, b.y, b.z),
            p(a.x, a.y, b.z),
        ],
        [
            p(b.x, a.y, a.z),
            p(b.x, b.y, a.z),
            p(b.x, b.y, b.z),
            p(b.x, a.y, b.z),
        ],
    ]
}

/// Adds the closed box `[lo, hi]` facing outwards (an object), every face cut by `s`.
fn add_box_outwards(b: &mut Scene3Builder, lo: DVec3, hi: DVec3, s: Subdivision) -> Result<()> {
    let centre = 0.5 * (lo + hi);
    for f in box_faces(lo, hi) {
        add_facing(b, &f, vertex_mean(&f) - centre, s)?;
    }
    Ok(())
}

/// Adds the box `[lo, hi]` facing inwards (a room), every face cut by `s`.
fn add_box_inwards(b: &mut Scene3Builder, lo: DVec3, hi: DVec3, s: Subdivision) -> Result<()> {
    let centre = 0.5 * (lo + hi);
    for f in box_faces(lo, hi) {
        add_facing(b, &f, centre - vertex_mean(&f), s)?;
    }
    Ok(())
}

/// `Err(TooManyPatches)` if `count` patches exceed [`MAX_PATCHES_3D`]: checked by the
/// constructors before building, so a huge request fails before allocating anything.
fn check_patch_total(count: u64) -> Result<()> {
    if count > MAX_PATCHES_3D as u64 {
        Err(ErrorKind::TooManyPatches {
            max: MAX_PATCHES_3D as u64,
        }
        .into())
    } else {
        Ok(())
    }
}

/// `Err(TooLarge)` unless `step < count`.
fn check_step(what: &'static str, step: u64, count: u64) -> Result<()> {
    if step < count {
        Ok(())
    } else {
        Err(ErrorKind::TooLarge {
            what,
            max: count - 1,
        }
        .into())
    }
}

#[cfg(all(test, feature = "std"))]
mod tests;

impl Preset3Entry {
    /// Number of steps of [`Scene3::sixty_four_cubes`] (0 = Figs. 4.5a/4.6a, 8 = Figs. 4.5f/4.6f).
    pub const SIXTY_FOUR_CUBES_STEPS: usize = SIXTY_FOUR_CUBES_STEPS;

    /// Every 3D preset, by name, in thesis order.
    ///
    /// Only `cube`, `cornell`, `cornell-lifted` and `cornell-thesis` (where it is the mesh level
    /// of [`Scene3::cornell_box_thesis`]) take the `grid` of `preset_3d`; the others
    /// have the fixed discretisation their constructor documents. The random cube rooms use the
    /// seed `PRESET_SEED`.
    #[must_use]
    pub fn all() -> &'static [Preset3Entry] {
        presets_3d()
    }
}

impl Scene3 {
    /// The 3D preset called `name` (one of `presets_3d`), with `grid` cells a side on the
    /// faces of the enclosures that take it (`cube`, `cornell`, `cornell-lifted`; ignored by the
    /// others).
    ///
    /// # Errors
    /// [`ErrorKind::UnknownPreset`] for a name not in `presets_3d`, and the errors of the
    /// constructor (e.g. [`ErrorKind::BadSubdivision`] for `grid = 0`).
    pub fn preset(name: &str, grid: u32) -> Result<Scene3> {
        preset_3d(name, grid)
    }
}
