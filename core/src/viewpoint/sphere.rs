//! The sphere of viewpoints: the vertices of an icosphere (an icosahedron whose triangles
//! are split in four `level` times, midpoints pushed out to the unit sphere), with the
//! icosphere's edges as the neighbour relation.
//!
//! `10 · 4^level + 2` viewpoints: 12, 42, 162, **642** (level 3, the count of Feixas, Sbert
//! and González 2009), 2562, 10242.

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use crate::geom::DVec3;
use crate::math;
use crate::{ErrorKind, Result};

/// Largest icosphere level of [`ViewSphere::new`] (10 242 viewpoints).
pub(crate) const MAX_VIEW_LEVEL: u32 = 5;

/// Unit viewing directions and their neighbours on the icosphere.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewSphere {
    directions: Vec<DVec3>,
    neighbours: Vec<Vec<u32>>,
    triangles: Vec<[u32; 3]>,
}

impl ViewSphere {
    /// The icosphere of `level` (0 = the icosahedron's 12 vertices).
    ///
    /// The icosahedron's vertices are `(0, ±1, ±φ)` and their cyclic permutations,
    /// normalised; vertex order: those 12, then each level's midpoints in the order their
    /// edges are first met. Deterministic on every target.
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] for `level >` `MAX_VIEW_LEVEL`.
    pub fn new(level: u32) -> Result<Self> {
        if level > MAX_VIEW_LEVEL {
            return Err(ErrorKind::TooLarge {
                what: "viewpoint sphere level",
                max: u64::from(MAX_VIEW_LEVEL),
            }
            .into());
        }
        let phi = 0.5 * (1.0 + math::sqrt(5.0));
        let mut points = Vec::new();
        for (a, b) in [(1.0, phi), (1.0, -phi), (-1.0, phi), (-1.0, -phi)] {
            points.push(DVec3::new(0.0, a, b));
        }
        for (a, b) in [(1.0, phi), (1.0, -phi), (-1.0, phi), (-1.0, -phi)] {
            points.push(DVec3::new(a, b, 0.0));
        }
        for (a, b) in [(1.0, phi), (1.0, -phi), (-1.0, phi), (-1.0, -phi)] {
            points.push(DVec3::new(b, 0.0, a));
        }
        let mut directions: Vec<DVec3> = points.iter().map(|p| *p / p.length()).collect();
        // The icosahedron's faces: triples of vertices at the edge distance 2 from each other
        let mut triangles: Vec<[u32; 3]> = Vec::new();
        for i in 0..12u32 {
            for j in i + 1..12 {
                for k in j + 1..12 {
                    let close = |a: u32, b: u32| {
                        (points[a as usize] - points[b as usize]).length_squared() < 4.5
                    };
                    if close(i, j) && close(j, k) && close(i, k) {
                        triangles.push([i, j, k]);
                    }
                }
            }
        }
        for _ in 0..level {
            let mut midpoints: BTreeMap<(u32, u32), u32> = BTreeMap::new();
            let mut next = Vec::with_capacity(triangles.len() * 4);
            for &[a, b, c] in &triangles {
                let mut mid = |u: u32, v: u32| -> u32 {
                    let key = (u.min(v), u.max(v));
                    *midpoints.entry(key).or_insert_with(|| {
                        let m = directions[key.0 as usize] + directions[key.1 as usize];
                        directions.push(m / m.length());
                        (directions.len() - 1) as u32
                    })
                };
                let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
                next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
            }
            triangles = next;
        }
        // Counter-clockwise seen from outside
        for t in &mut triangles {
            let [a, b, c] = t.map(|k| directions[k as usize]);
            if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
                t.swap(1, 2);
            }
        }
        let mut neighbours: Vec<Vec<u32>> = alloc::vec![Vec::new(); directions.len()];
        for &[a, b, c] in &triangles {
            for (u, v) in [(a, b), (b, c), (c, a)] {
                for (x, y) in [(u, v), (v, u)] {
                    let list = &mut neighbours[x as usize];
                    if !list.contains(&y) {
                        list.push(y);
                    }
                }
            }
        }
        for list in &mut neighbours {
            list.sort_unstable();
        }
        Ok(Self {
            directions,
            neighbours,
            triangles,
        })
    }

    /// The sphere with `count` viewpoints: `count = 10 · 4^level + 2`.
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for a count that is not one of 12, 42, 162, 642, 2562,
    /// 10242.
    pub fn with_count(count: usize) -> Result<Self> {
        let level = (0..=MAX_VIEW_LEVEL).find(|&l| 10 * (1usize << (2 * l)) + 2 == count);
        match level {
            Some(l) => Self::new(l),
            None => Err(ErrorKind::BadParameter {
                name: "views (12, 42, 162, 642, 2562 or 10242)",
                value: count as f64,
            }
            .into()),
        }
    }

    /// Unit directions from the scene's centre to the viewpoints.
    #[must_use]
    pub fn directions(&self) -> &[DVec3] {
        &self.directions
    }

    /// The icosphere neighbours of each viewpoint (5 or 6 each), ascending.
    #[must_use]
    pub fn neighbours(&self) -> &[Vec<u32>] {
        &self.neighbours
    }

    /// The icosphere's triangles (indices into [`ViewSphere::directions`]), for drawing a
    /// quantity over the sphere, counter-clockwise seen from outside.
    #[must_use]
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of viewpoints.
    #[must_use]
    pub fn len(&self) -> usize {
        self.directions.len()
    }

    /// Never true (a sphere has at least 12 viewpoints); for clippy's `len` convention.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.directions.is_empty()
    }
}
