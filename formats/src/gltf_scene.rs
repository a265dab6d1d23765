//! glTF 2.0 scenes (`.gltf` with external or data-URI buffers, `.glb`).
//!
//! The `gltf` crate parses and validates the JSON document (references between objects);
//! this module does the rest with every size checked against the bytes actually there:
//! the GLB container, the buffers (GLB binary chunk, `data:` URIs, files beside the
//! `.gltf`), the accessors, and the walk of the scene graph.
//!
//! What becomes of the document:
//! - the default scene's nodes (all scenes' if there is no default; the root nodes if the
//!   file has no scene), each mesh instance placed by its node's world transform; a
//!   transform of negative determinant (a mirror) reverses each triangle's winding so faces
//!   keep facing out;
//! - primitives of mode TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN as triangles, indexed or
//!   not; POINTS and LINES primitives are skipped with a warning;
//! - materials: `pbrMetallicRoughness.baseColorFactor` (rgb) is the reflectance ρ (clamped
//!   to [`Material::MAX_REFLECTANCE`]), `emissiveFactor` × `KHR_materials_emissive_strength`
//!   the emittance E; textures and vertex colours are ignored with a warning;
//! - object names: the node's name, else the mesh's, else `node K`.
//!
//! Not read: skins, morph targets, cameras, lights, images.
//! Files that require an extension the `gltf` crate does not know (Draco or meshopt
//! compression, `KHR_mesh_quantization`, …) are refused by its validation.

use std::collections::HashMap;
use std::path::Path;

use anyhow::{Context, Result, bail};
use base64::Engine as _;
use glam::{DMat4, DQuat, DVec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::{Mode, Semantic};
use sceneinfo::io::{LoadReport, LoadWarningKind};
use sceneinfo::scene::{Material, Scene3, Scene3Builder};

use crate::mesh::add_face;

/// Most elements of an accessor without a buffer view (zeros under sparse values).
const MAX_ZERO_ELEMENTS: usize = 1 << 26;

/// Most node visits in one walk of the scene graph (instances of instances multiply).
const MAX_NODE_VISITS: u64 = 1 << 24;

/// The GLB chunk types.
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// Reads the glTF or GLB file `path`, whose bytes are `bytes`, into a scene; what was
/// skipped or repaired goes to `report`.
///
/// # Errors
/// `file: where: what` for a broken container, a buffer shorter than it declares, an
/// accessor outside its buffer view, an index out of range, a face the scene refuses, …
pub fn read(path: &Path, bytes: &[u8], report: &mut LoadReport) -> Result<Scene3> {
    read_with(path, bytes, report, &|file| super::read_capped(file))
}

/// [`read`] with the files a `.gltf`'s buffer URIs name read by `open` (given the path:
/// the URI, percent-decoded, relative to the `.gltf`'s folder) rather than from the disk:
/// the 3D lab in a browser, which has the files the user picked and no folder.
///
/// # Errors
/// Those of [`read`]; `open`'s, in the context of the buffer whose file it is.
pub fn read_with(
    path: &Path,
    bytes: &[u8],
    report: &mut LoadReport,
    open: &dyn Fn(&Path) -> Result<Vec<u8>>,
) -> Result<Scene3> {
    let file = path.display();
    let (json, blob) = if bytes.starts_with(b"glTF") {
        split_glb(bytes).with_context(|| format!("{file}: GLB container"))?
    } else {
        (bytes, None)
    };
    let document = parse_document(json).with_context(|| format!("{file}: glTF"))?;
    let document = &document;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let buffers = load_buffers(document, blob, &dir, open).with_context(|| format!("{file}"))?;
    let mut reader = Reader {
        path,
        document,
        buffers,
        positions: HashMap::new(),
        indices: HashMap::new(),
        materials: HashMap::new(),
        builder: Scene3Builder::default(),
    };
    reader.walk(document, report)?;
    crate::mesh::build(reader.builder, report, path)
}

/// The validated document of a glTF JSON text.
///
/// The `gltf` crate's validation indexes the accessor a primitive's POSITION names before
/// checking it exists (gltf-json 1.4.1, `primitive_validate_hook`), so that reference is
/// checked here first.
fn parse_document(json: &[u8]) -> Result<gltf::Document> {
    let unchecked = gltf::Gltf::from_slice_without_validation(json)
        .map_err(|e| anyhow::anyhow!("{e}"))?
        .document
        .into_json();
    let accessors = unchecked.accessors.len();
    for (m, mesh) in unchecked.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = gltf::json::validation::Checked::Valid(Semantic::Positions);
            if let Some(k) = primitive.attributes.get(&position)
                && k.value() >= accessors
            {
                bail!(
                    "meshes[{m}].primitives[{p}].attributes[\"POSITION\"]: accessor {} \
                     does not exist ({accessors} accessors)",
                    k.value()
                );
            }
        }
    }
    gltf::Document::from_json(unchecked).map_err(|e| anyhow::anyhow!("{e}"))
}

/// The JSON chunk and the binary chunk (if any) of a GLB file, sizes checked.
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>)> {
    let word = |at: usize| -> Option<u32> {
        let b = bytes.get(at..at.checked_add(4)?)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        bail!("{} bytes: shorter than the 12-byte GLB header", bytes.len());
    };
    if version != 2 {
        bail!("byte 4: GLB version {version}: only version 2 is read");
    }
    if u64::from(length) != bytes.len() as u64 {
        bail!(
            "byte 8: the header declares {length} bytes but the file has {} (truncated or \
             padded)",
            bytes.len()
        );
    }
    // Chunks: 8-byte header (length, type), data, each start 4-aligned
    let mut at = 12usize;
    let (mut json, mut bin) = (None, None);
    while at < bytes.len() {
        let (Some(len), Some(kind)) = (word(at), word(at + 4)) else {
            bail!("byte {at}: a chunk header cut short by the end of the file");
        };
        let start = at + 8;
        let end = start
            .checked_add(len as usize)
            .filter(|&e| e <= bytes.len())
            .with_context(|| {
                format!(
                    "byte {at}: a chunk of {len} bytes runs past the end of the file \
                     ({} bytes)",
                    bytes.len()
                )
            })?;
        let data = &bytes[start..end];
        match kind {
            CHUNK_JSON if json.is_none() && at == 12 => json = Some(data),
            CHUNK_BIN if bin.is_none() && json.is_some() => bin = Some(data),
            CHUNK_JSON | CHUNK_BIN => {
                bail!("byte {at}: a misplaced or repeated JSON or BIN chunk")
            }
            // Chunks of unknown types are skipped, as the specification says
            _ => {}
        }
        // Next chunk, 4-aligned (the lengths are multiples of 4 in valid files)
        at = end.next_multiple_of(4);
    }
    let json = json.context("byte 12: no JSON chunk first")?;
    Ok((json, bin))
}

/// The bytes of each buffer that the geometry uses (`None` for the others, which may stay
/// unread: images in missing files do not stop a scene), each checked to hold at least the
/// bytes it declares.
fn load_buffers(
    document: &gltf::Document,
    blob: Option<&[u8]>,
    dir: &Path,
    open: &dyn Fn(&Path) -> Result<Vec<u8>>,
) -> Result<Vec<Option<Vec<u8>>>> {
    // The buffers the meshes' positions and indices read
    let mut used = vec![false; document.buffers().len()];
    for mesh in document.meshes() {
        for primitive in mesh.primitives() {
            let accessors = primitive
                .get(&Semantic::Positions)
                .into_iter()
                .chain(primitive.indices());
            for accessor in accessors {
                let json = &document.as_json().accessors[accessor.index()];
                let sparse = json
                    .sparse
                    .iter()
                    .flat_map(|s| [s.indices.buffer_view.value(), s.values.buffer_view.value()]);
                let views = json.buffer_view.iter().map(|v| v.value()).chain(sparse);
                for view in views.filter_map(|v| document.views().nth(v)) {
                    used[view.buffer().index()] = true;
                }
            }
        }
    }
    let mut buffers = Vec::with_capacity(used.len());
    for buffer in document.buffers() {
        let k = buffer.index();
        if !used[k] {
            buffers.push(None);
            continue;
        }
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob
                .with_context(|| {
                    format!("buffer {k}: refers to the GLB binary chunk, but there is none")
                })?
                .to_vec(),
            gltf::buffer::Source::Uri(uri) => {
                read_uri(uri, dir, open).with_context(|| format!("buffer {k}"))?
            }
        };
        if data.len() < buffer.length() {
            bail!(
                "buffer {k}: declares {} bytes but its data has {}",
                buffer.length(),
                data.len()
            );
        }
        buffers.push(Some(data));
    }
    Ok(buffers)
}

/// The bytes a buffer URI names: a base64 `data:` URI, or a file relative to `dir`
/// (percent-escapes decoded) read by `open` (from the disk: held to
/// [`super::MAX_FILE_BYTES`] or `--max-input`).
fn read_uri(uri: &str, dir: &Path, open: &dyn Fn(&Path) -> Result<Vec<u8>>) -> Result<Vec<u8>> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest
            .split_once(";base64,")
            .context("a data: URI that is not base64")?;
        let engine = base64::engine::GeneralPurpose::new(
            &base64::alphabet::STANDARD,
            base64::engine::GeneralPurposeConfig::new()
                .with_decode_padding_mode(base64::engine::DecodePaddingMode::Indifferent),
        );
        return engine
            .decode(data.trim())
            .map_err(|e| anyhow::anyhow!("data: URI: invalid base64: {e}"));
    }
    let relative = match uri.split_once(':') {
        // A one-letter "scheme" is a Windows drive; other schemes are not read
        Some((scheme, _)) if scheme.len() > 1 && !scheme.contains('/') => {
            bail!("URI '{uri}': only data: URIs and relative file names are read")
        }
        _ => percent_decode(uri).with_context(|| format!("URI '{uri}'"))?,
    };
    open(&dir.join(&relative))
}

/// `uri` with its `%XX` escapes decoded.
fn percent_decode(uri: &str) -> Result<String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut k = 0;
    while k < bytes.len() {
        if bytes[k] == b'%' {
            let hex = bytes
                .get(k + 1..k + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .with_context(|| format!("byte {k}: a '%' not followed by two hex digits"))?;
            out.push(hex);
            k += 3;
        } else {
            out.push(bytes[k]);
            k += 1;
        }
    }
    String::from_utf8(out).context("percent escapes that are not UTF-8")
}

/// The state of one read: buffers, accessors read so far (instances share them), the
/// materials made so far and the scene being built.
struct Reader<'p> {
    path: &'p Path,
    document: &'p gltf::Document,
    buffers: Vec<Option<Vec<u8>>>,
    positions: HashMap<usize, Vec<DVec3>>,
    indices: HashMap<usize, Vec<u32>>,
    materials: HashMap<Option<usize>, Material>,
    builder: Scene3Builder,
}

impl Reader<'_> {
    /// Walks the scene graph from its roots, adding every mesh instance.
    fn walk(&mut self, document: &gltf::Document, report: &mut LoadReport) -> Result<()> {
        let roots: Vec<gltf::Node<'_>> = if let Some(scene) = document.default_scene() {
            scene.nodes().collect()
        } else if document.scenes().len() > 0 {
            document.scenes().flat_map(|s| s.nodes()).collect()
        } else {
            // No scene: the nodes that are nobody's child
            let mut child = vec![false; document.nodes().len()];
            for node in document.nodes() {
                for c in node.children() {
                    child[c.index()] = true;
                }
            }
            document.nodes().filter(|n| !child[n.index()]).collect()
        };
        // Depth-first, with the world transform of each node's parent; a path longer than
        // the node count has a cycle
        let max_depth = document.nodes().len();
        let mut stack: Vec<(gltf::Node<'_>, DMat4, usize)> = roots
            .into_iter()
            .rev()
            .map(|n| (n, DMat4::IDENTITY, 1))
            .collect();
        let mut visits = 0u64;
        while let Some((node, parent, depth)) = stack.pop() {
            visits += 1;
            if visits > MAX_NODE_VISITS {
                bail!(
                    "{}: more than {MAX_NODE_VISITS} node instances: refused",
                    self.path.display()
                );
            }
            if depth > max_depth {
                bail!(
                    "{}: node {}: the node hierarchy has a cycle",
                    self.path.display(),
                    node.index()
                );
            }
            let world = parent * local_transform(&node);
            if let Some(mesh) = node.mesh() {
                self.add_instance(&node, &mesh, world, report)?;
            }
            for child in node.children().collect::<Vec<_>>().into_iter().rev() {
                stack.push((child, world, depth + 1));
            }
        }
        Ok(())
    }

    /// Adds the triangles of `mesh` placed by `world`.
    fn add_instance(
        &mut self,
        node: &gltf::Node<'_>,
        mesh: &gltf::Mesh<'_>,
        world: DMat4,
        report: &mut LoadReport,
    ) -> Result<()> {
        let file = self.path.display();
        let name = match (node.name(), mesh.name()) {
            (Some(n), _) | (None, Some(n)) => n.to_owned(),
            (None, None) => format!("node {}", node.index()),
        };
        let mirrored = world.determinant() < 0.0;
        for primitive in mesh.primitives() {
            let here = || format!("mesh {} primitive {}", mesh.index(), primitive.index());
            let mode = match primitive.mode() {
                m @ (Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) => m,
                other => {
                    let mode = match other {
                        Mode::Points => "POINTS",
                        Mode::Lines => "LINES",
                        Mode::LineLoop => "LINE_LOOP",
                        _ => "LINE_STRIP",
                    };
                    report.warn(None, LoadWarningKind::NonSurfacePrimitive { mode });
                    continue;
                }
            };
            let positions = primitive
                .get(&Semantic::Positions)
                .with_context(|| format!("{file}: {}: no POSITION attribute", here()))?;
            let material = self.material(&primitive.material(), report)?;
            if primitive.get(&Semantic::Colors(0)).is_some() {
                report.warn(
                    None,
                    LoadWarningKind::IgnoredMaterialData {
                        what: "vertex colours (COLOR_0)",
                    },
                );
            }
            self.read_positions(&positions)
                .with_context(|| format!("{file}: {}: POSITION", here()))?;
            if let Some(indices) = primitive.indices() {
                self.read_indices(&indices)
                    .with_context(|| format!("{file}: {}: indices", here()))?;
            }
            let points = &self.positions[&positions.index()];
            let world_points: Vec<DVec3> =
                points.iter().map(|&p| world.transform_point3(p)).collect();
            let indices = primitive.indices().map(|a| &self.indices[&a.index()]);
            let count = indices.map_or(world_points.len(), Vec::len);
            let index = |k: usize| -> Result<DVec3> {
                let i = indices.map_or(k, |ix| ix[k] as usize);
                world_points.get(i).copied().with_context(|| {
                    format!(
                        "{file}: {}: vertex index {i} out of range ({} vertices)",
                        here(),
                        world_points.len()
                    )
                })
            };
            self.builder.object(&name).material(material);
            // The triangles of the mode, in the order and winding the specification gives
            let triangles = match mode {
                Mode::Triangles => count / 3,
                _ => count.saturating_sub(2),
            };
            for t in 0..triangles {
                let [a, b, c] = match mode {
                    Mode::Triangles => [3 * t, 3 * t + 1, 3 * t + 2],
                    Mode::TriangleStrip if t % 2 == 0 => [t, t + 1, t + 2],
                    Mode::TriangleStrip => [t + 1, t, t + 2],
                    _ => [0, t + 1, t + 2],
                };
                let mut v = [index(a)?, index(b)?, index(c)?];
                if mirrored {
                    v.swap(1, 2);
                }
                add_face(
                    &mut self.builder,
                    &v,
                    report,
                    self.path,
                    format_args!(
                        "node {} mesh {} primitive {} triangle {t}",
                        node.index(),
                        mesh.index(),
                        primitive.index()
                    ),
                )?;
            }
        }
        Ok(())
    }

    /// The scene material of a glTF material (made once per material).
    fn material(
        &mut self,
        material: &gltf::Material<'_>,
        report: &mut LoadReport,
    ) -> Result<Material> {
        if let Some(m) = self.materials.get(&material.index()) {
            return Ok(*m);
        }
        let pbr = material.pbr_metallic_roughness();
        let [r, g, b, _] = pbr.base_color_factor().map(as_written);
        let strength = material.emissive_strength().map_or(1.0, as_written);
        let emit = material.emissive_factor().map(|e| as_written(e) * strength);
        let (m, clamped) = Material::clamped([r, g, b], emit).map_err(|e| {
            let which = material.index().map_or_else(
                || "the default material".to_owned(),
                |k| format!("material {k}"),
            );
            crate::located_at(self.path, which, e.kind())
        })?;
        if clamped {
            report.warn(None, LoadWarningKind::BaseColorClamped);
        }
        if pbr.base_color_texture().is_some() {
            report.warn(
                None,
                LoadWarningKind::IgnoredMaterialData {
                    what: "base colour textures (the base colour factor is used)",
                },
            );
        }
        if material.emissive_texture().is_some() {
            report.warn(
                None,
                LoadWarningKind::IgnoredMaterialData {
                    what: "emissive textures (the emissive factor is used)",
                },
            );
        }
        self.materials.insert(material.index(), m);
        Ok(m)
    }

    /// Reads a POSITION accessor (VEC3 of floats or, quantised, integers) once.
    fn read_positions(&mut self, accessor: &gltf::Accessor<'_>) -> Result<()> {
        if self.positions.contains_key(&accessor.index()) {
            return Ok(());
        }
        if accessor.dimensions() != Dimensions::Vec3 {
            bail!(
                "accessor {}: type {:?}, not VEC3",
                accessor.index(),
                accessor.dimensions()
            );
        }
        let values = self.components(accessor)?;
        let points = values
            .chunks_exact(3)
            .map(|c| DVec3::new(c[0], c[1], c[2]))
            .collect();
        self.positions.insert(accessor.index(), points);
        Ok(())
    }

    /// Reads an index accessor (SCALAR of unsigned integers) once.
    fn read_indices(&mut self, accessor: &gltf::Accessor<'_>) -> Result<()> {
        if self.indices.contains_key(&accessor.index()) {
            return Ok(());
        }
        if accessor.dimensions() != Dimensions::Scalar
            || !matches!(
                accessor.data_type(),
                DataType::U8 | DataType::U16 | DataType::U32
            )
        {
            bail!(
                "accessor {}: {:?} {:?}, not SCALAR of unsigned integers",
                accessor.index(),
                accessor.dimensions(),
                accessor.data_type()
            );
        }
        // Unsigned integers up to 2³² are exact in f64
        let values = self.components(accessor)?;
        let indices = values.into_iter().map(|v| v as u32).collect();
        self.indices.insert(accessor.index(), indices);
        Ok(())
    }

    /// The components of every element of `accessor`, in order, as f64 (normalised
    /// integers mapped to [0, 1] or [−1, 1]), sparse substitutions applied; every byte range
    /// checked against its buffer view and each view's against its buffer.
    fn components(&self, accessor: &gltf::Accessor<'_>) -> Result<Vec<f64>> {
        let k = accessor.index();
        let comps = accessor.dimensions().multiplicity();
        let size = accessor.data_type().size();
        let (data_type, normalized) = (accessor.data_type(), accessor.normalized());
        let count = accessor.count();
        if count == 0 {
            return Ok(Vec::new());
        }
        let element = comps * size;
        let sparse = self.document.as_json().accessors[k].sparse.as_ref();
        // The dense elements: from the buffer view, or zeros under a sparse accessor
        let mut out = match accessor.view() {
            Some(view) => {
                let stride = view.stride().unwrap_or(element);
                if stride < element {
                    bail!(
                        "buffer view {}: stride {stride} is shorter than accessor {k}'s \
                         {element}-byte elements",
                        view.index()
                    );
                }
                let bytes = self
                    .elements(&view, accessor.offset(), count, element, stride)
                    .with_context(|| format!("accessor {k}"))?;
                let mut out = Vec::with_capacity(count * comps);
                for e in 0..count {
                    for c in 0..comps {
                        let at = e * stride + c * size;
                        out.push(component(&bytes[at..at + size], data_type, normalized));
                    }
                }
                out
            }
            None if sparse.is_some() => {
                if count > MAX_ZERO_ELEMENTS {
                    bail!(
                        "accessor {k}: {count} elements without a buffer view: more than \
                         {MAX_ZERO_ELEMENTS}"
                    );
                }
                vec![0.0; count * comps]
            }
            None => bail!("accessor {k}: no buffer view (all zeros): nothing to draw"),
        };
        // Sparse substitutions: tightly packed indices and values
        if let Some(sparse) = sparse {
            let n = sparse.count.0 as usize;
            if n > count {
                bail!("accessor {k}: {n} sparse values for {count} elements");
            }
            let index_size = match sparse.indices.component_type {
                gltf::json::validation::Checked::Valid(t) => match t.0 {
                    gltf::json::accessor::ComponentType::U8 => 1,
                    gltf::json::accessor::ComponentType::U16 => 2,
                    gltf::json::accessor::ComponentType::U32 => 4,
                    other => bail!("accessor {k}: sparse indices of type {other:?}"),
                },
                gltf::json::validation::Checked::Invalid => {
                    bail!("accessor {k}: sparse indices of an invalid type")
                }
            };
            let view_of = |index: &gltf::json::Index<gltf::json::buffer::View>| {
                self.document.views().nth(index.value())
            };
            let (Some(index_view), Some(value_view)) = (
                view_of(&sparse.indices.buffer_view),
                view_of(&sparse.values.buffer_view),
            ) else {
                bail!("accessor {k}: sparse buffer view does not exist");
            };
            let indices = self
                .elements(
                    &index_view,
                    sparse.indices.byte_offset.0 as usize,
                    n,
                    index_size,
                    index_size,
                )
                .with_context(|| format!("accessor {k}: sparse indices"))?;
            let values = self
                .elements(
                    &value_view,
                    sparse.values.byte_offset.0 as usize,
                    n,
                    element,
                    element,
                )
                .with_context(|| format!("accessor {k}: sparse values"))?;
            for j in 0..n {
                let b = &indices[j * index_size..(j + 1) * index_size];
                let mut w = [0u8; 4];
                w[..index_size].copy_from_slice(b);
                let i = u32::from_le_bytes(w) as usize;
                if i >= count {
                    bail!("accessor {k}: sparse index {i} out of range ({count} elements)");
                }
                for c in 0..comps {
                    let at = j * element + c * size;
                    out[i * comps + c] = component(&values[at..at + size], data_type, normalized);
                }
            }
        }
        if out.iter().any(|x| !x.is_finite()) {
            bail!("accessor {k}: a value that is not a finite number");
        }
        Ok(out)
    }

    /// The bytes of `count` elements of `element` bytes, `stride` apart, from byte `offset`
    /// of `view`: from the first element's start to the last one's end, checked to lie in
    /// the view and the view in its buffer's data.
    fn elements(
        &self,
        view: &gltf::buffer::View<'_>,
        offset: usize,
        count: usize,
        element: usize,
        stride: usize,
    ) -> Result<&[u8]> {
        let (v, buffer) = (view.index(), view.buffer().index());
        let data = self.buffers[buffer]
            .as_deref()
            .with_context(|| format!("buffer {buffer} not loaded"))?;
        let view_bytes = view
            .offset()
            .checked_add(view.length())
            .and_then(|end| data.get(view.offset()..end))
            .with_context(|| {
                format!(
                    "buffer view {v}: bytes {}..+{} past the end of buffer {buffer} ({} bytes)",
                    view.offset(),
                    view.length(),
                    data.len()
                )
            })?;
        let end = count
            .checked_sub(1)
            .and_then(|last| last.checked_mul(stride))
            .and_then(|b| b.checked_add(element))
            .and_then(|b| b.checked_add(offset))
            .filter(|&n| n <= view_bytes.len())
            .with_context(|| {
                format!(
                    "{count} elements of {element} bytes (stride {stride}) from byte {offset} \
                     run past the end of buffer view {v} ({} bytes)",
                    view_bytes.len()
                )
            })?;
        Ok(&view_bytes[offset..end])
    }
}

/// A number of the JSON document, which the `gltf` crate holds as f32, as the decimal the
/// file most likely wrote: the shortest decimal that rounds to that f32, read as f64 (so a
/// reflectance written `0.2` is 0.2, as in an OBJ file, not 0.2000000029…).
fn as_written(v: f32) -> f64 {
    // Rust prints the shortest representation that reads back to the same f32
    v.to_string().parse().unwrap_or(f64::from(v))
}

/// A node's transform (parent from node) in f64: its matrix, or its translation × rotation
/// × scale with the rotation quaternion normalised in f64 (the file's, to 7 digits, is
/// not quite unit length).
fn local_transform(node: &gltf::Node<'_>) -> DMat4 {
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            DMat4::from_cols_array_2d(&matrix.map(|c| c.map(as_written)))
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            let [x, y, z, w] = rotation.map(as_written);
            let q = DQuat::from_xyzw(x, y, z, w);
            // A zero quaternion (invalid) is left as no rotation rather than NaN
            let q = if q.length_squared() > 0.0 {
                q.normalize()
            } else {
                DQuat::IDENTITY
            };
            DMat4::from_scale_rotation_translation(
                DVec3::from_array(scale.map(as_written)),
                q,
                DVec3::from_array(translation.map(as_written)),
            )
        }
    }
}

/// One little-endian component of `data_type` from `b` (exactly its size), as f64.
fn component(b: &[u8], data_type: DataType, normalized: bool) -> f64 {
    let raw = |n: usize| -> [u8; 4] {
        let mut w = [0u8; 4];
        w[..n].copy_from_slice(&b[..n]);
        w
    };
    match data_type {
        DataType::I8 => {
            let v = f64::from(b[0] as i8);
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        DataType::U8 => {
            let v = f64::from(b[0]);
            if normalized { v / 255.0 } else { v }
        }
        DataType::I16 => {
            let w = raw(2);
            let v = f64::from(i16::from_le_bytes([w[0], w[1]]));
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let w = raw(2);
            let v = f64::from(u16::from_le_bytes([w[0], w[1]]));
            if normalized { v / 65535.0 } else { v }
        }
        DataType::U32 => f64::from(u32::from_le_bytes(raw(4))),
        DataType::F32 => f64::from(f32::from_le_bytes(raw(4))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percent_escapes() {
        assert_eq!(percent_decode("a%20b.bin").unwrap(), "a b.bin");
        assert_eq!(percent_decode("%C3%A9.bin").unwrap(), "é.bin");
        assert!(percent_decode("a%2").is_err());
        assert!(percent_decode("a%zz").is_err());
        assert!(percent_decode("%FF").is_err());
    }

    #[test]
    fn components_normalised_and_not() {
        assert_eq!(component(&[255], DataType::U8, true), 1.0);
        assert_eq!(component(&[0x80], DataType::I8, true), -1.0);
        assert_eq!(component(&[0x81], DataType::I8, true), -1.0);
        assert_eq!(component(&[0xff, 0x7f], DataType::I16, true), 1.0);
        assert_eq!(component(&[0x34, 0x12], DataType::U16, false), 4660.0);
        assert_eq!(component(&[1, 0, 0, 0], DataType::U32, false), 1.0);
        assert_eq!(component(&1.5f32.to_le_bytes(), DataType::F32, false), 1.5);
    }

    #[test]
    fn glb_chunks_checked() {
        let mut glb = b"glTF".to_vec();
        glb.extend(2u32.to_le_bytes());
        glb.extend(28u32.to_le_bytes());
        glb.extend(8u32.to_le_bytes());
        glb.extend(CHUNK_JSON.to_le_bytes());
        glb.extend(b"{}      ");
        let (json, bin) = split_glb(&glb).unwrap();
        assert_eq!(json, b"{}      ");
        assert!(bin.is_none());
        // A chunk longer than the file
        let mut long = glb.clone();
        long[12..16].copy_from_slice(&9u32.to_le_bytes());
        assert!(split_glb(&long).is_err());
        // Shorter than a header, another version
        assert!(split_glb(b"glTF\x02\0").is_err());
        let mut v1 = glb.clone();
        v1[4] = 1;
        assert!(split_glb(&v1).is_err());
    }

    /// A `.gltf` whose buffer is a file beside it (Khronos' BoxTextured, in the corpus):
    /// `read_with` given that file reads the scene `read` reads from the disk, asks for the
    /// buffer's file only (not the texture's), and passes on `open`'s error for it.
    #[test]
    fn buffers_read_by_the_caller() {
        let dir =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/corpus/gltf/BoxTextured");
        let path = dir.join("BoxTextured.gltf");
        let bytes = std::fs::read(&path).unwrap();
        let from_disk = read(&path, &bytes, &mut LoadReport::default()).unwrap();
        let asked = std::cell::RefCell::new(Vec::new());
        let open = |file: &Path| {
            asked.borrow_mut().push(file.to_path_buf());
            std::fs::read(file).map_err(anyhow::Error::from)
        };
        let given = read_with(&path, &bytes, &mut LoadReport::default(), &open).unwrap();
        assert_eq!(asked.into_inner(), [dir.join("BoxTextured0.bin")]);
        assert_eq!(given.n_patches(), from_disk.n_patches());
        assert_eq!(
            given.total_area().to_bits(),
            from_disk.total_area().to_bits()
        );
        let refuse = |file: &Path| -> Result<Vec<u8>> { bail!("{} is missing", file.display()) };
        let name = Path::new("BoxTextured.gltf");
        let e = read_with(name, &bytes, &mut LoadReport::default(), &refuse).unwrap_err();
        assert_eq!(
            format!("{e:#}"),
            "BoxTextured.gltf: buffer 0: BoxTextured0.bin is missing"
        );
    }

    #[test]
    fn numbers_as_written() {
        assert_eq!(as_written(0.2), 0.2);
        assert_eq!(as_written(1.0), 1.0);
        // The shortest decimal of f32::MAX, not its exact value
        assert_eq!(as_written(f32::MAX), 3.402_823_5e38);
    }
}
