//! Hierarchical radiosity (Hanrahan, Salzman and Aupperle 1991; thesis §2.1.11): an element
//! quadtree over the scene's patches, links between elements chosen by an [`Oracle`], and
//! the gather / push–pull iteration.

use alloc::vec;
use alloc::vec::Vec;

use crate::error::{ErrorKind, Result};
use crate::formfactor::exact_3d;
use crate::geom::{self, DVec3};
use crate::hierarchy::choice::OracleChoice3;
use crate::hierarchy::element::Polygon4;
use crate::hierarchy::kernel::{
    KernelSamples, MAX_PAIRS, NoOccluders, RayCounter, Surface, Visibility,
};
use crate::hierarchy::oracle::{Decision, Oracle, Pair, Side};
use crate::hierarchy::visibility::SceneVisibility;
use crate::lines::{chunk_rng, mix64 as mix};
use crate::scene::Scene3;

/// No element: the parent of a root, the children of a leaf.
pub(crate) const NONE: u32 = u32::MAX;

/// Patch `k`'s root elements: the patch itself, or when it is no [`Polygon4`] the fan of
/// triangles from its first vertex.
pub(crate) fn root_polygons(scene: &Scene3, k: usize) -> Vec<Polygon4> {
    let v = scene.patch_vertices(k);
    match Polygon4::new(v) {
        Some(poly) => vec![poly],
        None => (1..v.len().saturating_sub(1))
            .filter_map(|t| Polygon4::new(&[v[0], v[t], v[t + 1]]))
            .collect(),
    }
}

/// [`ErrorKind::TooLarge`] when `n` root elements already fill `max_elements`.
pub(crate) fn check_root_budget(n: usize, max_elements: usize) -> Result<()> {
    if n >= max_elements {
        return Err(ErrorKind::TooLarge {
            what: "root elements (max_elements)",
            max: max_elements as u64,
        }
        .into());
    }
    Ok(())
}

/// Deepest split of a scene patch (`4^24 ≈ 3·10¹⁴` elements per patch, far beyond any cap).
pub(crate) const MAX_DEPTH: u32 = 24;

/// One element: a scene patch (a root) or a quarter of its parent.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// Its shape.
    pub polygon: Polygon4,
    /// The scene patch it belongs to.
    pub patch: u32,
    /// The parent element, `NONE` for a root.
    pub parent: u32,
    /// The first of its four consecutive children, `NONE` for a leaf.
    pub children: u32,
    /// Splits from its root.
    pub depth: u32,
    /// Area `A`.
    pub area: f64,
    /// Unit front normal (the patch's).
    pub normal: DVec3,
    /// Reflectance ρ per channel (the patch's).
    pub rho: [f64; 3],
    /// Emittance `E` per channel (the patch's).
    pub emission: [f64; 3],
    /// Radiosity `B` per channel: `E + ρ H` on a leaf, the area average of its children's
    /// above.
    pub radiosity: [f64; 3],
    /// Irradiance `H` per channel: everything gathered by its links and its ancestors' on a
    /// leaf, the area average of its children's above.
    pub irradiance: [f64; 3],
    /// A hash of the element's path from its patch: seeds its pairs' random streams, so an
    /// oracle evaluation does not depend on the order elements were created in.
    key: u64,
}

impl Element {
    /// Whether it has no children.
    #[must_use]
    pub fn is_leaf(&self) -> bool {
        self.children == NONE
    }

    fn side(&self) -> Side<'_> {
        Side {
            polygon: &self.polygon,
            area: self.area,
            normal: self.normal,
            depth: self.depth,
            rho: self.rho,
            radiosity: self.radiosity,
            irradiance: self.irradiance,
        }
    }

    fn surface(&self) -> Surface<'_> {
        Surface {
            vertices: self.polygon.vertices(),
            normal: self.normal,
        }
    }
}

/// A link: the receiver gathers `F · B_source` from the source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Link {
    /// The receiving element `i`.
    pub receiver: u32,
    /// The source element `j`.
    pub source: u32,
    /// `F_ij`: the exact unoccluded polygon-to-polygon form factor times the fraction of
    /// the oracle's point pairs that see each other (1 when no patch can hide another).
    pub form_factor: f64,
}

/// Which budget stopped refinement.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Budget {
    /// [`HrOptions::max_elements`].
    Elements,
    /// [`HrOptions::max_links`].
    Links,
    /// [`HrOptions::max_rays`].
    Rays,
}

/// Budgets and stopping rules of [`Hierarchy::build`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HrOptions {
    /// Point pairs per oracle evaluation, `1..=``MAX_PAIRS` (the thesis: 10, and 4 for the
    /// robustness experiment of Figures 6.9–6.10).
    pub pairs: usize,
    /// Seed of the pairs' random streams.
    pub seed: u64,
    /// Smallest element area, relative to the scene's total area `A_T`: an element is not
    /// split when its children would be smaller. Finite, `≥ 0`.
    pub min_area: f64,
    /// Most elements (roots included). Refinement stops when a split would pass it.
    pub max_elements: usize,
    /// Most links: refinement stops once there are this many (each pair still being
    /// refined then gets its link, so a few more may be made).
    pub max_links: usize,
    /// Most rays (visibility tests): refinement stops once this many are cast.
    pub max_rays: u64,
    /// Refinement passes: the first with `B = E`, each further one with the radiosities of
    /// the previous solution (Cohen and Wallace's "BF refinement"). At least 1.
    pub passes: u32,
    /// The gather / push–pull iteration stops when no radiosity changes by more than this,
    /// relative to the largest emittance. Finite, `> 0`.
    pub tolerance: f64,
    /// Iteration cap of one solve.
    pub max_iterations: u64,
}

impl Default for HrOptions {
    /// 10 pairs, seed 1, `min_area = 10⁻⁶`, a million elements, 50 million links, no ray
    /// cap, 3 passes, tolerance `10⁻⁸`, 10 000 iterations.
    fn default() -> Self {
        Self {
            pairs: 10,
            seed: 1,
            min_area: 1e-6,
            max_elements: 1_000_000,
            max_links: 50_000_000,
            max_rays: u64::MAX,
            passes: 3,
            tolerance: 1e-8,
            max_iterations: 10_000,
        }
    }
}

impl HrOptions {
    /// Most point pairs one oracle evaluation may draw.
    pub const MAX_PAIRS: usize = MAX_PAIRS;

    fn validate(&self) -> Result<()> {
        let bad = |name, value| Err(ErrorKind::BadParameter { name, value }.into());
        if !(1..=MAX_PAIRS).contains(&self.pairs) {
            return bad("pairs (1 to 64)", self.pairs as f64);
        }
        if !(self.min_area.is_finite() && self.min_area >= 0.0) {
            return bad("min_area", self.min_area);
        }
        if self.passes == 0 {
            return bad("passes", 0.0);
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return bad("tolerance", self.tolerance);
        }
        Ok(())
    }
}

/// A solved element hierarchy: elements, links and what they cost.
#[derive(Clone, Debug)]
pub struct Hierarchy {
    elements: Vec<Element>,
    links: Vec<Link>,
    /// The root elements of each patch (one, or a fan of triangles for a patch of more
    /// than four vertices).
    roots: Vec<u32>,
    total_area: f64,
    /// The scene's frame: leaves are in its stored coordinates.
    frame: crate::scene::Frame,
    rays: u64,
    budget: Option<Budget>,
    iterations: u64,
    passes: u32,
}

/// The state of one build: the hierarchy, the options, the oracle and the visibility.
struct Builder<'a> {
    h: Hierarchy,
    opts: &'a HrOptions,
    oracle: &'a dyn Oracle,
    visibility: &'a RayCounter<'a, dyn Visibility + 'a>,
    /// Smallest area a child may have.
    min_child_area: f64,
}

impl Hierarchy {
    /// Builds and solves the hierarchy of `scene` with `oracle`: roots from the scene's
    /// patches, links for every pair of roots that face each other refined by the oracle,
    /// then [`HrOptions::passes`] rounds of solve and re-refinement, and a final solve.
    ///
    /// Visibility is tested by rays through a BVH of the scene's patches, unless no patch
    /// can hide another (`SceneVisibility::new`).
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] for options out of range; [`ErrorKind::TooLarge`] when
    /// the roots alone exceed `max_elements` or their links `max_links`; the errors of
    /// [`crate::accel::Bvh3::build`]; [`ErrorKind::NoConvergence`] when a solve reaches
    /// `max_iterations`; [`ErrorKind::NotFinite`] when a radiosity overflows.
    pub fn build(scene: &Scene3, oracle: &OracleChoice3, opts: &HrOptions) -> Result<Self> {
        Self::build_with(scene, oracle, opts)
    }

    /// [`Hierarchy::build`] with any oracle of the crate (the reference mesh's, the tests').
    pub(crate) fn build_with(
        scene: &Scene3,
        oracle: &dyn Oracle,
        opts: &HrOptions,
    ) -> Result<Self> {
        opts.validate()?;
        let occluders = SceneVisibility::new(scene)?;
        let visibility: &dyn Visibility = match &occluders {
            Some(v) => v,
            None => &NoOccluders,
        };
        let counter = RayCounter::new(visibility);
        let mut b = Builder {
            h: Self::with_roots(scene, opts)?,
            opts,
            oracle,
            visibility: &counter,
            min_child_area: 0.0,
        };
        b.min_child_area = opts.min_area * b.h.total_area;
        // Initial links: every ordered pair of roots that face each other
        let roots = b.h.roots.clone();
        let mut pairs = Vec::new();
        for &i in &roots {
            for &j in &roots {
                if i != j && b.facing(i, j) {
                    pairs.push((i, j));
                }
            }
        }
        if pairs.len() > opts.max_links {
            return Err(ErrorKind::TooLarge {
                what: "links between the scene's patches (max_links)",
                max: opts.max_links as u64,
            }
            .into());
        }
        for (i, j) in pairs {
            b.refine(i, j, None);
        }
        // Solve, re-refine with the solution, until nothing changes or the passes run out
        for pass in 1..opts.passes {
            b.h.solve(opts)?;
            b.h.passes = pass;
            let old = core::mem::take(&mut b.h.links);
            let before = (b.h.elements.len(), old.len());
            for link in &old {
                b.refine(link.receiver, link.source, Some(*link));
            }
            if (b.h.elements.len(), b.h.links.len()) == before {
                break;
            }
        }
        b.h.passes = b.h.passes.max(1);
        b.h.solve(opts)?;
        b.h.rays = counter.rays();
        Ok(b.h)
    }

    /// One root per patch of at most four vertices, a fan of triangles for larger ones;
    /// `B = E` everywhere.
    fn with_roots(scene: &Scene3, opts: &HrOptions) -> Result<Self> {
        let mut elements = Vec::new();
        let mut roots = Vec::new();
        for (k, p) in scene.patches().iter().enumerate() {
            let m = scene.patch_material(k).copied().unwrap_or_default();
            for poly in root_polygons(scene, k) {
                check_root_budget(elements.len(), opts.max_elements)?;
                roots.push(elements.len() as u32);
                elements.push(Element {
                    area: poly.area(),
                    polygon: poly,
                    patch: k as u32,
                    parent: NONE,
                    children: NONE,
                    depth: 0,
                    normal: p.normal,
                    rho: m.reflectance,
                    emission: m.emittance,
                    radiosity: m.emittance,
                    irradiance: [0.0; 3],
                    key: mix(k as u64 ^ (u64::from(roots.len() as u32) << 40)),
                });
            }
        }
        Ok(Self {
            elements,
            links: Vec::new(),
            roots,
            total_area: scene.total_area(),
            frame: scene.frame(),
            rays: 0,
            budget: None,
            iterations: 0,
            passes: 0,
        })
    }

    /// Gathers over the links and pushes–pulls until the radiosities settle (a Jacobi
    /// iteration of `B = E + ρ H`, `H_i = Σ_{links i←j} F_ij B_j` plus the ancestors'):
    ///
    /// ```text
    /// gather     G_i = Σ_{links (i, j)} F_ij B_j
    /// push       H_leaf = Σ_{a ∈ ancestors(leaf) ∪ {leaf}} G_a,   B_leaf = E + ρ H_leaf
    /// pull       B_e = Σ_children A_c B_c / A_e
    /// ```
    fn solve(&mut self, opts: &HrOptions) -> Result<()> {
        let scale = self
            .elements
            .iter()
            .flat_map(|e| e.emission)
            .fold(0.0, f64::max);
        let mut gathered = vec![[0.0; 3]; self.elements.len()];
        for it in 1..=opts.max_iterations {
            gathered.iter_mut().for_each(|g| *g = [0.0; 3]);
            for l in &self.links {
                let b = self.elements[l.source as usize].radiosity;
                let g = &mut gathered[l.receiver as usize];
                for c in 0..3 {
                    g[c] += l.form_factor * b[c];
                }
            }
            let mut change = 0.0f64;
            for k in 0..self.roots.len() {
                let root = self.roots[k];
                self.push_pull(root, [0.0; 3], &gathered, &mut change);
            }
            self.iterations += 1;
            // A NaN or infinite radiosity passes no tolerance test below: it is an error,
            // never a converged answer (it cannot arise from validated materials,
            // `Material::MAX_EMITTANCE`, but a caller may build elements otherwise)
            if !change.is_finite() {
                return Err(ErrorKind::NotFinite {
                    what: "hierarchical radiosity (gather, push-pull)",
                }
                .into());
            }
            if !(change > opts.tolerance * scale) {
                return Ok(());
            }
            if it == opts.max_iterations {
                break;
            }
        }
        Err(ErrorKind::NoConvergence {
            what: "hierarchical radiosity (gather, push-pull)",
            iterations: opts.max_iterations,
        }
        .into())
    }

    /// Push `down` (the ancestors' gathered irradiance) to element `e`'s leaves and pull
    /// their radiosities back up; returns `(B, H)` of `e`. Recursion depth ≤ [`MAX_DEPTH`].
    fn push_pull(
        &mut self,
        e: u32,
        down: [f64; 3],
        gathered: &[[f64; 3]],
        change: &mut f64,
    ) -> ([f64; 3], [f64; 3]) {
        let el = &self.elements[e as usize];
        let g = gathered[e as usize];
        let h = [down[0] + g[0], down[1] + g[1], down[2] + g[2]];
        let (b, irradiance) = if el.is_leaf() {
            let b = [0, 1, 2].map(|c| el.emission[c] + el.rho[c] * h[c]);
            (b, h)
        } else {
            let first = el.children;
            let mut b = [0.0; 3];
            let mut hh = [0.0; 3];
            let mut area = 0.0;
            for c in first..first + 4 {
                let (bc, hc) = self.push_pull(c, h, gathered, change);
                let a = self.elements[c as usize].area;
                area += a;
                for k in 0..3 {
                    b[k] += a * bc[k];
                    hh[k] += a * hc[k];
                }
            }
            (b.map(|x| x / area), hh.map(|x| x / area))
        };
        let el = &mut self.elements[e as usize];
        for (new, old) in b.iter().zip(&el.radiosity) {
            *change = change.max((new - old).abs());
        }
        el.radiosity = b;
        el.irradiance = irradiance;
        (b, irradiance)
    }

    /// All elements: roots first, children in groups of four.
    #[must_use]
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// The links.
    #[must_use]
    pub fn links(&self) -> &[Link] {
        &self.links
    }

    /// The root elements (one per patch, or a fan of triangles).
    #[must_use]
    pub fn roots(&self) -> &[u32] {
        &self.roots
    }

    /// The leaves: the final mesh.
    pub fn leaves(&self) -> impl Iterator<Item = &Element> + '_ {
        self.elements.iter().filter(|e| e.is_leaf())
    }

    /// Number of leaves.
    #[must_use]
    pub fn n_leaves(&self) -> usize {
        self.leaves().count()
    }

    /// The scene's frame ([`crate::scene::Frame`]): element vertices are stored
    /// coordinates, [`crate::scene::Frame::to_world`] gives the scene's units.
    #[must_use]
    pub fn frame(&self) -> crate::scene::Frame {
        self.frame
    }

    /// Total area of the scene `A_T` (stored units).
    #[must_use]
    pub fn total_area(&self) -> f64 {
        self.total_area
    }

    /// Rays cast (visibility tests), by the oracles' point pairs and their gradient probes.
    #[must_use]
    pub fn rays(&self) -> u64 {
        self.rays
    }

    /// The budget that stopped refinement, if one did.
    #[must_use]
    pub fn budget_hit(&self) -> Option<Budget> {
        self.budget
    }

    /// Gather / push–pull iterations over all solves.
    #[must_use]
    pub fn iterations(&self) -> u64 {
        self.iterations
    }

    /// Refinement passes run (at most [`HrOptions::passes`]; fewer when a pass changed
    /// nothing).
    #[must_use]
    pub fn passes(&self) -> u32 {
        self.passes
    }

    /// Power balance over the leaves: `(Σ A E, Σ A (1 − ρ) H)`, emitted and absorbed per
    /// channel. In a closed scene they agree up to the discretisation error.
    #[must_use]
    pub fn power_balance(&self) -> ([f64; 3], [f64; 3]) {
        let mut emitted = [0.0; 3];
        let mut absorbed = [0.0; 3];
        for e in self.leaves() {
            for c in 0..3 {
                emitted[c] += e.area * e.emission[c];
                absorbed[c] += e.area * (1.0 - e.rho[c]) * e.irradiance[c];
            }
        }
        (emitted, absorbed)
    }
}

impl Builder<'_> {
    /// Whether each element reaches strictly in front of the other's plane.
    fn facing(&self, i: u32, j: u32) -> bool {
        let (a, b) = (&self.h.elements[i as usize], &self.h.elements[j as usize]);
        let in_front = |of: &Element, other: &Element| {
            let p0 = of.polygon.vertices()[0];
            let size = geom::bounds_diagonal(of.polygon.vertices())
                + geom::bounds_diagonal(other.polygon.vertices());
            other
                .polygon
                .vertices()
                .iter()
                .any(|&v| of.normal.dot(v - p0) > 1e-9 * size)
        };
        in_front(a, b) && in_front(b, a)
    }

    /// Whether element `e` may be split now; records the budget that forbids it.
    fn can_split(&mut self, e: u32) -> bool {
        let el = &self.h.elements[e as usize];
        if !el.is_leaf() {
            return true;
        }
        if el.depth >= MAX_DEPTH || el.area * 0.25 < self.min_child_area {
            return false;
        }
        if self.h.elements.len() + 4 > self.opts.max_elements {
            self.h.budget.get_or_insert(Budget::Elements);
            return false;
        }
        true
    }

    /// Whether a budget that stops all refinement is spent.
    fn budget_spent(&mut self) -> bool {
        if self.h.links.len() >= self.opts.max_links {
            self.h.budget.get_or_insert(Budget::Links);
            return true;
        }
        if self.visibility.rays() >= self.opts.max_rays {
            self.h.budget.get_or_insert(Budget::Rays);
            return true;
        }
        false
    }

    /// The four children of `e`, created on first use; their first index.
    fn split(&mut self, e: u32) -> u32 {
        let el = &self.h.elements[e as usize];
        if !el.is_leaf() {
            return el.children;
        }
        let first = self.h.elements.len() as u32;
        let parent = el.clone();
        for (k, poly) in parent.polygon.split().into_iter().enumerate() {
            self.h.elements.push(Element {
                area: poly.area(),
                polygon: poly,
                parent: e,
                children: NONE,
                depth: parent.depth + 1,
                key: mix(parent.key ^ (k as u64 + 1)),
                ..parent.clone()
            });
        }
        self.h.elements[e as usize].children = first;
        first
    }

    /// Refines the pair (receiver `i`, source `j`) until the oracle links every sub-pair,
    /// appending the links. `existing` is the link (i, j) being re-examined, kept as it is
    /// if the oracle still accepts it.
    fn refine(&mut self, i: u32, j: u32, existing: Option<Link>) {
        let mut stack = vec![(i, j)];
        while let Some((i, j)) = stack.pop() {
            if !self.facing(i, j) {
                continue;
            }
            let (ei, ej) = (&self.h.elements[i as usize], &self.h.elements[j as usize]);
            let mut rng = chunk_rng(self.opts.seed, mix(ei.key.rotate_left(17) ^ ej.key));
            let samples = KernelSamples::draw(
                ei.surface(),
                ej.surface(),
                self.opts.pairs,
                &mut rng,
                self.visibility,
            );
            let pair = Pair {
                receiver: ei.side(),
                source: ej.side(),
                total_area: self.h.total_area,
            };
            let decision = self.oracle.decide(&pair, &samples, self.visibility);
            let decision = match decision {
                _ if decision != Decision::Link && self.budget_spent() => Decision::Link,
                Decision::RefineReceiver if !self.can_split(i) => Decision::Link,
                Decision::RefineSource if !self.can_split(j) => Decision::Link,
                d => d,
            };
            match decision {
                Decision::Link => match existing {
                    Some(l) if (l.receiver, l.source) == (i, j) => self.h.links.push(l),
                    _ => self.link(i, j, &samples),
                },
                Decision::RefineReceiver => {
                    let c = self.split(i);
                    stack.extend((c..c + 4).map(|k| (k, j)));
                }
                Decision::RefineSource => {
                    let c = self.split(j);
                    stack.extend((c..c + 4).map(|k| (i, k)));
                }
            }
        }
    }

    /// Links receiver `i` to source `j` with the exact unoccluded form factor times the
    /// visible fraction of the pairs.
    fn link(&mut self, i: u32, j: u32, samples: &KernelSamples) {
        let (ei, ej) = (&self.h.elements[i as usize], &self.h.elements[j as usize]);
        let mut f = exact_3d::polygon_to_polygon(ei.polygon.vertices(), ej.polygon.vertices());
        if self.visibility.casts_rays() {
            f *= samples.visible_fraction();
        }
        if f > 0.0 {
            self.h.links.push(Link {
                receiver: i,
                source: j,
                form_factor: f,
            });
        }
    }
}
