//! The check behind the `fuzz_obj_parse` target: OBJ text (and an MTL library) →
//! `parse_obj` → a validated `Scene3` → `write_obj` → `parse_obj` again, asserting the
//! invariant stated in `fuzz/fuzz_targets/fuzz_obj_parse.rs`.
//!
//! Input layout: the OBJ text, then optionally a NUL byte and the MTL text. Every
//! `mtllib` name resolves to that MTL text when the input has a NUL byte, and to nothing
//! (a missing library) when it does not.
//!
//! Compiled by the fuzz crate and, through `#[path]`, by `tests/fuzz_replay.rs`.

use core::fmt;

use sceneinfo::scene::{Scene3, Subdivision};

use super::invariants::{self, MAX_INPUT_BYTES, Outcome};

/// Largest scene, in patches, that is also written out, read back and subdivided.
pub const MAX_ROUND_TRIP_PATCHES: usize = 256;

/// One fuzz case: the OBJ text and the MTL text, if any. Its `Debug` output is a Rust
/// reproducer.
pub struct ObjCase<'a> {
    /// The OBJ text.
    pub obj: &'a str,
    /// The MTL text every `mtllib` resolves to, if the input has one.
    pub mtl: Option<&'a str>,
}

impl<'a> ObjCase<'a> {
    /// Splits an input at its first NUL byte; `None` for invalid UTF-8.
    #[must_use]
    pub fn from_bytes(data: &'a [u8]) -> Option<Self> {
        let text = core::str::from_utf8(data).ok()?;
        Some(match text.split_once('\0') {
            Some((obj, mtl)) => Self {
                obj,
                mtl: Some(mtl),
            },
            None => Self {
                obj: text,
                mtl: None,
            },
        })
    }

    /// Parses the OBJ with the case's MTL library.
    ///
    /// # Errors
    ///
    /// Those of [`sceneinfo::io::parse_obj`].
    pub fn parse(&self, subdivision: Subdivision) -> sceneinfo::Result<Scene3> {
        let mtl = self.mtl;
        let options = sceneinfo::io::ObjOptions::new(subdivision);
        sceneinfo::io::parse_obj(self.obj, &options, |_| mtl.map(String::from)).map(|(s, _)| s)
    }
}

impl fmt::Debug for ObjCase<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "reproducer:")?;
        writeln!(f, "    let obj = {:?};", self.obj)?;
        writeln!(f, "    let mtl: Option<&str> = {:?};", self.mtl)?;
        write!(
            f,
            "    let (scene, report) = sceneinfo::io::parse_obj(obj, \
             &sceneinfo::io::ObjOptions::default(), |_| mtl.map(String::from))?;"
        )
    }
}

/// Checks what a valid `Scene3` promises: finite points, positive finite patch sizes
/// summing to one, materials with `ρ ∈ [0, 1)` and `E ≥ 0`.
///
/// # Errors
///
/// Describes the first broken promise.
pub fn check_scene(scene: &Scene3) -> Result<(), String> {
    let n = scene.n_patches();
    if n == 0 {
        return Err("a parsed scene has no patches".into());
    }
    for p in scene.points() {
        invariants::all_finite("point", &p.to_array())?;
    }
    let mut sizes = vec![0.0; n];
    scene
        .relative_areas_into(&mut sizes)
        .map_err(|e| format!("relative areas: {e}"))?;
    invariants::all_finite("relative area", &sizes)?;
    if let Some(k) = sizes.iter().position(|&a| !(a > 0.0)) {
        return Err(format!("patch {k} has relative area {}", sizes[k]));
    }
    let total: f64 = sizes.iter().sum();
    if (total - 1.0).abs() > 1e-9 {
        return Err(format!("relative areas sum to {total}"));
    }
    if !(scene.total_area() > 0.0 && scene.total_area().is_finite()) {
        return Err(format!("total area {}", scene.total_area()));
    }
    for m in scene.materials() {
        let rho_ok = m.reflectance.iter().all(|&r| (0.0..1.0).contains(&r));
        let e_ok = m.emittance.iter().all(|&e| e >= 0.0 && e.is_finite());
        if !(rho_ok && e_ok) {
            return Err(format!("invalid material {m:?}"));
        }
    }
    Ok(())
}

/// Runs one input through the parser, the scene checks and the round trip.
///
/// # Panics
///
/// When the core panics or an invariant breaks (the message holds a reproducer).
pub fn check(data: &[u8]) -> Outcome {
    if data.len() > MAX_INPUT_BYTES {
        return Outcome::Rejected;
    }
    let Some(case) = ObjCase::from_bytes(data) else {
        return Outcome::Rejected;
    };
    let fail = |problem: String| -> ! { panic!("{problem}\n{case:?}") };

    // Parse and check the scene's promises
    let scene = match case.parse(Subdivision::None) {
        Ok(scene) => scene,
        Err(err) => return invariants::refused(&err, &case),
    };
    if let Err(problem) = check_scene(&scene) {
        fail(problem);
    }
    if scene.n_patches() > MAX_ROUND_TRIP_PATCHES {
        return Outcome::TooLarge;
    }

    // write_obj then parse_obj gives back the same scene, bit for bit
    let (obj, mtl) = sceneinfo::io::write_obj(&scene, "round-trip.mtl");
    // (and nothing skipped or repaired on the way)
    let options = sceneinfo::io::ObjOptions::default();
    match sceneinfo::io::parse_obj(&obj, &options, |_| Some(mtl.clone())) {
        Ok((again, report)) if again == scene && report.warnings.is_empty() => {}
        Ok((again, report)) if again == scene => fail(format!(
            "round trip warned: {:?}\nwritten:\n{obj}\n{mtl}",
            report.warnings
        )),
        Ok((again, _)) => fail(format!(
            "round trip changed the scene:\n{scene:?}\n→\n{again:?}\nwritten:\n{obj}\n{mtl}"
        )),
        Err(err) => fail(format!(
            "round trip does not parse: {err}\nwritten:\n{obj}\n{mtl}"
        )),
    }

    // Subdivided faces: either a typed error or a valid scene
    for subdivision in [Subdivision::Grid(2), Subdivision::Triangles(1)] {
        match case.parse(subdivision) {
            Ok(fine) => {
                if let Err(problem) = check_scene(&fine) {
                    fail(format!("{subdivision:?}: {problem}"));
                }
            }
            Err(err) => {
                invariants::refused(&err, &case);
            }
        }
    }
    Outcome::Checked
}
