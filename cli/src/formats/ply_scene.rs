//! PLY scenes (ASCII, binary little- and big-endian), read with the `ply-rs-bw` crate.
//!
//! What is read: the `vertex` element's `x y z` (any numeric type) and the `face`
//! element's `vertex_indices` (or `vertex_index`) lists (any integer types); each face is
//! one polygon through [`crate::mesh::add_face`]. Every other element and property is read
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

/// Reads the PLY file `path`, whose bytes are `bytes`, into a scene.
///
/// # Errors
/// `file: where: what` for a broken header, an element count the file cannot hold, a
/// payload cut short, a missing coordinate, a vertex index out of range, a face the scene
/// refuses, …
pub fn read(path: &Path, bytes: &[u8], report: &mut LoadReport) -> Result<Scene3> {
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
    if header.elements.values().any(has_colours) {
        report.warn(
            None,
            LoadWarningKind::IgnoredMaterialData {
                what: "PLY colours (PLY scenes have no materials: faces are black)",
            },
        );
    }
    // Vertices: x, y and z, each present
    let mut points = Vec::with_capacity(vertices.len());
    for (k, v) in vertices.iter().enumerate() {
        let (Some(x), Some(y), Some(z)) = (v.x, v.y, v.z) else {
            bail!("{file}: PLY vertex {k}: no x, y or z property of a number type");
        };
        points.push(DVec3::new(x, y, z));
    }
    // Faces through the one door
    let mut builder = Scene3Builder::default();
    let mut polygon = Vec::new();
    for (k, face) in faces.iter().enumerate() {
        let Some(indices) = &face.indices else {
            bail!("{file}: PLY face {k}: no vertex_indices list of an integer type");
        };
        polygon.clear();
        for &i in indices {
            let p = usize::try_from(i)
                .ok()
                .and_then(|i| points.get(i))
                .ok_or_else(|| {
                    anyhow::anyhow!(
                        "{file}: PLY face {k}: vertex index {i} out of range ({} vertices)",
                        points.len()
                    )
                })?;
            polygon.push(*p);
        }
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
