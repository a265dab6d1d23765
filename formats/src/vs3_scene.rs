//! View3D's input format (`.vs3`), read into a 3D scene, so that View3D's users can run
//! the same files through sceneinfo, and the map from the scene's patches to View3D's
//! output surfaces ([`Vs3Layout`]), so that sceneinfo's view factors can be written as
//! View3D's (`formfactors FILE.vs3 --out F.vf3`).
//!
//! The format, from the View3D 3.3 manual (`doc/view3d-manual.tex`, "View3D Surfaces",
//! "Input File Format"; the manual only, never View3D's code, which is GPL). Each line
//! begins with one character saying what it is (either case):
//!
//! | line | meaning | read as |
//! |---|---|---|
//! | `! …`, `/ …` | comment (also after data on a line) | skipped |
//! | `T title` | title | skipped |
//! | `C name=value …` | controls (`eps`, `maxU`, `maxO`, `minO`, `row`, `col`, `encl`, `emit`, `out`, `list`) | read and checked ([`crate::vs3_controls`]): `eps` the tolerance when no `--tol`; `encl=1`, `emit=1` applied to the output surfaces ([`Vs3Layout::view3d_matrix`]); `row`, `col` name output surfaces (printed by `formfactors`); an unknown name or bad value refused |
//! | `F 3`, `F 3a` | geometry format | both read; `F 2`, `F 1` (other programs') refused |
//! | `V n x y z` | vertex `n` (`F 3`) | a point |
//! | `S n v1 v2 v3 v4 base cmb emit name` | surface (`F 3`; `v4 = 0`: a triangle) | patches; `emit` the output surface's emittance |
//! | `S n shape base cmb emit name` + numbers | surface (`F 3a`): origin, azimuth, tilt, then `R` width height, `Q` four `(x, y)`, `T` three | patches (`vs3_parse::blast_corners`) |
//! | `S` with `base ≠ 0` | subsurface (a window in a wall) | its own patches; cut out of its base |
//! | `M` | masking surface, on a base, facing it | no patch; cut out of its base; its row sees only the base |
//! | `N` | null surface, on a base, facing it | no patch; cut out of its base; no row |
//! | `O` | obstruction only | patches that block, without a row or column in the output |
//! | `E …`, `e …`, `* …` | end of data | stops reading |
//!
//! Vertices are listed counter-clockwise seen from the front of the surface (the active
//! side), as in OBJ and sceneinfo: they are copied as they are. The emittance is the output
//! surface's (its `.vf3` line, Hottel's script-F with `emit=1`; with `emit=1` combined
//! surfaces must agree on it); the name is used in messages.
//!
//! **How each surface becomes patches.** A surface's region is its polygon minus the
//! subsurfaces, masks and null surfaces whose base it is, cut into disjoint convex pieces
//! (`vs3_pieces::minus`). A subsurface must lie in its base's plane, inside it,
//! facing the same way (masks and null surfaces: the opposite way), and be numbered after
//! it; otherwise the file is refused at its line. Surfaces with a non-zero `cmb` join the
//! lower-numbered surface they name: the pieces of one output surface become one patch when
//! they are coplanar and fill a convex polygon (their convex hull), else one patch each.
//!
//! **What View3D reports, and sceneinfo's [`Vs3Layout`].** Run on small files by the
//! project (View3D 4.0.0 from its public source, outside the project; `tests/data/vs3/README.md`),
//! View3D's output lists one surface per `S` or `M` line that joins no other, in order:
//! a base with subsurfaces or null surfaces has the area of what is left of it, and its
//! view factors are that region's; a base with a mask keeps its whole area, and
//! `F(base → mask) = A_mask / A_base`, `F(mask → base) = 1`, its other entries those of
//! the unmasked part times `A_unmasked / A_base`; null and obstruction-only surfaces have
//! no row or column. [`Vs3Layout::combined_row`] gives those rows from the patches'
//! (view-factor algebra: `A_K F_KL = Σ_{p∈K} Σ_{q∈L} A_p F_pq`).

use std::collections::HashMap;
use std::path::Path;

use anyhow::{Result, anyhow};
use sceneinfo::geom::DVec3;
use sceneinfo::io::LoadReport;
use sceneinfo::scene::{Scene3, Scene3Builder};

use crate::mesh::add_face;
use crate::vs3_controls::{EnclosureReport, Vs3FileControls, enclosure_adjust, script_f};
use crate::vs3_parse::{Kind, Record};
use crate::vs3_pieces::{area, inside, minus, vector_area};

/// Relative agreement asked of a combined surface's piece areas and its hull's area.
const COMBINE_AREA_TOL: f64 = 1e-9;

/// Relative agreement asked of an output surface's area in the file and in the scene.
const LAYOUT_AREA_TOL: f64 = 1e-9;

/// Reads the `.vs3` file `text` from `path` (see the module documentation).
///
/// # Errors
/// `file:line: what` for a line that cannot be read or a construct sceneinfo has no
/// counterpart for; the scene builder's errors as the other mesh readers report them.
pub fn read(path: &Path, text: &str, report: &mut LoadReport) -> Result<Scene3> {
    Ok(build(path, text, report)?.0)
}

/// [`read`], and the map from the scene's patches to View3D's output surfaces.
///
/// # Errors
/// [`read`]'s; `file:line: what` for an output surface whose area the scene does not keep
/// (a coincident surface dropped or clipped it, a piece was degenerate): its row would
/// not be View3D's.
pub fn read_with_layout(
    path: &Path,
    text: &str,
    report: &mut LoadReport,
) -> Result<(Scene3, Vs3Layout)> {
    let (scene, plan) = build(path, text, report)?;
    let layout = Vs3Layout::new(path, &scene, plan)?;
    Ok((scene, layout))
}

/// What a group of combined surfaces is in the output.
#[derive(Clone, Copy, Debug, PartialEq)]
enum GroupKind {
    /// An output surface with patches.
    Radiating,
    /// An output surface without patches: a mask on the group given.
    Mask { base: usize },
    /// Patches without an output surface.
    Obstruction,
}

/// One surface, or several joined by `cmb`, and the pieces that are its region.
struct Group {
    kind: GroupKind,
    number: usize,
    name: String,
    line: usize,
    /// The object name its faces carry in the scene (unique in the file).
    object: String,
    /// The region's area in the file's units (masks: the mask's).
    area: f64,
    /// The emittance of its first surface.
    emissivity: Option<f64>,
    pieces: Vec<Vec<DVec3>>,
}

/// The groups of the file, in order, before the scene is built.
struct Plan {
    groups: Vec<Group>,
    controls: Vs3FileControls,
}

/// The scene of the file and its groups.
fn build(path: &Path, text: &str, report: &mut LoadReport) -> Result<(Scene3, Plan)> {
    let at = |line: usize, what: &str| anyhow!("{}:{line}: {what}", path.display());
    let (mut records, controls) = crate::vs3_parse::parse(path, text)?;
    records.sort_by_key(|r| r.number);
    let mut index: HashMap<usize, usize> = HashMap::with_capacity(records.len());
    for (k, r) in records.iter().enumerate() {
        if index.insert(r.number, k).is_some() {
            return Err(at(r.line, &format!("surface {} is given twice", r.number)));
        }
    }
    // A surface without area is dropped with a warning, as in the other formats, unless
    // something lies on it or it lies on something (then it is refused)
    let normals: Vec<Option<DVec3>> = records
        .iter()
        .map(|r| {
            (r.corners.len() >= 3)
                .then(|| vector_area(&r.corners).try_normalize())
                .flatten()
        })
        .collect();
    let mut holes: Vec<Vec<Vec<DVec3>>> = vec![Vec::new(); records.len()];
    for (k, r) in records.iter().enumerate() {
        if let Some(b) = check_base(r, normals[k], &records, &index, &normals, &at)? {
            let mut hole = r.corners.clone();
            if r.kind != Kind::Radiating {
                hole.reverse();
            }
            holes[b].push(hole);
        }
        check_combine(r, &records, &index, &at)?;
    }
    // Each surface's region: its polygon minus what lies on it
    let mut regions: Vec<Vec<Vec<DVec3>>> = Vec::with_capacity(records.len());
    for (k, r) in records.iter().enumerate() {
        if holes[k].is_empty() {
            regions.push(vec![r.corners.clone()]);
            continue;
        }
        let Some(normal) = normals[k] else {
            return Err(at(r.line, &format!("surface {} has no area", r.number)));
        };
        if !convex(&r.corners, normal) {
            return Err(at(
                r.line,
                &format!(
                    "surface {} has subsurfaces but is not convex (View3D: quadrilaterals must \
                     be convex)",
                    r.number
                ),
            ));
        }
        let pieces = minus(&r.corners, &holes[k], normal).ok_or_else(|| {
            at(
                r.line,
                &format!(
                    "surface {}: too many pieces around its subsurfaces",
                    r.number
                ),
            )
        })?;
        let left: f64 = pieces.iter().map(|p| area(p)).sum();
        let cut: f64 = holes[k].iter().map(|h| area(h)).sum();
        let whole = area(&r.corners);
        if (left + cut - whole).abs() > 1e-6 * whole {
            return Err(at(
                r.line,
                &format!(
                    "the subsurfaces, masks or null surfaces on surface {} overlap one another",
                    r.number
                ),
            ));
        }
        regions.push(pieces);
    }
    let plan = plan(&records, &index, regions, controls, &at)?;
    let mut builder = Scene3Builder::default();
    for g in &plan.groups {
        if matches!(g.kind, GroupKind::Mask { .. }) {
            continue;
        }
        builder.object(&g.object);
        let whole = if g.pieces.len() > 1 {
            let parts: Vec<&[DVec3]> = g.pieces.iter().map(Vec::as_slice).collect();
            union_of_pieces(&parts)
        } else {
            None
        };
        let faces = match &whole {
            Some(w) => std::slice::from_ref(w),
            None => g.pieces.as_slice(),
        };
        for face in faces {
            add_face(
                &mut builder,
                face,
                report,
                path,
                format_args!("line {}", g.line),
            )?;
        }
    }
    let scene = crate::mesh::build(builder, report, path)?;
    Ok((scene, plan))
}

/// The record a surface's base names, checked as the manual asks (numbered before it,
/// in its plane, inside it, facing as its type says); `None` without a base.
fn check_base(
    r: &Record,
    normal: Option<DVec3>,
    records: &[Record],
    index: &HashMap<usize, usize>,
    normals: &[Option<DVec3>],
    at: &dyn Fn(usize, &str) -> anyhow::Error,
) -> Result<Option<usize>> {
    let letter = r.kind.letter();
    if r.base == 0 {
        if matches!(r.kind, Kind::Mask | Kind::Null) {
            return Err(at(
                r.line,
                &format!("a {letter} surface lies on a base surface: its base is 0"),
            ));
        }
        return Ok(None);
    }
    if r.kind == Kind::Obstruction {
        return Err(at(
            r.line,
            "an obstruction-only surface (O) with a base is not read (the manual gives O \
             surfaces subsurfaces, not bases)",
        ));
    }
    let b = match index.get(&r.base) {
        Some(&b) if r.base < r.number => b,
        _ => {
            return Err(at(
                r.line,
                &format!(
                    "base {} is not a surface numbered before surface {}",
                    r.base, r.number
                ),
            ));
        }
    };
    let base = &records[b];
    let allowed = match r.kind {
        Kind::Radiating => matches!(base.kind, Kind::Radiating | Kind::Obstruction),
        _ => base.kind == Kind::Radiating,
    };
    if !allowed {
        return Err(at(
            r.line,
            &format!(
                "a {letter} surface cannot lie on a {} surface (surface {})",
                base.kind.letter(),
                base.number
            ),
        ));
    }
    let (Some(normal), Some(n)) = (normal, normals[b]) else {
        return Err(at(
            r.line,
            &format!(
                "surface {} or its base {} has no area",
                r.number, base.number
            ),
        ));
    };
    let same_way = normal.dot(n) > 0.0;
    let (facing_ok, facing) = match r.kind {
        Kind::Radiating => (same_way, "the same way as"),
        _ => (!same_way, "towards"),
    };
    let mut corners = r.corners.clone();
    if !same_way {
        corners.reverse();
    }
    if !facing_ok || !inside(&corners, &base.corners, n) {
        return Err(at(
            r.line,
            &format!(
                "surface {} must lie in the plane of its base {} (line {}), inside it, facing \
                 {facing} it",
                r.number, base.number, base.line
            ),
        ));
    }
    Ok(Some(b))
}

/// Checks a surface's `cmb`: an earlier surface of the same type that joins no other.
fn check_combine(
    r: &Record,
    records: &[Record],
    index: &HashMap<usize, usize>,
    at: &dyn Fn(usize, &str) -> anyhow::Error,
) -> Result<()> {
    if r.combine == 0 {
        return Ok(());
    }
    if matches!(r.kind, Kind::Mask | Kind::Null) {
        return Err(at(
            r.line,
            &format!("a {} surface with cmb is not read", r.kind.letter()),
        ));
    }
    match index.get(&r.combine).map(|&h| &records[h]) {
        Some(h) if r.combine < r.number && h.combine == 0 && h.kind == r.kind => Ok(()),
        _ => Err(at(
            r.line,
            &format!(
                "cmb {} must name an earlier surface of the same type combined with no other \
                 (View3D: combine every piece with the lowest-numbered one, do not chain)",
                r.combine
            ),
        )),
    }
}

/// Whether the polygon `p` is convex, counter-clockwise about `normal`.
fn convex(p: &[DVec3], normal: DVec3) -> bool {
    let n = p.len();
    (0..n).all(|k| {
        let (a, b, c) = (p[k], p[(k + 1) % n], p[(k + 2) % n]);
        (b - a).cross(c - b).dot(normal) >= -1e-12 * (b - a).length() * (c - b).length()
    })
}

/// The groups of the records (sorted by number), each with its pieces.
fn plan(
    records: &[Record],
    index: &HashMap<usize, usize>,
    regions: Vec<Vec<Vec<DVec3>>>,
    controls: Vs3FileControls,
    at: &dyn Fn(usize, &str) -> anyhow::Error,
) -> Result<Plan> {
    let mut groups: Vec<Group> = Vec::new();
    let mut group_of: HashMap<usize, usize> = HashMap::new();
    for (r, pieces) in records.iter().zip(regions) {
        if r.combine != 0 {
            let Some(&g) = group_of.get(&r.combine) else {
                continue;
            };
            if controls.emit && r.emissivity != groups[g].emissivity {
                return Err(at(
                    r.line,
                    &format!(
                        "emit=1: surface {} has emittance {:?} but the surface {} it combines \
                         with has {:?}: a combined surface has one emittance (View3D 4.0.0 \
                         lists the emittances of the first input surfaces, not the combined \
                         ones'); give them the same",
                        r.number, r.emissivity, groups[g].number, groups[g].emissivity
                    ),
                ));
            }
            groups[g].area += pieces.iter().map(|p| area(p)).sum::<f64>();
            groups[g].pieces.extend(pieces);
            group_of.insert(r.number, g);
            continue;
        }
        let kind = match r.kind {
            Kind::Radiating => GroupKind::Radiating,
            Kind::Obstruction => GroupKind::Obstruction,
            Kind::Null => continue,
            Kind::Mask => {
                // Checked: the base is an earlier S surface, so it has a group
                let base = index
                    .get(&r.base)
                    .and_then(|_| group_of.get(&r.base))
                    .copied()
                    .ok_or_else(|| anyhow!("line {}: mask without its base's group", r.line))?;
                GroupKind::Mask { base }
            }
        };
        let object = match kind {
            GroupKind::Obstruction => format!("obstruction {}", r.number),
            _ => format!("surface {}", r.number),
        };
        let area_of = if matches!(kind, GroupKind::Mask { .. }) {
            area(&r.corners)
        } else {
            pieces.iter().map(|p| area(p)).sum()
        };
        group_of.insert(r.number, groups.len());
        groups.push(Group {
            kind,
            number: r.number,
            name: r.name.clone(),
            line: r.line,
            object: if r.name.is_empty() {
                object
            } else {
                format!("{object} {}", r.name)
            },
            area: area_of,
            emissivity: r.emissivity,
            pieces: if matches!(kind, GroupKind::Mask { .. }) {
                Vec::new()
            } else {
                pieces
            },
        });
    }
    Ok(Plan { groups, controls })
}

/// One of View3D's output surfaces.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputSurface {
    /// Its number in the file (the lowest of the surfaces combined into it).
    pub number: usize,
    /// Its name in the file.
    pub name: String,
    /// Its area in the file's units, as View3D reports it.
    pub area: f64,
    /// For a mask, the output surface it masks.
    pub mask_of: Option<usize>,
    /// The emittance of its `S` or `M` line (`None`: not given).
    pub emissivity: Option<f64>,
    /// Its line in the file.
    pub line: usize,
}

/// View3D's output for a `.vs3` file ([`Vs3Layout::view3d_matrix`]).
#[derive(Clone, Debug, PartialEq)]
pub struct View3dSurfaces {
    /// The output surfaces' areas, in the file's units.
    pub areas: Vec<f64>,
    /// Row-major `N × N`: view factors (`encl=1`: adjusted), or script-F factors
    /// (`emit=1`).
    pub form_factors: Vec<f64>,
    /// The surfaces' emittances (1 where the file gives none).
    pub emissivities: Vec<f64>,
    /// The file's `encl=1`, applied.
    pub encl: bool,
    /// The file's `emit=1`, applied.
    pub emit: bool,
    /// What the enclosure adjustment reached (with `encl=1`).
    pub enclosure: Option<EnclosureReport>,
}

/// Which of a `.vs3` scene's patches make which of View3D's output surfaces (see the
/// module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Vs3Layout {
    surfaces: Vec<OutputSurface>,
    /// Per patch: its output surface (`None`: an obstruction-only surface's).
    patch_surface: Vec<Option<usize>>,
    /// Per patch: its area in the file's units.
    patch_area: Vec<f64>,
    /// Per output surface: its patches, in order.
    members: Vec<Vec<usize>>,
    /// Per output surface: the masks on it.
    masks: Vec<Vec<usize>>,
    /// The file's controls.
    controls: Vs3FileControls,
}

impl Vs3Layout {
    fn new(path: &Path, scene: &Scene3, plan: Plan) -> Result<Self> {
        let mut surfaces = Vec::new();
        let mut output_of_group: Vec<Option<usize>> = Vec::with_capacity(plan.groups.len());
        let mut group_of_object: HashMap<&str, usize> = HashMap::new();
        for (g, group) in plan.groups.iter().enumerate() {
            group_of_object.insert(group.object.as_str(), g);
            if group.kind == GroupKind::Obstruction {
                output_of_group.push(None);
                continue;
            }
            output_of_group.push(Some(surfaces.len()));
            let mask_of = match group.kind {
                GroupKind::Mask { base } => output_of_group[base],
                _ => None,
            };
            surfaces.push(OutputSurface {
                number: group.number,
                name: group.name.clone(),
                area: group.area,
                mask_of,
                emissivity: group.emissivity,
                line: group.line,
            });
        }
        let mut masks = vec![Vec::new(); surfaces.len()];
        for (k, s) in surfaces.iter().enumerate() {
            if let Some(b) = s.mask_of {
                masks[b].push(k);
            }
        }
        let frame = scene.frame();
        let mut members = vec![Vec::new(); surfaces.len()];
        let mut patch_surface = Vec::with_capacity(scene.n_patches());
        let mut patch_area = Vec::with_capacity(scene.n_patches());
        for (p, patch) in scene.patches().iter().enumerate() {
            let object = scene
                .faces()
                .get(patch.face)
                .and_then(|f| scene.objects().get(f.object))
                .and_then(|o| group_of_object.get(o.as_str()))
                .ok_or_else(|| anyhow!("{}: patch {p} of no surface", path.display()))?;
            let k = output_of_group[*object];
            if let Some(k) = k {
                members[k].push(p);
            }
            patch_surface.push(k);
            patch_area.push(frame.area_to_world(patch.area));
        }
        // Each surface keeps its area in the scene
        for (g, group) in plan.groups.iter().enumerate() {
            let Some(k) = output_of_group[g] else {
                continue;
            };
            if group.kind != GroupKind::Radiating {
                continue;
            }
            let kept: f64 = members[k].iter().map(|&p| patch_area[p]).sum();
            if !(group.area > 0.0) {
                anyhow::bail!(
                    "{}:{}: surface {} has no area: View3D's rows divide by it",
                    path.display(),
                    group.line,
                    group.number
                );
            }
            if (kept - group.area).abs() > LAYOUT_AREA_TOL * group.area {
                anyhow::bail!(
                    "{}:{}: surface {} has area {} in the file but {kept} in the scene (a \
                     coincident surface was dropped or clipped, or a piece was degenerate): its \
                     view factors would not be View3D's",
                    path.display(),
                    group.line,
                    group.number,
                    group.area
                );
            }
        }
        let mut layout = Self {
            surfaces,
            patch_surface,
            patch_area,
            members,
            masks,
            controls: plan.controls,
        };
        layout.check_controls(path)?;
        // View3D's area of a masked base is the whole base
        for k in 0..layout.surfaces.len() {
            let masked: f64 = layout.masks[k]
                .iter()
                .map(|&m| layout.surfaces[m].area)
                .sum();
            layout.surfaces[k].area += masked;
        }
        Ok(layout)
    }

    /// The file's controls (its `C` lines).
    #[must_use]
    pub fn controls(&self) -> &Vs3FileControls {
        &self.controls
    }

    /// The index among [`Self::surfaces`] of the output surface numbered `number` in the
    /// file.
    #[must_use]
    pub fn surface_index(&self, number: usize) -> Option<usize> {
        self.surfaces.iter().position(|s| s.number == number)
    }

    /// The controls checked against the surfaces: `row` and `col` name output surfaces;
    /// with `emit=1` every output surface has an emittance.
    fn check_controls(&self, path: &Path) -> Result<()> {
        let c = &self.controls;
        for (name, number) in [("row", c.row), ("col", c.col)] {
            if number != 0 && self.surface_index(number).is_none() {
                anyhow::bail!(
                    "{}:{}: {name}={number} is not an output surface (a radiating or mask \
                     surface combined with no earlier one)",
                    path.display(),
                    c.row_line.max(c.line)
                );
            }
        }
        if c.emit
            && let Some(s) = self.surfaces.iter().find(|s| s.emissivity.is_none())
        {
            anyhow::bail!(
                "{}:{}: emit=1 but surface {} gives no emittance",
                path.display(),
                s.line,
                s.number
            );
        }
        Ok(())
    }

    /// View3D's output for the file: the output surfaces' areas, their `N × N` view
    /// factors combined from the patches' ([`Self::combined_row`], `patch_row` as there),
    /// then, as the file's controls ask, adjusted as an enclosure's (`encl=1`,
    /// [`enclosure_adjust`]) and turned into Hottel's script-F factors (`emit=1`,
    /// [`script_f`], after the adjustment), and the emittances (1 for a surface whose line
    /// gives none).
    ///
    /// # Errors
    /// [`Self::combined_row`]'s; [`enclosure_adjust`]'s; [`script_f`]'s.
    pub fn view3d_matrix(
        &self,
        buffer: &mut [f64],
        mut patch_row: impl FnMut(usize, &mut [f64]) -> Result<()>,
    ) -> Result<View3dSurfaces> {
        let n = self.surfaces.len();
        let mut form_factors = vec![0.0; n * n];
        for (k, out) in form_factors.chunks_exact_mut(n.max(1)).enumerate() {
            self.combined_row(k, buffer, out, &mut patch_row)?;
        }
        let areas = self.areas();
        let enclosure = if self.controls.encl {
            Some(enclosure_adjust(&areas, &mut form_factors)?)
        } else {
            None
        };
        let emissivities: Vec<f64> = self
            .surfaces
            .iter()
            .map(|s| s.emissivity.unwrap_or(1.0))
            .collect();
        if self.controls.emit {
            form_factors = script_f(&form_factors, &emissivities)?;
        }
        Ok(View3dSurfaces {
            areas,
            form_factors,
            emissivities,
            encl: self.controls.encl,
            emit: self.controls.emit,
            enclosure,
        })
    }

    /// The output surfaces, in View3D's order.
    #[must_use]
    pub fn surfaces(&self) -> &[OutputSurface] {
        &self.surfaces
    }

    /// The output surfaces' areas, in the file's units.
    #[must_use]
    pub fn areas(&self) -> Vec<f64> {
        self.surfaces.iter().map(|s| s.area).collect()
    }

    /// Whether the output surfaces are the scene's patches, one for one, in order (no
    /// combination, subsurface, mask or obstruction): the patches' view factors are then
    /// View3D's as they are.
    #[must_use]
    pub fn is_one_to_one(&self) -> bool {
        self.members.len() == self.patch_surface.len()
            && self.members.iter().enumerate().all(|(k, m)| m == &[k])
    }

    /// The number of the scene's patches.
    #[must_use]
    pub fn n_patches(&self) -> usize {
        self.patch_surface.len()
    }

    /// Row `k` of View3D's view factors into `out` (one entry per output surface), from
    /// the rows of the patches: `patch_row(p, buffer)` fills `buffer` (one entry per patch,
    /// any further entries ignored) with row `p` of the patches' view factors.
    /// `A_K F_KL = Σ_{p∈K} Σ_{q∈L} A_p F_pq`, with `A_K` View3D's area of `K` (a masked
    /// base's includes its masks); `F(K → mask on K) = A_mask / A_K`; a mask's row is 1 at
    /// its base.
    ///
    /// # Errors
    /// `patch_row`'s; `out` or `buffer` too short.
    pub fn combined_row(
        &self,
        k: usize,
        buffer: &mut [f64],
        out: &mut [f64],
        mut patch_row: impl FnMut(usize, &mut [f64]) -> Result<()>,
    ) -> Result<()> {
        let (m, np) = (self.surfaces.len(), self.patch_surface.len());
        if out.len() < m || buffer.len() < np || k >= m {
            anyhow::bail!(
                "row {k}: {} entries for {m} surfaces, {} for {np} patches",
                out.len(),
                buffer.len()
            );
        }
        out[..m].fill(0.0);
        if let Some(b) = self.surfaces[k].mask_of {
            out[b] = 1.0;
            return Ok(());
        }
        let a_k = self.surfaces[k].area;
        for &p in &self.members[k] {
            patch_row(p, buffer)?;
            for (q, v) in buffer[..np].iter().enumerate() {
                if let Some(l) = self.patch_surface[q] {
                    out[l] += self.patch_area[p] * v;
                }
            }
        }
        for v in &mut out[..m] {
            *v /= a_k;
        }
        for &mask in &self.masks[k] {
            out[mask] = self.surfaces[mask].area / a_k;
        }
        Ok(())
    }
}

/// The union of coplanar convex `pieces` facing one way when it is a convex polygon: the
/// convex hull of their corners (counter-clockwise about their common normal), provided
/// the pieces' areas add up to the hull's within [`COMBINE_AREA_TOL`] (pieces that do not
/// overlap and fill their hull). `None` otherwise.
fn union_of_pieces(pieces: &[&[DVec3]]) -> Option<Vec<DVec3>> {
    let normals: Vec<DVec3> = pieces.iter().map(|p| vector_area(p)).collect();
    let total = normals.iter().copied().fold(DVec3::ZERO, |a, b| a + b);
    let n = total.try_normalize()?;
    let area_sum: f64 = normals.iter().map(|v| v.length()).sum();
    // Facing one way
    if normals.iter().any(|v| v.dot(n) < 0.0) {
        return None;
    }
    let corners: Vec<DVec3> = pieces.iter().flat_map(|p| p.iter().copied()).collect();
    let origin = corners[0];
    let scale = corners
        .iter()
        .map(|c| (*c - origin).length())
        .fold(0.0, f64::max);
    // Coplanar
    if corners
        .iter()
        .any(|c| (*c - origin).dot(n).abs() > 1e-9 * scale.max(f64::MIN_POSITIVE))
    {
        return None;
    }
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let mut pts: Vec<(f64, f64, DVec3)> = corners
        .iter()
        .map(|&c| ((c - origin).dot(u), (c - origin).dot(v), c))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    pts.dedup_by(|a, b| (a.0 - b.0).hypot(a.1 - b.1) <= 1e-12 * scale);
    // Andrew's monotone chain, counter-clockwise in (u, v), that is about n = u × v
    let cross = |o: &(f64, f64, DVec3), a: &(f64, f64, DVec3), b: &(f64, f64, DVec3)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut hull: Vec<(f64, f64, DVec3)> = Vec::with_capacity(pts.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &(f64, f64, DVec3)>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for p in iter {
            while hull.len() >= start + 2
                && cross(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= 1e-12 * scale * scale
            {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    if hull.len() < 3 {
        return None;
    }
    let polygon: Vec<DVec3> = hull.iter().map(|h| h.2).collect();
    let hull_area = vector_area(&polygon).length();
    ((hull_area - area_sum).abs() <= COMBINE_AREA_TOL * hull_area).then_some(polygon)
}

#[cfg(test)]
mod tests;
