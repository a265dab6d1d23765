//! A small ASCII PLY writer: polygons with per-face colours, and optionally per-vertex
//! colours on shared vertices, for `sceneinfo draw` and `sceneinfo radiosity`.
//!
//! [`Ply::polygon`] gives a polygon its own vertices (shared corners are written once per
//! polygon), so a viewer that interpolates colours across vertices still shows each face in
//! one colour. [`Ply::vertex`] and [`Ply::face`] build an indexed mesh whose vertices carry
//! colours too (Gouraud shading in viewers that use vertex colours, e.g. MeshLab and
//! Blender); the two styles cannot be mixed in one file.
//! The header is plain ASCII: comments are cut to one line of printable ASCII.
//!
//! Why a hand writer and not `ply-rs-bw`'s (whose reader is the one reader,
//! [`crate::formats::ply_scene`]): the crate's ASCII writer prints each value with `{}` as
//! this one does, so it would write the same bytes, but only from a whole `Ply<E>` payload
//! (`KeyMap<Vec<E>>`, one row type `E` for vertices and faces alike, read back through
//! `PropertyAccess` getters per property): a second copy of every mesh in memory and an
//! adapter longer than this writer. What the crate gives, a check that the files are
//! well-formed PLY, the tests below get by reading every file written with the crate's
//! reader. The format is the one MeshLab and Blender read (vertex colours as `uchar red
//! green blue`, faces as a `vertex_indices` list).

use std::fmt::Write as _;

use anyhow::{Result, bail};
use sceneinfo::geom::DVec3;
use sceneinfo::scene::Frame;

use crate::svg::Rgb;

/// A polygon mesh being assembled.
#[derive(Debug, Default)]
pub struct Ply {
    comments: Vec<String>,
    vertices: Vec<[f32; 3]>,
    /// Vertex colours, one per vertex when the mesh is indexed ([`Ply::vertex`]).
    vertex_colours: Vec<Rgb>,
    /// The faces' vertex indices, back to back.
    indices: Vec<usize>,
    /// `(first index, vertex count, colour)` of each face.
    faces: Vec<(usize, usize, Rgb)>,
    /// Per face, the RGB radiosity written as three float properties
    /// (`radiosity_red`, `radiosity_green`, `radiosity_blue`) when every face has one.
    radiosity: Vec<[f32; 3]>,
    /// The scene's frame, undone for every vertex added (the identity when the scene's
    /// units do not fit in `f32`: see [`Ply::in_frame`]).
    frame: Frame,
}

impl Ply {
    /// An empty mesh in the identity frame.
    #[cfg(test)]
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty mesh whose vertices are given in `frame`'s stored coordinates and written in
    /// the scene's own units — unless those do not fit in `f32` (a scene 10⁻²⁰⁰ or 10⁵⁰
    /// wide, or 10⁴⁰ from the origin): then the stored coordinates are written, and a header
    /// comment says how to get back (`world = origin + 2^exponent · xyz`).
    pub fn in_frame(frame: Frame) -> Self {
        let mut ply = Self::default();
        let e = frame.exponent();
        let fits = e.abs() <= 90 && frame.origin().abs().max_element() <= 1e30;
        if fits {
            ply.frame = frame;
        } else {
            let o = frame.origin();
            ply.comment(&format!(
                "coordinates in the scene's normalised frame (f32 cannot hold its units): \
                 world = ({:e}, {:e}, {:e}) + 2^{e} * (x, y, z)",
                o.x, o.y, o.z
            ));
        }
        ply
    }

    /// A vertex in the written coordinates.
    fn point(&self, v: DVec3) -> [f32; 3] {
        let w = self.frame.to_world(v);
        [w.x as f32, w.y as f32, w.z as f32]
    }

    /// Adds a `comment` line to the header; anything but printable ASCII becomes `?`.
    pub fn comment(&mut self, text: &str) {
        let line: String = text
            .chars()
            .map(|c| {
                if c == ' ' || c.is_ascii_graphic() {
                    c
                } else {
                    '?'
                }
            })
            .collect();
        self.comments.push(line);
    }

    /// Adds a polygon with its own copies of `vertices` (in order) and one colour.
    pub fn polygon(&mut self, vertices: &[DVec3], colour: Rgb) {
        let first = self.vertices.len();
        for &v in vertices {
            let p = self.point(v);
            self.vertices.push(p);
        }
        self.faces
            .push((self.indices.len(), vertices.len(), colour));
        self.indices.extend(first..first + vertices.len());
    }

    /// Adds a shared vertex with its colour and returns its index (for [`Ply::face`]).
    pub fn vertex(&mut self, v: DVec3, colour: Rgb) -> usize {
        let p = self.point(v);
        self.vertices.push(p);
        self.vertex_colours.push(colour);
        self.vertices.len() - 1
    }

    /// Adds a face over vertices added with [`Ply::vertex`], with its own colour.
    pub fn face(&mut self, indices: &[usize], colour: Rgb) {
        self.faces.push((self.indices.len(), indices.len(), colour));
        self.indices.extend_from_slice(indices);
    }

    /// Adds a polygon as [`Ply::polygon`] does, with its radiosity as float properties
    /// (written only if every face has one).
    pub fn polygon_with_radiosity(&mut self, vertices: &[DVec3], colour: Rgb, b: [f64; 3]) {
        self.polygon(vertices, colour);
        self.radiosity.push(b.map(|x| x as f32));
    }

    /// The file's text.
    ///
    /// The face's vertex count is a `uchar` unless some face has more than 255 vertices
    /// (then `ushort`).
    ///
    /// # Errors
    /// A face of fewer than 3 or more than 65 535 vertices; more vertices than an `int` index.
    pub fn finish(&self) -> Result<String> {
        let max_count = self.faces.iter().map(|f| f.1).max().unwrap_or(3);
        if let Some(f) = self.faces.iter().position(|f| f.1 < 3) {
            bail!("PLY face {f} has fewer than 3 vertices");
        }
        let count_type = match max_count {
            0..=255 => "uchar",
            256..=65535 => "ushort",
            _ => bail!("a PLY face has more than 65535 vertices"),
        };
        if i32::try_from(self.vertices.len()).is_err() {
            bail!("too many vertices for a PLY file ({})", self.vertices.len());
        }
        let coloured = !self.vertex_colours.is_empty();
        if coloured && self.vertex_colours.len() != self.vertices.len() {
            bail!("a PLY mesh mixes coloured shared vertices with per-polygon vertices");
        }
        if let Some(&k) = self.indices.iter().find(|&&k| k >= self.vertices.len()) {
            bail!("PLY face index {k} is not a vertex");
        }
        let mut s = String::with_capacity(64 * self.vertices.len() + 512);
        s.push_str("ply\nformat ascii 1.0\n");
        for c in &self.comments {
            let _ = writeln!(s, "comment {c}");
        }
        let _ = writeln!(s, "element vertex {}", self.vertices.len());
        s.push_str("property float x\nproperty float y\nproperty float z\n");
        if coloured {
            s.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
        }
        let _ = writeln!(s, "element face {}", self.faces.len());
        let _ = writeln!(s, "property list {count_type} int vertex_indices");
        s.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
        let with_radiosity = self.radiosity.len() == self.faces.len() && !self.faces.is_empty();
        if with_radiosity {
            s.push_str(
                "property float radiosity_red\nproperty float radiosity_green\n\
                 property float radiosity_blue\n",
            );
        }
        s.push_str("end_header\n");
        for (k, [x, y, z]) in self.vertices.iter().enumerate() {
            match self.vertex_colours.get(k) {
                Some(Rgb(r, g, b)) => {
                    let _ = writeln!(s, "{x} {y} {z} {r} {g} {b}");
                }
                None => {
                    let _ = writeln!(s, "{x} {y} {z}");
                }
            }
        }
        for (k, &(first, count, Rgb(r, g, b))) in self.faces.iter().enumerate() {
            let _ = write!(s, "{count}");
            for v in &self.indices[first..first + count] {
                let _ = write!(s, " {v}");
            }
            let _ = write!(s, " {r} {g} {b}");
            if with_radiosity {
                let [br, bg, bb] = self.radiosity[k];
                let _ = write!(s, " {br} {bg} {bb}");
            }
            s.push('\n');
        }
        Ok(s)
    }
}

#[cfg(test)]
pub mod check {
    //! The files [`super::Ply`] writes, read back by the one PLY reader
    //! ([`crate::formats::ply_scene::read_mesh`], the `ply-rs-bw` crate), for tests.

    use std::path::Path;

    /// What a PLY file holds.
    #[derive(Debug)]
    pub struct Parsed {
        /// Header comments.
        pub comments: Vec<String>,
        /// Vertex positions.
        pub vertices: Vec<[f32; 3]>,
        /// Vertex colours, when the vertex element has them.
        pub vertex_colours: Vec<[u8; 3]>,
        /// Each face's vertex indices and colour.
        pub faces: Vec<(Vec<usize>, [u8; 3])>,
    }

    /// Reads `text` with the crate's reader and checks what our writer promises: an ASCII
    /// header, every face coloured, every index a vertex.
    pub fn parse(text: &str) -> Result<Parsed, String> {
        let header = &text[..text.find("end_header").ok_or("no end_header")?];
        if !header.starts_with("ply\nformat ascii 1.0\n") || !header.is_ascii() {
            return Err("not an ASCII PLY 1.0 file with an ASCII header".into());
        }
        let mesh = crate::formats::ply_scene::read_mesh(Path::new("t.ply"), text.as_bytes())
            .map_err(|e| format!("{e:#}"))?;
        let n = mesh.vertices.len();
        let faces = mesh
            .faces
            .iter()
            .map(|f| {
                let colour = f.colour.ok_or("a face without red green blue")?;
                let idx = f
                    .indices
                    .iter()
                    .map(|&k| usize::try_from(k).ok().filter(|&k| k < n))
                    .collect::<Option<Vec<usize>>>()
                    .ok_or("a face index that is not a vertex")?;
                Ok((idx, colour))
            })
            .collect::<Result<_, String>>()?;
        Ok(Parsed {
            comments: mesh.comments,
            vertices: mesh
                .vertices
                .iter()
                .map(|v| [v.x as f32, v.y as f32, v.z as f32])
                .collect(),
            vertex_colours: mesh.vertex_colours,
            faces,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::check::parse;
    use super::*;

    fn square(x: f64) -> Vec<DVec3> {
        vec![
            DVec3::new(x, 0.0, 0.0),
            DVec3::new(x + 1.0, 0.0, 0.0),
            DVec3::new(x + 1.0, 1.0, 0.0),
            DVec3::new(x, 1.0, 0.0),
        ]
    }

    #[test]
    fn header_counts_match_the_body() {
        let mut ply = Ply::new();
        ply.comment("quantity: I_i (6.8), bits\nsecond line");
        ply.comment("I_i^c − I_i, é");
        ply.polygon(&square(0.0), Rgb(1, 2, 3));
        ply.polygon(&square(0.5), Rgb(250, 128, 0));
        ply.polygon(&square(0.0)[..3], Rgb(0, 0, 0));
        let text = ply.finish().unwrap();
        assert!(text.contains("\nelement vertex 11\n"), "{text}");
        assert!(text.contains("\nelement face 3\n"));
        assert!(text.contains("\nproperty list uchar int vertex_indices\n"));
        let p = parse(&text).unwrap();
        assert_eq!(p.vertices.len(), 11);
        assert_eq!(p.faces.len(), 3);
        assert_eq!(
            p.comments,
            ["quantity: I_i (6.8), bits?second line", "I_i^c ? I_i, ?"]
        );
        // Each face has its own vertices, in order, and its colour.
        assert_eq!(p.faces[0], (vec![0, 1, 2, 3], [1, 2, 3]));
        assert_eq!(p.faces[1], (vec![4, 5, 6, 7], [250, 128, 0]));
        assert_eq!(p.faces[2], (vec![8, 9, 10], [0, 0, 0]));
        assert_eq!(p.vertices[5], [1.5, 0.0, 0.0]);
        assert!(text.ends_with("3 8 9 10 0 0 0\n"));
    }

    #[test]
    fn an_empty_mesh_is_still_a_valid_file() {
        let p = parse(&Ply::new().finish().unwrap()).unwrap();
        assert!(p.vertices.is_empty() && p.faces.is_empty());
    }

    #[test]
    fn faces_of_more_than_255_vertices_count_in_ushort() {
        let ring: Vec<DVec3> = (0..300)
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / 300.0;
                DVec3::new(t.cos(), t.sin(), 1.0 / 3.0)
            })
            .collect();
        let mut ply = Ply::new();
        ply.polygon(&ring, Rgb(9, 9, 9));
        let text = ply.finish().unwrap();
        assert!(text.contains("property list ushort int vertex_indices"));
        let p = parse(&text).unwrap();
        assert_eq!(p.faces[0].0.len(), 300);
        assert_eq!(p.vertices[0], [1.0, 0.0, 1.0 / 3.0]);
    }

    #[test]
    fn indexed_meshes_carry_vertex_colours() {
        let mut ply = Ply::new();
        let sq = square(0.0);
        let v: Vec<usize> = sq
            .iter()
            .enumerate()
            .map(|(k, &p)| ply.vertex(p, Rgb(k as u8, 10, 20)))
            .collect();
        ply.face(&v[..3], Rgb(1, 2, 3));
        ply.face(&[v[0], v[2], v[3]], Rgb(4, 5, 6));
        let text = ply.finish().unwrap();
        let p = parse(&text).unwrap();
        assert_eq!(p.vertices.len(), 4);
        assert_eq!(p.vertex_colours[3], [3, 10, 20]);
        assert_eq!(p.faces[1], (vec![0, 2, 3], [4, 5, 6]));
        // Mixing styles, or a face over a missing vertex, is refused.
        let mut mixed = Ply::new();
        mixed.vertex(sq[0], Rgb(0, 0, 0));
        mixed.polygon(&sq, Rgb(0, 0, 0));
        assert!(mixed.finish().is_err());
        let mut dangling = Ply::new();
        dangling.face(&[0, 1, 2], Rgb(0, 0, 0));
        assert!(dangling.finish().is_err());
    }

    #[test]
    fn degenerate_faces_are_refused() {
        let mut ply = Ply::new();
        ply.polygon(&square(0.0)[..2], Rgb(0, 0, 0));
        assert!(ply.finish().is_err());
    }
}
