//! The one PLY reader (ASCII, binary little- and big-endian), on the `ply-rs-bw` crate:
//! scenes ([`read`]), the reference solutions of `refine --reference` (faces with their
//! radiosities, [`read_mesh`]) and, in tests, the files our own writer
//! (the CLI's `ply::Ply`) makes.
//!
//! What is read: the header's comments, the `vertex` element's `x y z` (any numeric type)
//! and `red green blue`, the `face` element's `vertex_indices` (or `vertex_index`) lists
//! (any integer types), `red green blue` and `radiosity_red/green/blue`. A scene makes
//! each face one polygon through [`crate::mesh::add_face`]. Every other element and property is read
//! past and ignored. PLY carries no materials: every face is black (ρ = 0, E = 0); colours
//! (`red`/`green`/`blue`, as sceneinfo's own `radiosity --ply` writes them) are ignored
//! with a warning.
//!
//! Before any payload is read, each element's count is checked against the bytes left in
//! the file (every element takes at least one byte), so a header cannot make the reader
//! allocate or loop for elements that are not there.

use std::io::{BufReader, Cursor};
use std::path::Path;

use anyhow::{Result, bail};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{ElementDef, Property, PropertyAccess, PropertyAccessResult};
use sceneinfo::geom::DVec3;
use sceneinfo::io::{LoadReport, LoadWarningKind};
use sceneinfo::scene::{Scene3, Scene3Builder};

use crate::mesh::add_face;

/// Longest excerpt of the `ply-rs-bw` error message quoted (it may quote a whole line).
const MAX_MESSAGE_CHARS: usize = 240;

/// Colour property names (per vertex or per face).
const COLOUR_NAMES: &[&str] = &[
    "red",
    "green",
    "blue",
    "r",
    "g",
    "b",
    "diffuse_red",
    "diffuse_green",
    "diffuse_blue",
];

/// One element of any kind, keeping the properties sceneinfo reads.
#[derive(Debug, Default)]
struct Item {
    x: Option<f64>,
    y: Option<f64>,
    z: Option<f64>,
    /// Vertex indices as the file gives them (negative ones are refused later).
    indices: Option<Vec<i64>>,
    /// `red green blue` (numbers; kept when all three are bytes).
    rgb: [Option<f64>; 3],
    /// `radiosity_red radiosity_green radiosity_blue`.
    radiosity: [Option<f64>; 3],
}

impl PropertyAccess for Item {
    fn new() -> Self {
        Self::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        match name {
            "x" => self.x = number(&property),
            "y" => self.y = number(&property),
            "z" => self.z = number(&property),
            "red" => self.rgb[0] = number(&property),
            "green" => self.rgb[1] = number(&property),
            "blue" => self.rgb[2] = number(&property),
            "radiosity_red" => self.radiosity[0] = number(&property),
            "radiosity_green" => self.radiosity[1] = number(&property),
            "radiosity_blue" => self.radiosity[2] = number(&property),
            "vertex_indices" | "vertex_index" => {
                self.indices = match property {
                    Property::ListChar(v) => Some(v.into_iter().map(i64::from).collect()),
                    Property::ListUChar(v) => Some(v.into_iter().map(i64::from).collect()),
                    Property::ListShort(v) => Some(v.into_iter().map(i64::from).collect()),
                    Property::ListUShort(v) => Some(v.into_iter().map(i64::from).collect()),
                    Property::ListInt(v) => Some(v.into_iter().map(i64::from).collect()),
                    Property::ListUInt(v) => Some(v.into_iter().map(i64::from).collect()),
                    _ => return PropertyAccessResult::UnsupportedType,
                };
            }
            _ => return PropertyAccessResult::Ignored,
        }
        PropertyAccessResult::Set
    }
}

/// A scalar property's value as f64 (`None` for lists).
fn number(property: &Property) -> Option<f64> {
    Some(match *property {
        Property::Char(v) => f64::from(v),
        Property::UChar(v) => f64::from(v),
        Property::Short(v) => f64::from(v),
        Property::UShort(v) => f64::from(v),
        Property::Int(v) => f64::from(v),
        Property::UInt(v) => f64::from(v),
        Property::Float(v) => f64::from(v),
        Property::Double(v) => v,
        _ => return None,
    })
}

/// A PLY file's polygon mesh, as read by [`read_mesh`].
#[derive(Debug)]
pub struct PlyMesh {
    /// The header's `comment` lines, without the keyword.
    #[cfg_attr(not(test), allow(dead_code, reason = "read by the PLY writer's tests"))]
    pub comments: Vec<String>,
    /// Vertex positions (every vertex has `x y z`).
    pub vertices: Vec<DVec3>,
    /// Vertex colours, when every vertex has `red green blue` bytes (else empty).
    #[cfg_attr(not(test), allow(dead_code, reason = "read by the PLY writer's tests"))]
    pub vertex_colours: Vec<[u8; 3]>,
    /// The faces, in the file's order.
    pub faces: Vec<PlyFace>,
    /// Whether some element carries colours (a scene ignores them with a warning).
    pub coloured: bool,
}

/// One face of a [`PlyMesh`].
#[derive(Debug)]
pub struct PlyFace {
    /// Vertex indices as the file gives them (checked by [`PlyMesh::polygon`]).
    pub indices: Vec<i64>,
    /// `red green blue`, when the face has them as bytes.
    #[cfg_attr(not(test), allow(dead_code, reason = "read by the PLY writer's tests"))]
    pub colour: Option<[u8; 3]>,
    /// `radiosity_red/green/blue`, when the face has all three.
    pub radiosity: Option<[f64; 3]>,
}

impl PlyMesh {
    /// Face `k`'s corners into `polygon` (cleared first).
    ///
    /// # Errors
    /// `file: PLY face k: vertex index i out of range (n vertices)`.
    pub fn polygon(&self, path: &Path, k: usize, polygon: &mut Vec<DVec3>) -> Result<()> {
        polygon.clear();
        for &i in &self.faces[k].indices {
            let p = usize::try_from(i)
                .ok()
                .and_then(|i| self.vertices.get(i))
                .ok_or_else(|| {
                    anyhow::anyhow!(
                        "{}: PLY face {k}: vertex index {i} out of range ({} vertices)",
                        path.display(),
                        self.vertices.len()
                    )
                })?;
            polygon.push(*p);
        }
        Ok(())
    }
}

/// Reads the PLY file `path`, whose bytes are `bytes`, into a scene.
///
/// # Errors
/// `file: where: what` for a broken header, an element count the file cannot hold, a
/// payload cut short, a missing coordinate, a vertex index out of range, a face the scene
/// refuses, …
pub fn read(path: &Path, bytes: &[u8], report: &mut LoadReport) -> Result<Scene3> {
    let mesh = read_mesh(path, bytes)?;
    if mesh.coloured {
        report.warn(
            None,
            LoadWarningKind::IgnoredMaterialData {
                what: "PLY colours (PLY scenes have no materials: faces are black)",
            },
        );
    }
    // Faces through the one door
    let mut builder = Scene3Builder::default();
    let mut polygon = Vec::new();
    for k in 0..mesh.faces.len() {
        mesh.polygon(path, k, &mut polygon)?;
        add_face(
            &mut builder,
            &polygon,
            report,
            path,
            format_args!("PLY face {k}"),
        )?;
    }
    crate::mesh::build(builder, report, path)
}

/// Reads the PLY file `path`, whose bytes are `bytes`, as a polygon mesh.
///
/// # Errors
/// `file: where: what` for a broken header, an element count the file cannot hold, a
/// payload cut short, a vertex without a numeric `x y z`, a face without an integer
/// `vertex_indices` list.
pub fn read_mesh(path: &Path, bytes: &[u8]) -> Result<PlyMesh> {
    let file = path.display();
    let mut reader = ply_rs_bw::parser::Reader::new(BufReader::new(Cursor::new(bytes)));
    let parser = Parser::<Item>::new();
    let header = parser
        .read_header(&mut reader)
        .map_err(|e| anyhow::anyhow!("{file}: PLY header: {}", short(&e.to_string())))?;
    // Every element takes at least one byte of what follows the header
    let payload = payload_bytes(bytes);
    for element in header.elements.values() {
        if element.count as u64 > payload {
            bail!(
                "{file}: PLY element '{}': the header declares {} of them but only {payload} \
                 bytes follow it",
                element.name,
                element.count
            );
        }
    }
    // The payload, element by element in the header's order
    let (mut vertices, mut faces) = (Vec::new(), Vec::new());
    for element in header.elements.values() {
        let items = parser
            .read_payload_for_element(&mut reader, element, &header)
            .map_err(|e| {
                anyhow::anyhow!(
                    "{file}: PLY element '{}': {}",
                    element.name,
                    short(&e.to_string())
                )
            })?;
        match element.name.as_str() {
            "vertex" => vertices = items,
            "face" => faces = items,
            _ => {}
        }
    }
    let coloured = header.elements.values().any(has_colours);
    // Vertices: x, y and z, each present
    let mut points = Vec::with_capacity(vertices.len());
    for (k, v) in vertices.iter().enumerate() {
        let (Some(x), Some(y), Some(z)) = (v.x, v.y, v.z) else {
            bail!("{file}: PLY vertex {k}: no x, y or z property of a number type");
        };
        points.push(DVec3::new(x, y, z));
    }
    let vertex_colours: Option<Vec<[u8; 3]>> = vertices.iter().map(|v| bytes_of(v.rgb)).collect();
    let faces = faces
        .into_iter()
        .enumerate()
        .map(|(k, face)| {
            let Some(indices) = face.indices else {
                bail!("{file}: PLY face {k}: no vertex_indices list of an integer type");
            };
            let radiosity = match face.radiosity {
                [Some(r), Some(g), Some(b)] => Some([r, g, b]),
                _ => None,
            };
            Ok(PlyFace {
                indices,
                colour: bytes_of(face.rgb),
                radiosity,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(PlyMesh {
        comments: header.comments,
        vertices: points,
        vertex_colours: vertex_colours.unwrap_or_default(),
        faces,
        coloured,
    })
}

/// Three colour components as bytes, when all are whole numbers 0 to 255.
fn bytes_of(rgb: [Option<f64>; 3]) -> Option<[u8; 3]> {
    let byte = |c: Option<f64>| {
        c.filter(|c| c.fract() == 0.0 && (0.0..=255.0).contains(c))
            .map(|c| c as u8)
    };
    Some([byte(rgb[0])?, byte(rgb[1])?, byte(rgb[2])?])
}

/// How many bytes follow the header's `end_header` line (all of them if there is none:
/// then the header read has already failed).
fn payload_bytes(bytes: &[u8]) -> u64 {
    let marker = b"end_header";
    let Some(at) = bytes.windows(marker.len()).position(|w| w == marker) else {
        return bytes.len() as u64;
    };
    let mut end = at + marker.len();
    // The line ends with \n or \r\n
    if bytes.get(end) == Some(&b'\r') {
        end += 1;
    }
    if bytes.get(end) == Some(&b'\n') {
        end += 1;
    }
    (bytes.len() - end) as u64
}

/// Whether an element carries colours.
fn has_colours(element: &ElementDef) -> bool {
    element
        .properties
        .keys()
        .any(|name| COLOUR_NAMES.contains(&name.as_str()))
}

/// A `ply-rs-bw` message on one line and at most [`MAX_MESSAGE_CHARS`] characters.
fn short(message: &str) -> String {
    let one_line = message
        .replace("\n\t", "; ")
        .replace(['\n', '\t', '\r'], " ");
    if one_line.chars().count() <= MAX_MESSAGE_CHARS {
        one_line
    } else {
        let mut s: String = one_line.chars().take(MAX_MESSAGE_CHARS).collect();
        s.push('…');
        s
    }
}
