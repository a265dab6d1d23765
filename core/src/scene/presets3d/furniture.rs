//! A room with tables and chairs (thesis Fig. 4.2, Table 4.2).

use alloc::format;
use alloc::string::String;
use alloc::vec::Vec;

use super::{
    ENCLOSURE, ENCLOSURE_MATERIAL, OBJECT_MATERIAL, add_box_outwards, add_facing, vertex_mean,
};
use crate::error::{ErrorKind, Result, token};
use crate::geom::{DVec2, DVec3};
use crate::scene::{Scene3, Scene3Builder, Subdivision};

/// The room of [`Scene3::table_and_chairs_room`]: `[0, 10] × [0, 10] × [0, 3]` (metres, z up).
pub(crate) const TABLE_ROOM: [f64; 3] = [10.0, 10.0, 3.0];

/// Gap left between furniture parts that would touch (legs and the floor, legs and the
/// table top or seat, a chair back and its seat): 5 mm.
pub(crate) const FURNITURE_GAP: f64 = 0.005;

/// Side of the room's square cells (each cell a face and a patch).
const ROOM_CELL: f64 = 0.5;

/// Half the side of a set's square footprint (table and four chairs).
const SET_HALF: f64 = 0.85;

/// Gap between a set and the walls in the arrangements against the walls (d, e, f).
const WALL_GAP: f64 = 0.1;

/// The parts of one set centred at the origin: a table (top and four legs) and four chairs
/// (seat, back and four legs each), as `(name, lo, hi)` boxes.
fn set_parts() -> Vec<(String, DVec3, DVec3)> {
    let g = FURNITURE_GAP;
    let b = |x0: f64, x1: f64, y0: f64, y1: f64, z0: f64, z1: f64| {
        (DVec3::new(x0, y0, z0), DVec3::new(x1, y1, z1))
    };
    let mut parts = Vec::new();
    // Table: top 0.8 × 0.8 × 0.04 at 0.72–0.76 m, legs 5 cm square inset 3 cm
    let (top_lo, top_hi) = b(-0.4, 0.4, -0.4, 0.4, 0.72, 0.76);
    parts.push((String::from("table/top"), top_lo, top_hi));
    for (k, (sx, sy)) in [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)]
        .into_iter()
        .enumerate()
    {
        let (x0, x1) = span(sx, 0.32, 0.37);
        let (y0, y1) = span(sy, 0.32, 0.37);
        let (lo, hi) = b(x0, x1, y0, y1, g, 0.72 - g);
        parts.push((format!("table/leg-{k}"), lo, hi));
    }
    // Chair on the +x side: seat 0.4 × 0.4 × 0.04 at 0.43–0.47 m, back 4 cm thick up to
    // 0.92 m over the far edge of the seat, legs 4 cm square inset 1 cm
    let mut chair = Vec::new();
    chair.push(("seat", b(0.45, 0.85, -0.2, 0.2, 0.43, 0.47)));
    chair.push(("back", b(0.81, 0.85, -0.2, 0.2, 0.47 + g, 0.92)));
    let legs = [
        ("leg-0", b(0.46, 0.50, -0.19, -0.15, g, 0.43 - g)),
        ("leg-1", b(0.80, 0.84, -0.19, -0.15, g, 0.43 - g)),
        ("leg-2", b(0.80, 0.84, 0.15, 0.19, g, 0.43 - g)),
        ("leg-3", b(0.46, 0.50, 0.15, 0.19, g, 0.43 - g)),
    ];
    chair.extend(legs);
    // Four chairs, turned by quarter turns about the z axis ((x, y) → (−y, x), exact)
    for c in 0..4 {
        for &(part, (lo, hi)) in &chair {
            let (mut p, mut q) = (lo, hi);
            for _ in 0..c {
                p = DVec3::new(-p.y, p.x, p.z);
                q = DVec3::new(-q.y, q.x, q.z);
            }
            parts.push((format!("chair-{c}/{part}"), p.min(q), p.max(q)));
        }
    }
    parts
}

/// `[a, b]` on the side of the sign `s`: `[a, b]` or `[−b, −a]`.
fn span(s: f64, a: f64, b: f64) -> (f64, f64) {
    if s > 0.0 { (a, b) } else { (-b, -a) }
}

/// Centres `(x, y)` of the sets of arrangement `letter` (Fig. 4.2a–f), or `None`.
fn arrangement(letter: char) -> Option<Vec<DVec2>> {
    let grid = |coords: &[f64]| -> Vec<DVec2> {
        coords
            .iter()
            .flat_map(|&y| coords.iter().map(move |&x| DVec2::new(x, y)))
            .collect()
    };
    let near = SET_HALF + WALL_GAP;
    let far = TABLE_ROOM[0] - near;
    Some(match letter {
        'a' => grid(&[5.0]),
        'b' => grid(&[4.0, 6.0]),
        'c' => grid(&[2.0, 4.0, 6.0, 8.0]),
        'd' => {
            // The 16 border positions of a 5 × 5 grid from wall to wall
            let at = |k: usize| near + (far - near) * (k as f64 / 4.0);
            (0..25)
                .filter(|n| [n % 5, n / 5].iter().any(|&k| k == 0 || k == 4))
                .map(|n| DVec2::new(at(n % 5), at(n / 5)))
                .collect()
        }
        'e' => {
            // Packed into the corner at the origin, sets `WALL_GAP` apart
            let pitch = 2.0 * SET_HALF + WALL_GAP;
            let coords: Vec<f64> = (0..4).map(|k| near + pitch * k as f64).collect();
            grid(&coords)
        }
        'f' => {
            // Spread evenly over the floor, the outer sets against the walls
            let coords: Vec<f64> = (0..4)
                .map(|k| near + (far - near) * (k as f64 / 3.0))
                .collect();
            grid(&coords)
        }
        _ => return None,
    })
}

impl Scene3 {
    /// Fig. 4.2 (Table 4.2): a room with sets of one table and four chairs, arranged as
    /// panel `arrangement` of the figure (`'a'` to `'f'`).
    ///
    /// Geometry (metres, z up): room `TABLE_ROOM` `= [0,10] × [0,10] × [0,3]`, facing
    /// inwards, every wall cut into 0.5 m square cells (each its own face and patch: 400 on
    /// the floor, 400 on the ceiling, 120 on each wall, 1280 in all). A set, centred at
    /// `(x, y)`:
    ///
    /// ```text
    /// table top     [−0.4, 0.4]² × [0.72, 0.76]
    /// table legs    ±[0.32, 0.37]² × [g, 0.72 − g]
    /// chair (+x)    seat [0.45, 0.85] × [−0.2, 0.2] × [0.43, 0.47]
    ///               back [0.81, 0.85] × [−0.2, 0.2] × [0.47 + g, 0.92]
    ///               legs [0.46, 0.50] or [0.80, 0.84] × ±[0.15, 0.19] × [g, 0.43 − g]
    /// chairs        the +x chair turned by 0, 90, 180, 270° about the set's vertical axis
    /// ```
    ///
    /// with `g` = `FURNITURE_GAP` = 5 mm: parts that would touch are kept apart so that
    /// each is a closed box of its own facing outwards (29 boxes, 174 patches, a footprint
    /// of 1.7 × 1.7 m per set). Arrangements of the set centres:
    ///
    /// - `a`: one set at the centre (5, 5);
    /// - `b`: 2 × 2 sets at 4 and 6 on each axis (0.3 m apart);
    /// - `c`: 4 × 4 sets at 2, 4, 6, 8 (1.15 m from the walls);
    /// - `d`: 16 sets in a ring along the walls, the border of a 5 × 5 grid from 0.95 to
    ///   9.05 (0.1 m from the walls);
    /// - `e`: 4 × 4 sets packed into a corner, 0.1 m apart and from the walls;
    /// - `f`: 4 × 4 sets spread evenly from wall to wall, at 0.95, 3.65, 6.35, 9.05 (0.1 m
    ///   from the walls, 1 m apart).
    ///
    /// The thesis does not give its dimensions; these keep its topology (the same 16 sets in
    /// c–f: in the middle, against the walls, in a corner, spread) and its trends, not its
    /// values, which are about 1.1–1.4 bits higher (its sets are larger for their room, or
    /// closer packed). Global lines (10⁵) give:
    ///
    /// ```text
    /// scene   a      b      c      d      e      f
    /// I_S^c   2.40   2.76   3.95   4.12   4.07   4.06
    /// thesis  3.837  4.102  5.023  5.043  5.044  5.089
    /// ```
    ///
    /// Complexity grows with the number of sets, and c–f are alike, those with sets near the
    /// walls a little above c. Patches: 1454 (a),
    /// 1976 (b), 4064 (c–f). Objects: `ENCLOSURE` (`super::ENCLOSURE_MATERIAL`) and one
    /// per box, named `set-<n>/table/top`, `set-<n>/chair-<c>/leg-<k>`, …
    /// (`super::OBJECT_MATERIAL`).
    ///
    /// # Errors
    /// [`ErrorKind::UnknownPreset`] for a letter other than `'a'`–`'f'`.
    pub fn table_and_chairs_room(arrangement: char) -> Result<Scene3> {
        let centres = arrangement_or_error(arrangement)?;
        let [sx, sy, sz] = TABLE_ROOM;
        let mut b = Scene3::builder();
        b.object(ENCLOSURE).material(ENCLOSURE_MATERIAL);
        add_room_cells(&mut b, DVec3::new(sx, sy, sz), ROOM_CELL)?;
        b.material(OBJECT_MATERIAL);
        let parts = set_parts();
        for (n, c) in centres.iter().enumerate() {
            let offset = DVec3::new(c.x, c.y, 0.0);
            for (name, lo, hi) in &parts {
                b.object(&format!("set-{n}/{name}"));
                add_box_outwards(&mut b, *lo + offset, *hi + offset, Subdivision::None)?;
            }
        }
        b.build()
    }
}

/// The set centres of `letter`, or `Err(UnknownPreset)` naming the would-be preset.
fn arrangement_or_error(letter: char) -> Result<Vec<DVec2>> {
    arrangement(letter).ok_or_else(|| {
        let mut name = String::from("table-chairs-");
        name.push(letter);
        ErrorKind::UnknownPreset(token(&name)).into()
    })
}

/// Adds the box room `[0, size]`, facing inwards, each face cut into square-ish cells of
/// side about `cell`, each its own face.
fn add_room_cells(b: &mut Scene3Builder, size: DVec3, cell: f64) -> Result<()> {
    let centre = 0.5 * size;
    let x = DVec3::X * size.x;
    let y = DVec3::Y * size.y;
    let z = DVec3::Z * size.z;
    // (corner, u, v) of each face
    let faces = [
        (DVec3::ZERO, x, y),
        (z, x, y),
        (DVec3::ZERO, x, z),
        (y, x, z),
        (DVec3::ZERO, y, z),
        (x, y, z),
    ];
    for (corner, u, v) in faces {
        let count = |w: DVec3| ((w.length() / cell + 0.5) as u32).max(1);
        let (nu, nv) = (count(u), count(v));
        let at = |i: u32, j: u32| {
            corner + u * (f64::from(i) / f64::from(nu)) + v * (f64::from(j) / f64::from(nv))
        };
        for j in 0..nv {
            for i in 0..nu {
                let q = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                add_facing(b, &q, centre - vertex_mean(&q), Subdivision::None)?;
            }
        }
    }
    Ok(())
}
