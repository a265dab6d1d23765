//! A small ASCII PLY writer: polygons with per-face colours, and optionally per-vertex
//! colours on shared vertices, for `sceneinfo draw` and `sceneinfo radiosity`.
//!
//! [`Ply::polygon`] gives a polygon its own vertices (shared corners are written once per
//! polygon), so a viewer that interpolates colours across vertices still shows each face in
//! one colour. [`Ply::vertex`] and [`Ply::face`] build an indexed mesh whose vertices carry
//! colours too (Gouraud shading in viewers that use vertex colours, e.g. MeshLab and
//! Blender); the two styles cannot be mixed in one file.
//! The header is plain ASCII: comments are cut to one line of printable ASCII.

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
    //! A tiny reader of the PLY files [`super::Ply`] writes, for tests.

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

    /// Parses an ASCII PLY of one `vertex` element (x, y, z floats, optionally red, green,
    /// blue) and one `face` element
    /// (a vertex index list, then red, green, blue), checking the header against the body.
    pub fn parse(text: &str) -> Result<Parsed, String> {
        let mut lines = text.lines();
        if lines.next() != Some("ply") || lines.next() != Some("format ascii 1.0") {
            return Err("not an ASCII PLY 1.0 file".into());
        }
        let mut comments = Vec::new();
        let mut elements: Vec<(String, usize, Vec<String>)> = Vec::new();
        loop {
            let line = lines.next().ok_or("no end_header")?;
            if !line.is_ascii() {
                return Err(format!("non-ASCII header line {line:?}"));
            }
            let words: Vec<&str> = line.split(' ').collect();
            match words.as_slice() {
                ["end_header"] => break,
                ["comment", ..] => comments.push(line["comment ".len()..].to_owned()),
                ["element", name, n] => elements.push((
                    (*name).to_owned(),
                    n.parse().map_err(|e| format!("{line}: {e}"))?,
                    Vec::new(),
                )),
                ["property", ..] => elements
                    .last_mut()
                    .ok_or("property before element")?
                    .2
                    .push(words[1..].join(" ")),
                _ => return Err(format!("unexpected header line {line:?}")),
            }
        }
        let [(v, nv, vprops), (f, nf, fprops)] = elements.as_slice() else {
            return Err(format!("expected two elements, found {}", elements.len()));
        };
        let xyz = ["float x", "float y", "float z"];
        let rgb = ["uchar red", "uchar green", "uchar blue"];
        let coloured = vprops.len() == 6 && vprops[3..] == rgb;
        if v != "vertex"
            || vprops.len() < 3
            || vprops[..3] != xyz
            || !(vprops.len() == 3 || coloured)
        {
            return Err(format!("bad vertex element {vprops:?}"));
        }
        let list_ok = matches!(
            fprops.first().map(String::as_str),
            Some("list uchar int vertex_indices" | "list ushort int vertex_indices")
        );
        if f != "face" || !list_ok || fprops[1..] != ["uchar red", "uchar green", "uchar blue"] {
            return Err(format!("bad face element {fprops:?}"));
        }
        let mut vertices = Vec::with_capacity(*nv);
        let mut vertex_colours = Vec::new();
        for _ in 0..*nv {
            let line = lines.next().ok_or("too few vertex lines")?;
            let words: Vec<&str> = line.split(' ').collect();
            if words.len() != if coloured { 6 } else { 3 } {
                return Err(format!("vertex line {line:?}"));
            }
            let xyz: Vec<f32> = words[..3]
                .iter()
                .map(|w| w.parse())
                .collect::<Result<_, _>>()
                .map_err(|e| format!("{line}: {e}"))?;
            vertices.push([xyz[0], xyz[1], xyz[2]]);
            if coloured {
                let c: Vec<u8> = words[3..]
                    .iter()
                    .map(|w| w.parse())
                    .collect::<Result<_, _>>()
                    .map_err(|e| format!("{line}: {e}"))?;
                vertex_colours.push([c[0], c[1], c[2]]);
            }
        }
        let mut faces = Vec::with_capacity(*nf);
        for _ in 0..*nf {
            let line = lines.next().ok_or("too few face lines")?;
            let nums: Vec<usize> = line
                .split(' ')
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|e| format!("{line}: {e}"))?;
            let count = *nums.first().ok_or("empty face line")?;
            if nums.len() != 1 + count + 3 {
                return Err(format!(
                    "face line {line:?} does not hold {count} indices + rgb"
                ));
            }
            let idx = nums[1..=count].to_vec();
            if let Some(&k) = idx.iter().find(|&&k| k >= *nv) {
                return Err(format!("face index {k} ≥ vertex count {nv}"));
            }
            let rgb = nums[count + 1..]
                .iter()
                .map(|&c| u8::try_from(c).map_err(|e| format!("{line}: {e}")))
                .collect::<Result<Vec<u8>, _>>()?;
            faces.push((idx, [rgb[0], rgb[1], rgb[2]]));
        }
        if let Some(extra) = lines.next() {
            return Err(format!("trailing line {extra:?}"));
        }
        Ok(Parsed {
            comments,
            vertices,
            vertex_colours,
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
