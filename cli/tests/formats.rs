//! glTF 2.0, GLB and PLY scenes through the real binary: the same room read from each
//! format gives the OBJ's measures; node transforms, mirrors, strips and fans; broken files
//! give located errors; the format comes from the content.

mod common;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use common::{bin, number, stdout_of, temp, without_timing};

/// The unit cube's corners.
const CORNERS: [[f32; 3]; 8] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
    [0.0, 1.0, 1.0],
];

/// The cube's six faces as quads facing inward (a room), counter-clockwise seen from inside.
const QUADS: [[u16; 4]; 6] = [
    [0, 1, 2, 3],
    [4, 7, 6, 5],
    [0, 4, 5, 1],
    [1, 5, 6, 2],
    [2, 6, 7, 3],
    [3, 7, 4, 0],
];

/// The room's 12 triangles (each quad as two, fan order).
fn triangles() -> Vec<[u16; 3]> {
    QUADS
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect()
}

/// The room as OBJ text.
fn room_obj() -> String {
    let mut s = String::new();
    for [x, y, z] in CORNERS {
        s += &format!("v {x} {y} {z}\n");
    }
    for [a, b, c] in triangles() {
        s += &format!("f {} {} {}\n", a + 1, b + 1, c + 1);
    }
    s
}

/// Standard base64 with padding.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                s.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// A glTF document of the cube's corners (accessor 0) and one primitive per entry of
/// `primitives` (mode, `u16` indices: accessor k + 1), one material, under `nodes` (JSON
/// of the node array; node 0 is the scene's root) and the binary buffer it reads; `uri` is
/// the buffer's URI, `None` for a GLB's binary chunk.
fn gltf(primitives: &[(u32, Vec<u16>)], nodes: &str, uri: Option<&str>) -> (String, Vec<u8>) {
    let mut buf: Vec<u8> = CORNERS
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    let (mut views, mut accessors, mut prims) = (
        vec![r#"{"buffer":0,"byteOffset":0,"byteLength":96}"#.to_string()],
        vec![
            r#"{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3","min":[0,0,0],"max":[1,1,1]}"#
                .to_string(),
        ],
        Vec::new(),
    );
    for (k, (mode, indices)) in primitives.iter().enumerate() {
        let offset = buf.len();
        buf.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{}}}"#,
            2 * indices.len()
        ));
        accessors.push(format!(
            r#"{{"bufferView":{},"componentType":5123,"count":{},"type":"SCALAR"}}"#,
            k + 1,
            indices.len()
        ));
        prims.push(format!(
            r#"{{"attributes":{{"POSITION":0}},"indices":{},"mode":{mode},"material":0}}"#,
            k + 1
        ));
        // Keep every view 4-aligned
        while !buf.len().is_multiple_of(4) {
            buf.push(0);
        }
    }
    let uri = uri.map_or(String::new(), |u| format!(r#","uri":"{u}""#));
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":{nodes},
"meshes":[{{"name":"box","primitives":[{}]}}],
"materials":[{{"pbrMetallicRoughness":{{"baseColorFactor":[0.5,0.5,0.5,1]}}}}],
"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}{uri}}}]}}"#,
        prims.join(","),
        accessors.join(","),
        views.join(","),
        buf.len()
    );
    (json, buf)
}

/// The room as 12 indexed TRIANGLES, with `nodes`, its buffer in a data URI.
fn room_gltf(nodes: &str) -> String {
    let indices = triangles().into_iter().flatten().collect();
    let (json, buf) = gltf(&[(4, indices)], nodes, Some("@"));
    json.replace(
        "\"uri\":\"@\"",
        &format!(
            "\"uri\":\"data:application/octet-stream;base64,{}\"",
            base64(&buf)
        ),
    )
}

/// A GLB container of `json` and `bin`.
fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(j);
    out.extend((b.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(b);
    out
}

/// The room as PLY: `format` is `ascii`, `binary_little_endian` or `binary_big_endian`;
/// float coordinates, `uchar int` index lists and per-face colours (ignored by the reader).
fn room_ply(format: &str) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat {format} 1.0\ncomment a room\nelement vertex 8\nproperty float x\n\
         property float y\nproperty float z\nelement face 12\n\
         property list uchar int vertex_indices\nproperty uchar red\nproperty uchar green\n\
         property uchar blue\nend_header\n"
    )
    .into_bytes();
    let big = format == "binary_big_endian";
    let f32s = |v: f32| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    let i32s = |v: i32| {
        if big {
            v.to_be_bytes()
        } else {
            v.to_le_bytes()
        }
    };
    for [x, y, z] in CORNERS {
        if format == "ascii" {
            out.extend(format!("{x} {y} {z}\n").bytes());
        } else {
            out.extend([x, y, z].into_iter().flat_map(f32s));
        }
    }
    for [a, b, c] in triangles() {
        if format == "ascii" {
            out.extend(format!("3 {a} {b} {c} 200 10 10\n").bytes());
        } else {
            out.push(3);
            out.extend([a, b, c].into_iter().flat_map(|i| i32s(i32::from(i))));
            out.extend([200, 10, 10]);
        }
    }
    out
}

/// Writes `bytes` to a temporary file named `name`.
fn write(name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let path = temp(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// `measure FILE --json [EXTRA]` without its timing keys.
fn measure(path: &Path, extra: &[&str]) -> String {
    let mut args = vec!["measure", path.to_str().unwrap(), "--json"];
    args.extend(extra);
    without_timing(stdout_of(&args).trim())
}

/// The measures every test compares.
const KEYS: &[&str] = &[
    "h_p",
    "h_s",
    "h_j",
    "i_s",
    "e_mse",
    "fano",
    "max_row_sum_error",
];

/// Asserts that two reports' measures agree to `tol`.
fn assert_close(a: &str, b: &str, tol: f64) {
    for key in KEYS {
        let (x, y) = (number(a, key), number(b, key));
        assert!((x - y).abs() <= tol, "{key}: {x} vs {y}\n{a}\n{b}");
    }
}

/// The room's measures from OBJ (a file of its own per call: the tests run in parallel).
fn obj_measures(extra: &[&str]) -> String {
    static CALLS: AtomicUsize = AtomicUsize::new(0);
    let k = CALLS.fetch_add(1, Ordering::Relaxed);
    measure(&write(&format!("room{k}.obj"), room_obj()), extra)
}

#[test]
fn gltf_glb_and_ply_rooms_measure_as_the_obj_room() {
    let obj = obj_measures(&[]);
    // A closed room: every row sums to one, no background
    assert!(obj.contains("\"n_patches\":12"), "{obj}");
    assert!(obj.contains("\"faces_read\":12"), "{obj}");
    let root = r#"[{"mesh":0}]"#;
    let gltf_path = write("room.gltf", room_gltf(root));
    // The same buffer in a file beside the .gltf, and in a GLB
    let indices = triangles().into_iter().flatten().collect();
    let (json, buf) = gltf(&[(4, indices)], root, Some("room%20data.bin"));
    write("room data.bin", &buf);
    let external = write("room_external.gltf", json);
    let indices = triangles().into_iter().flatten().collect();
    let (json, buf) = gltf(&[(4, indices)], root, None);
    let glb_path = write("room.glb", glb(&json, &buf));
    for path in [&gltf_path, &external, &glb_path] {
        assert_eq!(measure(path, &[]), obj, "{}", path.display());
    }
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let path = write(&format!("room_{format}.ply"), room_ply(format));
        assert_eq!(measure(&path, &[]), obj, "{format}");
    }
    // Monte Carlo lines with one seed: the same faces in the same order, the same numbers
    let lines = ["--lines", "65536", "--seed", "7"];
    assert_eq!(measure(&glb_path, &lines), obj_measures(&lines));
}

#[test]
fn node_transforms_and_mirrors_keep_the_measures() {
    let obj = obj_measures(&[]);
    // Uniform scale, rotation (unit quaternion), translation, on a parent of the mesh node
    let nodes = r#"[{"children":[1],"scale":[2.5,2.5,2.5],"rotation":[0.1825742,0.3651484,0.5477226,0.7302967],"translation":[3,-4,5]},{"mesh":0,"translation":[-0.5,-0.5,-0.5]}]"#;
    let moved = measure(&write("room_moved.gltf", room_gltf(nodes)), &[]);
    assert_close(&moved, &obj, 1e-12);
    // A column-major matrix
    let nodes = r#"[{"mesh":0,"matrix":[0,1,0,0, -1,0,0,0, 0,0,1,0, 10,20,30,1]}]"#;
    let matrix = measure(&write("room_matrix.gltf", room_gltf(nodes)), &[]);
    assert_close(&matrix, &obj, 1e-12);
    // Mirrors (negative determinant): the faces must still face into the room, else every
    // row would leave to the background
    for (name, scale) in [("x", "[-1,1,1]"), ("xyz", "[-2,-2,-2]")] {
        let nodes = format!(r#"[{{"mesh":0,"scale":{scale}}}]"#);
        let mirrored = measure(
            &write(&format!("room_mirror_{name}.gltf"), room_gltf(&nodes)),
            &[],
        );
        assert!(mirrored.contains("\"background\":false"), "{mirrored}");
        assert_close(&mirrored, &obj, 1e-12);
    }
}

#[test]
fn the_default_scene_else_every_scene_else_the_root_nodes() {
    let nodes = r#"[{"mesh":0},{"mesh":0,"translation":[10,0,0]}]"#;
    let two_scenes = r#""scenes":[{"nodes":[0]},{"nodes":[1]}]"#;
    let base = room_gltf(nodes).replace(r#""scene":0,"scenes":[{"nodes":[0]}]"#, two_scenes);
    assert!(base.contains(two_scenes));
    let lines = ["--lines", "200000"];
    let patches =
        |name: &str, json: String| number(&measure(&write(name, json), &lines), "n_patches");
    // No default scene: both scenes' rooms
    assert_eq!(patches("two_scenes.gltf", base.clone()), 24.0);
    // The default scene only
    let default = base.replace(two_scenes, &format!(r#""scene":1,{two_scenes}"#));
    assert_eq!(patches("default_scene.gltf", default), 12.0);
    // No scene at all: the nodes that are nobody's child
    let none = base.replace(&format!("{two_scenes},"), "");
    assert!(!none.contains("scenes"));
    assert_eq!(patches("no_scene.gltf", none), 24.0);
}

#[test]
fn strips_fans_and_skipped_primitives() {
    let obj = obj_measures(&[]);
    // One triangle strip over all six faces, joined by degenerate triangles (skipped)
    let mut strip = Vec::new();
    for (k, &[a, b, c, d]) in QUADS.iter().enumerate() {
        if k > 0 {
            let last = *strip.last().unwrap();
            strip.extend([last, a]);
        }
        strip.extend([a, b, d, c]);
    }
    // Six fans, and a POINTS primitive (skipped)
    let mut prims = vec![(5, strip.clone())];
    let (json, buf) = gltf(&prims, r#"[{"mesh":0}]"#, None);
    let strip_path = write("room_strip.glb", glb(&json, &buf));
    let out = measure(&strip_path, &[]);
    // The strip splits each quad along its other diagonal: equal up to rounding
    assert_close(&out, &obj, 1e-12);
    assert!(out.contains("\"faces_read\":32"), "{out}");
    assert!(
        out.contains("dropped a face or piece of zero area (20 times)"),
        "{out}"
    );
    prims = QUADS.iter().map(|q| (6, q.to_vec())).collect();
    prims.push((0, vec![0, 1, 2]));
    let (json, buf) = gltf(&prims, r#"[{"mesh":0}]"#, None);
    let fan_path = write("room_fan.glb", glb(&json, &buf));
    let out = measure(&fan_path, &[]);
    assert_close(&out, &obj, 0.0);
    assert!(out.contains("skipped POINTS primitives"), "{out}");
    // The table prints the warnings on stderr
    let run = bin().arg("measure").arg(&fan_path).output().unwrap();
    assert!(run.status.success());
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        err.contains(&format!("warning: {}: skipped POINTS", fan_path.display())),
        "{err}"
    );
}

#[test]
fn sparse_positions_over_zeros_give_the_room() {
    let obj = obj_measures(&[]);
    // POSITION without a buffer view (zeros), every corner given by sparse values
    let indices = triangles().into_iter().flatten().collect();
    let (json, mut buf) = gltf(&[(4, indices)], r#"[{"mesh":0}]"#, None);
    let at = buf.len();
    buf.extend(0u8..8);
    let json = json
        .replace(
            r#"{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3","#,
            r#"{"componentType":5126,"count":8,"type":"VEC3","sparse":{"count":8,"indices":{"bufferView":2,"componentType":5121},"values":{"bufferView":0}},"#,
        )
        .replace(
            r#"],"buffers""#,
            &format!(r#",{{"buffer":0,"byteOffset":{at},"byteLength":8}}],"buffers""#),
        )
        .replace(
            &format!(r#""byteLength":{at}}}]"#),
            &format!(r#""byteLength":{}}}]"#, buf.len()),
        );
    assert!(
        json.contains(r#""count":8,"type":"VEC3","sparse""#),
        "{json}"
    );
    assert!(
        json.contains(&format!(r#""byteLength":{}}}]"#, buf.len())),
        "{json}"
    );
    let out = measure(&write("room_sparse.glb", glb(&json, &buf)), &[]);
    assert_eq!(out, obj);
}

#[test]
fn gltf_materials_match_the_obj_and_mtl() {
    // One emissive face (emissive factor × KHR_materials_emissive_strength), white walls
    // (base colour 1: clamped to 0.99 with a warning)
    let indices: Vec<u16> = triangles().into_iter().flatten().collect();
    let (json, buf) = gltf(
        &[(4, indices[..6].to_vec()), (4, indices[6..].to_vec())],
        r#"[{"mesh":0}]"#,
        None,
    );
    let json = json
        .replace(
            r#""material":0}]"#,
            r#""material":1}]"#,
        )
        .replace(
            r#""materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.5,0.5,0.5,1]}}]"#,
            r#""materials":[{"emissiveFactor":[1,0.5,0.25],"extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":4}},"pbrMetallicRoughness":{"baseColorFactor":[0.2,0.3,0.4,1]}},{"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,1]}}],"extensionsUsed":["KHR_materials_emissive_strength"]"#,
        );
    let glb_path = write("lit_room.glb", glb(&json, &buf));
    let mut obj = String::from("mtllib lit_room.mtl\n");
    for [x, y, z] in CORNERS {
        obj += &format!("v {x} {y} {z}\n");
    }
    for (k, [a, b, c]) in triangles().into_iter().enumerate() {
        if k == 0 {
            obj += "usemtl lamp\n";
        }
        if k == 2 {
            obj += "usemtl wall\n";
        }
        obj += &format!("f {} {} {}\n", a + 1, b + 1, c + 1);
    }
    write(
        "lit_room.mtl",
        "newmtl lamp\nKd 0.2 0.3 0.4\nKe 4 2 1\nnewmtl wall\nKd 0.99 0.99 0.99\n",
    );
    let obj_path = write("lit_room.obj", obj);
    let radiosity = |p: &Path| {
        let out = bin()
            .arg("radiosity")
            .arg(p)
            .arg("--json")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        (
            without_timing(String::from_utf8(out.stdout).unwrap().trim()),
            String::from_utf8(out.stderr).unwrap(),
        )
    };
    let (from_glb, warnings) = radiosity(&glb_path);
    let (from_obj, _) = radiosity(&obj_path);
    assert_eq!(from_glb, from_obj);
    assert!(warnings.contains("clamped to 0.99"), "{warnings}");
}

#[test]
fn broken_files_give_located_errors() {
    let fails = |path: &Path, expected: &str| {
        let out = bin().arg("measure").arg(path).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{}", path.display());
        let err = String::from_utf8_lossy(&out.stderr);
        let want = format!("{}: {expected}", path.display());
        assert!(err.contains(&want), "want {want:?}, got {err}");
    };
    // A GLB cut short, and one whose binary chunk is shorter than its buffer declares
    let indices = triangles().into_iter().flatten().collect();
    let (json, buf) = gltf(&[(4, indices)], r#"[{"mesh":0}]"#, None);
    let whole = glb(&json, &buf);
    fails(
        &write("cut.glb", &whole[..whole.len() - 10]),
        &format!(
            "GLB container: byte 8: the header declares {} bytes but the file has {}",
            whole.len(),
            whole.len() - 10
        ),
    );
    fails(
        &write("short_bin.glb", glb(&json, &buf[..buf.len() - 8])),
        &format!(
            "buffer 0: declares {} bytes but its data has {}",
            buf.len(),
            buf.len() - 8
        ),
    );
    // An index past the vertices; an accessor past its view
    let (json, buf) = gltf(&[(4, vec![0, 1, 9])], r#"[{"mesh":0}]"#, None);
    fails(
        &write("bad_index.glb", glb(&json, &buf)),
        "mesh 0 primitive 0: vertex index 9 out of range (8 vertices)",
    );
    let (json, buf) = gltf(&[(4, vec![0, 1, 2])], r#"[{"mesh":0}]"#, None);
    let json = json.replace(r#""count":8"#, r#""count":9"#);
    fails(
        &write("bad_accessor.glb", glb(&json, &buf)),
        "mesh 0 primitive 0: POSITION: accessor 0: 9 elements of 12 bytes (stride 12) from byte 0 \
         run past the end of buffer view 0 (96 bytes)",
    );
    // A POSITION accessor that does not exist (the gltf crate's validation would index it)
    let json = json.replace(r#""POSITION":0"#, r#""POSITION":7"#);
    fails(
        &write("no_position.glb", glb(&json, &buf)),
        "glTF: meshes[0].primitives[0].attributes[\"POSITION\"]: accessor 7 does not exist \
         (2 accessors)",
    );
    // Nothing but lines: the error says what was skipped
    let (json, buf) = gltf(&[(1, vec![0, 1, 2, 3])], r#"[{"mesh":0}]"#, None);
    fails(
        &write("lines.glb", glb(&json, &buf)),
        "scene has no patches (skipped LINES primitives",
    );
    // A PLY cut short, one whose header promises more than the file holds, a bad index
    let ply = room_ply("binary_little_endian");
    fails(
        &write("cut.ply", &ply[..ply.len() - 7]),
        "PLY element 'face': ",
    );
    let text = String::from_utf8(room_ply("ascii")).unwrap();
    fails(
        &write(
            "many.ply",
            text.replace("element face 12", "element face 4000000000"),
        ),
        "PLY element 'face': the header declares 4000000000 of them but only",
    );
    fails(
        &write("bad_index.ply", text.replace("3 0 1 2 ", "3 0 1 8 ")),
        "PLY face 0: vertex index 8 out of range (8 vertices)",
    );
    // Over the 2 GiB cap (a sparse file: nothing is written), refused before reading
    let huge = temp("huge.glb");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len((2 << 30) + 1)
        .unwrap();
    fails(
        &huge,
        "2147483649 bytes, larger than 2147483648 bytes (2 GiB), the cap on scene files; \
         raise --max-input",
    );
    std::fs::remove_file(&huge).unwrap();
    // Not glTF at all
    fails(&write("not.glb", b"glTF\x01\0\0\0"), "GLB container: ");
}

#[test]
fn the_format_comes_from_the_content() {
    let obj = obj_measures(&[]);
    // A PLY named .obj, a GLB named .gltf... read as what they are, with a note
    let ply_as_obj = write("really_ply.obj", room_ply("ascii"));
    let out = measure(&ply_as_obj, &[]);
    assert_close(&out, &obj, 0.0);
    assert!(
        out.contains("the extension says '.obj' but the content is PLY: read as PLY"),
        "{out}"
    );
    let gltf_as_ply = write("really_gltf.ply", room_gltf(r#"[{"mesh":0}]"#));
    let out = measure(&gltf_as_ply, &[]);
    assert_close(&out, &obj, 0.0);
    assert!(out.contains("content is glTF"), "{out}");
    // An OBJ without an extension, and an OBJ named .flat
    let plain = write("room_without_extension", room_obj());
    assert_close(&measure(&plain, &[]), &obj, 0.0);
    let out = measure(&write("room_obj.flat", room_obj()), &[]);
    assert!(out.contains("content is OBJ"), "{out}");
    // A flatland scene named .obj: read as flat, the note in its JSON too
    let out = measure(&write("flat_named.obj", "seg 0 0 1 0\nseg 1 1 0 1\n"), &[]);
    assert!(out.contains("\"n_patches\":2"), "{out}");
    assert!(out.contains("the content is flat: read as flat"), "{out}");
    // `draw` sends a PLY to the 3D drawer by its content too
    let out_ply = temp("room_drawn.ply");
    let status = bin()
        .args(["draw", ply_as_obj.to_str().unwrap(), "--ply"])
        .arg(&out_ply)
        .status()
        .unwrap();
    assert!(status.success());
}
