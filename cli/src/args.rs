//! Raw command-line arguments (clap derive; ripgrep's `lowargs.rs`). They become a validated
//! run in [`crate::config`]; each command checks the combinations that need its scene.

use std::path::PathBuf;

use clap::{Parser, Subcommand};

/// Information-theoretic complexity of scenes for light transport (Feixas 2002).
#[derive(Debug, Parser)]
#[command(name = "sceneinfo", version, about, long_about = None)]
pub struct Cli {
    /// Largest input file read, in bytes or with a suffix K, M, G, T (`64M`, `2G`): scene
    /// files, material libraries, glTF buffers, partial results, reference PLYs. Larger files
    /// are refused before reading. Default: 2 GiB, and 64 MiB for material libraries.
    #[arg(long, global = true, value_name = "SIZE", value_parser = parse_bytes)]
    pub max_input: Option<u64>,
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Write a preset scene as a .flat file (stdout, or -o FILE).
    Scene {
        /// Which preset.
        #[command(subcommand)]
        preset: ScenePreset,
    },
    /// Measure a scene: entropies, mutual information, E(MSE), Fano bound and checks.
    Measure(MeasureArgs),
    /// Write a scene's form-factor matrix (CSV or View3D-style text) and report its checks.
    Formfactors(FormFactorsArgs),
    /// Recompute the thesis' tables and print ours beside theirs.
    Reproduce(ReproduceArgs),
    /// Solve the scene's illumination (B = E + ρFB per colour channel) and measure its
    /// radiosity entropy and complexity beside the visibility ones; optionally write the lit
    /// scene as a PLY mesh.
    Radiosity(RadiosityArgs),
    /// Draw a flatland scene as SVG, patches coloured by I_i, H_i, I_i^c or I_i^c − I_i, and
    /// optionally the mutual information matrix I_ij as a heat map.
    Draw(DrawArgs),
    /// Merge partial results (`measure … --partial`) into the result of one run, bit for bit.
    Merge(MergeArgs),
    /// Benchmark whole jobs: lines/s against a naive baseline, 1 vs N threads, peak memory,
    /// exact form-factor times and the cost per line against the number of patches; with
    /// --split, what casting costs alone against casting and tallying.
    Bench(BenchArgs),
    /// Refine a scene's mesh with an oracle: flatland (.flat) by halving patches (de, power,
    /// regular; thesis §6.5.2), 3D (.obj) by hierarchical radiosity (power, ks, ks-av, mi,
    /// mi-increase; §6.4). Prints the mesh's measures; --svg/--ply/--png draw it.
    Refine(RefineArgs),
    /// The viewpoint channel of a 3D scene (Feixas, Sbert, González 2009): viewpoint entropy
    /// and mutual information from viewpoints on a sphere around it, the best views, a
    /// greedy selection of representative views and mesh saliency.
    Viewpoints(ViewpointsArgs),
    /// Entropy and mutual-information fields at interior points of a flatland scene
    /// (thesis §7.3): at a point (--at), over a grid (--grid, --png) and along a camera path
    /// (--path: its animation complexity ∫ I(x) ds).
    Field(crate::commands::field::FieldArgs),
    /// Render a 3D scene's radiosity solution through a pinhole camera (ray-cast primary
    /// visibility), with pixel samples spent uniformly or where an entropy or
    /// mutual-information contrast asks for them (thesis §7.3; docs/supersampling.md);
    /// --rmse compares the three at equal total samples against a converged reference.
    Render(RenderArgs),
    /// Simplify a mesh by merging adjacent patches with the least mutual information lost
    /// (thesis §7.3), to --to N patches or a --max-loss budget in bits; compares the result
    /// with regular and power-based coarsening at the same patch count (I_S kept, radiosity
    /// RMSE against the fine solution).
    Simplify(SimplifyArgs),
}

/// Arguments of `render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// The 3D scene file (OBJ with its .mtl, glTF/GLB, PLY); the Cornell box of
    /// tests/data/corpus/obj/cornell_box needs --emit-from-ka.
    pub file: PathBuf,
    /// Where the samples go: uniformly (none), or adaptively by the entropy contrast
    /// (entropy, ref. 68) or the mutual-information contrast (mi, ref. 69), at the same
    /// total number of samples.
    #[arg(long, value_enum, default_value_t = AdaptiveArg::Entropy)]
    pub adaptive: AdaptiveArg,
    /// Samples per pixel on average (the budget is spp × pixels; adaptive renders start at
    /// min(spp, 4) per pixel and give one pixel at most 16 spp, capped at 4096).
    #[arg(long, value_name = "N", default_value_t = 16,
          value_parser = clap::value_parser!(u32).range(1..=65_536))]
    pub spp: u32,
    /// The oracle's threshold, in [0, 1]: a pixel whose contrast exceeds it may take more
    /// samples, highest contrast first, until the budget is spent. Default: each
    /// contrast's own (the papers' could not be read; ours are 0.02 for entropy and for
    /// mi, each with its reason: docs/supersampling.md). 0 makes the budget the only
    /// stopping rule, which wins on dim scenes.
    #[arg(long, value_name = "T")]
    pub threshold: Option<f64>,
    /// Adaptive: judge a pixel by its own samples only, not also by its samples with its
    /// four neighbours' (the default compares neighbours: it catches edges that fall
    /// between a pixel's first samples).
    #[arg(long)]
    pub own_samples_only: bool,
    /// Write the rendered image as PNG (sRGB).
    #[arg(long, value_name = "OUT.png")]
    pub png: Option<PathBuf>,
    /// Write where the samples went as PNG: samples per pixel on a log scale (viridis,
    /// dark = fewest).
    #[arg(long, value_name = "OUT.png")]
    pub samples_png: Option<PathBuf>,
    /// Also render uniform, entropy and mi at the same total samples over --seeds seeds,
    /// and print each one's RMSE against a reference of --reference-spp samples per pixel.
    #[arg(long)]
    pub rmse: bool,
    /// With --rmse: how many render seeds (1, 2, …) to repeat each comparison over.
    #[arg(long, value_name = "K", default_value_t = 5,
          value_parser = clap::value_parser!(u64).range(1..=1000))]
    pub seeds: u64,
    /// With --rmse: samples per pixel of the reference (uniform, its own seed).
    #[arg(long, value_name = "N", default_value_t = 1024,
          value_parser = clap::value_parser!(u32).range(1..=65_536))]
    pub reference_spp: u32,
    /// Seed of the image's sample positions (--rmse uses seeds 1 to --seeds instead).
    #[arg(long, default_value_t = 1)]
    pub render_seed: u64,
    /// Cut every face into K × K patches (triangles into K²) before solving the radiosity.
    #[arg(long, value_name = "K", default_value_t = 8,
          value_parser = clap::value_parser!(u32).range(1..=64))]
    pub grid: u32,
    /// A material without `Ke` emits its ambient colour `Ka` (old-style lamps).
    #[arg(long)]
    pub emit_from_ka: bool,
    /// The camera's eye, `x,y,z` (default: in front of the scene, on its −z side, far
    /// enough to frame it).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_point)]
    pub eye: Option<[f64; 3]>,
    /// The point the camera looks at, `x,y,z` (default: the scene's centre).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_point)]
    pub look: Option<[f64; 3]>,
    /// Vertical field of view in degrees.
    #[arg(long, value_name = "DEG", default_value = "40", value_parser = parse_fov)]
    pub fov: f64,
    /// Image size in pixels, `WxH`, each 16 to 8192.
    #[arg(long, value_name = "WxH", default_value = "256x256", value_parser = parse_picture_size)]
    pub size: (u32, u32),
    /// How the form factors of the radiosity solve are computed (occluded scenes need
    /// --lines).
    #[command(flatten)]
    pub sampling: SamplingArgs,
}

/// `--adaptive` of `render`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum AdaptiveArg {
    /// Uniform: spp samples in every pixel.
    None,
    /// The entropy contrast (Rigau, Feixas & Sbert, ref. 68).
    Entropy,
    /// The mutual-information contrast (ref. 69, as read in docs/supersampling.md).
    Mi,
}

/// Arguments of `simplify`.
#[derive(Debug, clap::Args)]
#[command(group(clap::ArgGroup::new("stop").required(true).multiple(true).args(["to", "max_loss"])))]
pub struct SimplifyArgs {
    /// The scene: .flat (exact form factors), or 3D (OBJ, glTF/GLB, PLY) when no polygon can
    /// hide another (exact unoccluded form factors).
    pub file: PathBuf,
    /// Merge down to N patches (at least 1).
    #[arg(long, value_name = "N", value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
    pub to: Option<usize>,
    /// Stop before the merge that would take the information lost past BITS (≥ 0).
    #[arg(long, value_name = "BITS", value_parser = parse_bits)]
    pub max_loss: Option<f64>,
    /// 3D only: cut each face into a K × K grid first.
    #[arg(long, value_name = "K", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..=64))]
    pub grid: u32,
    /// Print every merge (step, merged patches, loss, I_S) in the table.
    #[arg(long)]
    pub steps: bool,
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Write the simplified flatland scene (.flat).
    #[arg(long, short = 'o', value_name = "OUT.flat")]
    pub output: Option<PathBuf>,
}

/// A loss budget in bits: finite and `≥ 0`.
fn parse_bits(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("'{s}' is not a number of bits ≥ 0")),
    }
}

/// Arguments of `viewpoints`.
#[derive(Debug, clap::Args)]
pub struct ViewpointsArgs {
    /// The 3D scene file (OBJ, glTF/GLB, PLY).
    pub file: PathBuf,
    /// Number of viewpoints on the icosphere: 12, 42, 162, 642, 2562 or 10242.
    #[arg(long, default_value_t = sceneinfo::viewpoint::ViewpointOptions::DEFAULT_VIEWS)]
    pub views: usize,
    /// Side of each view's image in pixels (the raster error of a polygon's projected area
    /// halves with each doubling).
    #[arg(long, value_name = "N", default_value_t = sceneinfo::viewpoint::ViewpointOptions::DEFAULT_RESOLUTION)]
    pub resolution: u32,
    /// Distance of the viewpoints from the scene's centre, in bounding-sphere radii (> 1).
    #[arg(long, value_name = "R", default_value_t = sceneinfo::viewpoint::ViewpointOptions::DEFAULT_DISTANCE)]
    pub distance: f64,
    /// How many best views to list (least VMI first) and the most views the greedy
    /// selection picks.
    #[arg(long, value_name = "K", default_value_t = 5)]
    pub best: usize,
    /// Stop the greedy selection once it holds this fraction of I(V;O) (0 to 1), or at
    /// --best views.
    #[arg(long, value_name = "F", default_value_t = 1.0)]
    pub fraction: f64,
    /// p(v): `uniform` or weighted by the projected area each viewpoint sees (`area`).
    #[arg(long, value_enum, default_value_t = ViewWeightingArg::Uniform)]
    pub weighting: ViewWeightingArg,
    /// Print JSON instead of tables (the same bytes as the wasm `viewpoints`).
    #[arg(long)]
    pub json: bool,
    /// Write the mesh coloured by saliency (viridis, per polygon) as an ASCII PLY.
    #[arg(long, value_name = "OUT.ply")]
    pub ply: Option<PathBuf>,
    /// Write the viewpoint sphere coloured by `--sphere-color` (viridis per viewpoint
    /// vertex) as a PLY, placed around the scene at 1.5 bounding radii.
    #[arg(long, value_name = "OUT.ply")]
    pub sphere_ply: Option<PathBuf>,
    /// What colours the --sphere-ply viewpoints.
    #[arg(long, value_enum, default_value_t = SphereColour::Vmi)]
    pub sphere_color: SphereColour,
    /// Write pictures of the mesh coloured by saliency seen from the --best views (PNG):
    /// the best to OUT.png, the k-th best to OUT-k.png.
    #[arg(long, value_name = "OUT.png")]
    pub png: Option<PathBuf>,
    /// Side of the --png picture in pixels.
    #[arg(long, value_name = "PX", default_value_t = 512,
          value_parser = clap::value_parser!(u32).range(16..=sceneinfo::viewpoint::IdRaster::MAX_RESOLUTION as i64))]
    pub png_size: u32,
    /// Worker threads (default: all cores). Never changes the result.
    #[arg(long)]
    pub threads: Option<usize>,
}

/// `--sphere-color` of `viewpoints`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SphereColour {
    /// Viewpoint mutual information I(v;O) (the best view has the least).
    Vmi,
    /// Viewpoint entropy H(v), the background a term.
    Ve,
    /// Mean Jensen–Shannon divergence to the neighbouring viewpoints.
    Instability,
    /// Viewpoint saliency Σ_o p(v|o) S(o).
    Saliency,
}

/// `--weighting` of `viewpoints`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ViewWeightingArg {
    /// p(v) = 1/N_v.
    Uniform,
    /// p(v) proportional to the solid angle of the scene seen from v.
    Area,
}

/// Arguments of `bench`.
#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Longer measurements (3 s each instead of 0.25 s) and the curve up to 10^6 patches.
    #[arg(long)]
    pub full: bool,
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Threads of the multi-threaded measurement (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Run only the parts whose name contains this text (a scene's name, `exact`, `curve`).
    #[arg(long)]
    pub only: Option<String>,
    /// Repetitions of every measurement (the configurations of a scene interleaved: naive,
    /// global 1t, global Nt, bundle 1t, bundle Nt, then again); rates are printed as
    /// median [min-max].
    #[arg(long, default_value_t = 3)]
    pub reps: usize,
    /// Also run the memory check: this many global lines on the 99,846-patch cube (sparse
    /// counts) on all threads, printing the time and the peak resident memory.
    #[arg(long, value_name = "N", value_parser = parse_count)]
    pub memory_lines: Option<u64>,
    /// Run only the cast/tally split: on 3D scenes, global lines and bundles on 1 and
    /// --threads threads, each job once with its full tally and once cast alone — the same
    /// lines, BVH queries or bundle rasters, each line's hits found and sorted as the tally
    /// gets them, then only counted (with a checksum of the patches) — configurations
    /// interleaved, marginal rates median [min-max] and the tally's share of a line's time;
    /// the hits of both must agree (column `same`). On the --scene files, else on the
    /// Embree harness' three scenes (cube 5400, Cornell grid 10, room of 512 cubes) that
    /// --only selects.
    #[arg(long)]
    pub split: bool,
    /// With --split: a 3D scene file to run it on (repeatable).
    #[arg(long, value_name = "FILE", requires = "split")]
    pub scene: Vec<PathBuf>,
    /// With --split: the job length L (jobs of L and 2L lines, e.g. 2e6); default grown
    /// until a full job takes half the measurement time.
    #[arg(long, value_name = "N", value_parser = parse_count, requires = "split")]
    pub lines: Option<u64>,
    /// With --split: only this method (default both).
    #[arg(long, value_enum, requires = "split")]
    pub method: Option<SplitMethod>,
}

/// The line methods `bench --split` compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SplitMethod {
    /// Independent global lines (BVH queries).
    Global,
    /// Bundles of parallel lines (rasters).
    Bundle,
}

impl SplitMethod {
    /// The core's sampling method.
    #[must_use]
    pub fn line_method(self) -> sceneinfo::tally::LineMethod {
        match self {
            SplitMethod::Global => sceneinfo::tally::LineMethod::Global,
            SplitMethod::Bundle => sceneinfo::tally::LineMethod::Bundle,
        }
    }
}

/// Arguments of `merge`.
#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// Partial-result files of one job (any order).
    #[arg(required = true, value_name = "PART.sip")]
    pub files: Vec<PathBuf>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also write the form-factor matrix as CSV.
    #[arg(long, value_name = "F.csv")]
    pub matrix: Option<PathBuf>,
    /// Write the merged partial result instead of measuring (the inputs need not cover the
    /// whole job; neighbouring chunk or row ranges only): for merging in stages.
    #[arg(long, value_name = "OUT.sip")]
    pub partial: Option<PathBuf>,
    /// Also write the form factors as `formfactors --out` does (`.csv`, `.txt`, `.ijv` or
    /// View3D's `.vf3`).
    #[arg(
        long,
        value_name = "F.ijv|F.vf3|F.csv|F.txt",
        conflicts_with = "partial"
    )]
    pub out: Option<PathBuf>,
    /// The View3D `.vs3` file the rows were computed from: `--out F.vf3` then holds its
    /// output surfaces as `formfactors FILE.vs3 --out F.vf3` writes them (combined
    /// surfaces joined, masks, obstruction-only surfaces left out, the file's `encl` and
    /// `emit`), not one row per patch.
    #[arg(long, value_name = "FILE.vs3", requires = "out")]
    pub scene: Option<PathBuf>,
}

/// Preset scenes.
#[derive(Clone, Debug, Subcommand)]
pub enum ScenePreset {
    /// A regular polygon inscribed in the unit circle, facing inwards.
    Polygon {
        /// Number of sides (≥ 3).
        #[arg(long)]
        sides: usize,
        /// Patches per side.
        #[arg(long, default_value_t = 10)]
        per_side: u64,
        /// Output file (default: stdout).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// A width × height rectangle, facing inwards.
    Rect {
        /// Width.
        #[arg(long, default_value_t = 1.0)]
        width: f64,
        /// Height.
        #[arg(long, default_value_t = 1.0)]
        height: f64,
        /// Patches per side.
        #[arg(long, default_value_t = 10)]
        per_side: u64,
        /// Output file (default: stdout).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// A scene of the thesis' flatland catalogue by name (`sceneinfo scene list` lists them).
    Catalogue {
        /// The scene's name, e.g. koch-2, l-room-3, 16-squares-4, 64-squares-a.
        name: String,
        /// Patches per side of the enclosure (other sides proportionally).
        #[arg(long, default_value_t = 10)]
        per_side: u64,
        /// Output file (default: stdout).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// The empty unit cube, each face cut into K × K patches (writes OBJ + MTL, or View3D's
    /// `.vs3` when the output's extension says so).
    Cube {
        /// Patches per face edge.
        #[arg(long, default_value_t = 10)]
        grid: u32,
        /// Output `.obj` file (its `.mtl` is written beside it) or `.vs3` (View3D's input).
        #[arg(short, long)]
        output: PathBuf,
        /// View3D's tolerance `eps` written into a `.vs3` file's controls.
        #[arg(long, default_value_t = 1e-4)]
        eps: f64,
    },
    /// A 3D preset by name: tetrahedron, octahedron, dodecahedron, icosahedron, cornell,
    /// cornell-lifted, … (`sceneinfo scene list` lists them; writes OBJ + MTL, or View3D's
    /// `.vs3` when the output's extension says so).
    Solid {
        /// The preset's name.
        name: String,
        /// Subdivision of the preset's faces where it has one (K × K per quad).
        #[arg(long, default_value_t = 1)]
        grid: u32,
        /// Output `.obj` file (its `.mtl` is written beside it) or `.vs3` (View3D's input).
        #[arg(short, long)]
        output: PathBuf,
        /// View3D's tolerance `eps` written into a `.vs3` file's controls.
        #[arg(long, default_value_t = 1e-4)]
        eps: f64,
    },
    /// Any scene file sceneinfo reads (OBJ, glTF, PLY, `.vs3`, `.flat`) written as OBJ + MTL,
    /// View3D's `.vs3` (3D) or `.flat` (flatland), by the output's extension: one patch of
    /// the scene per OBJ face or View3D surface, in order, so results compare row by row.
    /// A `.vs3` written as `.vs3` keeps its records (subsurfaces, masks, null and
    /// obstruction-only surfaces, combinations, emittances, controls) in `F 3` form.
    Convert {
        /// The scene file to read.
        file: PathBuf,
        /// Output `.obj`, `.vs3` or `.flat` file.
        #[arg(short, long)]
        output: PathBuf,
        /// View3D's tolerance `eps` written into a `.vs3` file's controls (View3D's default
        /// 1e-4; it warns below 1e-6; a `.vs3` input's own `eps` when not given).
        #[arg(long)]
        eps: Option<f64>,
        /// Write `encl=1` into a `.vs3` file's controls: View3D adjusts every row to sum to 1.
        #[arg(long)]
        enclosure: bool,
    },
    /// List the names of the flatland catalogue and the 3D presets.
    List,
}

/// Arguments of `measure`.
#[derive(Debug, clap::Args)]
pub struct MeasureArgs {
    /// The scene file: `.flat` (flatland) or `.obj` (3D, with its `.mtl`).
    pub file: PathBuf,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also write the form-factor matrix as CSV (one row per state; the background state,
    /// if any, last).
    #[arg(long, value_name = "F.csv")]
    pub matrix: Option<PathBuf>,
    /// How the form factors are computed.
    #[command(flatten)]
    pub sampling: SamplingArgs,
    /// Compute only the seeded chunks A..B (half-open; chunk k holds lines k·65536 ..
    /// (k+1)·65536 of the job) of the `--lines` job, into the `--partial` file.
    #[arg(long, value_name = "A..B", value_parser = parse_chunks, requires = "partial")]
    pub chunks: Option<std::ops::Range<u64>>,
    /// Write the tally of the job (or of its `--chunks`) to this partial-result file
    /// instead of measuring; `sceneinfo merge` combines such files.
    #[arg(long, value_name = "OUT.sip", requires = "lines")]
    pub partial: Option<PathBuf>,
    /// Instead of the usual report, the long-range mutual information I(X_0;X_n) of the
    /// scene's chain for n = 1..N bounces (exact from F^n; see --walks), its per-patch split and its
    /// links with I_S and the excess entropy (thesis §7.3, Proposition 1).
    #[arg(long, value_name = "N", conflicts_with = "partial",
          value_parser = clap::value_parser!(u32).range(1..=sceneinfo::channel::LongRange::MAX_BOUNCES as i64))]
    pub bounces: Option<u32>,
    /// With --bounces: also estimate I(X_0;X_n) by about W random walks (at least 32 from
    /// each patch; seeded by --seed; the last step averaged over the known rows), with its
    /// standard error and the bias removed, beside the exact curve; alone when F^n is too
    /// large to compute densely.
    #[arg(long, value_name = "W", requires = "bounces",
          value_parser = clap::value_parser!(u64).range(1..))]
    pub walks: Option<u64>,
    /// With --walks: compute the walks' curve only, not the exact one from F^n (what a
    /// scene too large for dense powers gets anyway).
    #[arg(long, requires = "walks")]
    pub walks_only: bool,
}

/// Parses a half-open chunk range `A..B` with `A < B`.
pub fn parse_chunks(s: &str) -> Result<std::ops::Range<u64>, String> {
    let bad = || format!("'{s}' is not a chunk range A..B with A < B (e.g. 0..16)");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    let (a, b) = (
        a.trim().parse::<u64>().map_err(|_| bad())?,
        b.trim().parse::<u64>().map_err(|_| bad())?,
    );
    if a < b { Ok(a..b) } else { Err(bad()) }
}

/// Parses a half-open row range `A..B` with `A < B`.
pub fn parse_rows(s: &str) -> Result<std::ops::Range<usize>, String> {
    let bad = || format!("'{s}' is not a row range A..B with A < B (e.g. 0..100)");
    let (a, b) = s.split_once("..").ok_or_else(bad)?;
    let (a, b) = (
        a.trim().parse::<usize>().map_err(|_| bad())?,
        b.trim().parse::<usize>().map_err(|_| bad())?,
    );
    if a < b { Ok(a..b) } else { Err(bad()) }
}

/// Exact form factors, or Monte Carlo lines.
#[derive(Debug, clap::Args)]
pub struct SamplingArgs {
    /// Estimate the form factors and the continuous mutual information I_S^c by Monte Carlo
    /// with this many lines (e.g. 10000000 or 1e7), or `auto`: start at 2^17 = 131072 lines
    /// and double until every patch has received a line or --max-lines is reached (the lines
    /// already cast are kept, so the result is that of one run of the final count, which is
    /// reported). Without it, form factors are exact. When some patch receives no line, its
    /// row of F is unknown: `measure` still reports I_S^c and its standard error, the
    /// discrete measures undefined (null in JSON), with a warning that says how many patches
    /// were missed and about how many lines would reach them all; `formfactors` and
    /// `radiosity`, which need every row, refuse with the same numbers.
    #[arg(long, value_name = "N|auto", value_parser = parse_lines)]
    pub lines: Option<LinesArg>,
    /// With --lines auto: the most lines it may double to (default 2^30 = 1073741824).
    #[arg(long, value_name = "N", value_parser = parse_count)]
    pub max_lines: Option<u64>,
    /// Which lines: uniform global lines (2.37), cosine local lines (2.36), or global lines
    /// cast as bundles of parallel lines: in flatland 256 lines a bundle
    /// in sheaves of 256 directions, each sheaf (a chunk of 65,536 lines) one observation of
    /// the standard error; in 3D square lattices of 1024 to 4096 lines (a quarter of the
    /// polygons outside gridded faces) in sheaves of up to 16 directions, and the lines
    /// cast differ from --lines by a few.
    #[arg(long, value_enum, default_value_t = Method::Global)]
    pub method: Method,
    /// Seed of the line streams: the result depends on (seed, lines) only.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: all cores). Never changes the result.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Refuse the job, before it starts, if its large tables would need more memory than
    /// this (bytes, or with a suffix K, M, G, T = 2^10, 2^20, 2^30, 2^40: `512M`, `1.5G`).
    #[arg(long, value_name = "SIZE", value_parser = parse_bytes)]
    pub max_memory: Option<u64>,
    /// Exact form factors of a 3D scene where some patch may hide another: the target
    /// absolute error of each F_ij (default 1e-6, from 1e-10 to 1). The visible part of a
    /// patch from each point is exact; the integral over the source is adaptive, and its
    /// error estimate (a-posteriori, not a proof) is reported. Pairs no patch can come
    /// between stay exact. Not with --lines.
    #[arg(long, value_name = "TOL")]
    pub tol: Option<f64>,
}

/// Parses a memory size: bytes (`1000000`, `1e9`) or a number with a binary suffix `K`,
/// `M`, `G`, `T` (optionally followed by `iB` or `B`, any case): `512M`, `1.5GiB`.
pub fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let lower = t.to_ascii_lowercase();
    let stripped = lower
        .strip_suffix("ib")
        .or_else(|| lower.strip_suffix('b'))
        .unwrap_or(&lower);
    let (number, scale) = match stripped.chars().last() {
        Some('k') => (&stripped[..stripped.len() - 1], 1u64 << 10),
        Some('m') => (&stripped[..stripped.len() - 1], 1 << 20),
        Some('g') => (&stripped[..stripped.len() - 1], 1 << 30),
        Some('t') => (&stripped[..stripped.len() - 1], 1 << 40),
        _ => (stripped, 1),
    };
    match number.parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 && v * (scale as f64) < u64::MAX as f64 => {
            Ok((v * scale as f64) as u64)
        }
        _ => Err(format!(
            "'{s}' is not a memory size (bytes, or a number with K, M, G or T)"
        )),
    }
}

/// Arguments of `formfactors`.
#[derive(Debug, clap::Args)]
pub struct FormFactorsArgs {
    /// The scene file: `.flat`, `.obj`, glTF, `.ply` or View3D's `.vs3`.
    pub file: PathBuf,
    /// Output: `.csv` (one row of F per line), `.txt` (number of states, their relative
    /// sizes, then the rows of F), `.ijv` (sparse: `i,j,F_ij,error` per non-zero entry
    /// and per zero entry with a non-zero error estimate, rows in order) or `.vf3` (View3D's output file: header, areas, rows, emissivities;
    /// 3D scenes: one row per patch, or for a `.vs3` file View3D's own output surfaces).
    /// Required unless `--partial`, or a `.vs3` file whose `C` line sets `row=n`: that
    /// row alone is then computed and printed (View3D writes no matrix either).
    #[arg(long, value_name = "F.csv|F.txt|F.ijv|F.vf3")]
    pub out: Option<PathBuf>,
    /// Exact 3D form factors: compute only rows A..B (half-open, of 0..patches) into the
    /// `--partial` file; `sceneinfo merge` joins the ranges into the whole job's form
    /// factors, bit for bit.
    #[arg(long, value_name = "A..B", value_parser = parse_rows, requires = "partial")]
    pub rows: Option<std::ops::Range<usize>>,
    /// Write the exact rows (all, or `--rows`) to this partial-result file instead of the
    /// matrix (exact 3D form factors only).
    #[arg(long, value_name = "OUT.sir", conflicts_with = "out")]
    pub partial: Option<PathBuf>,
    /// How the form factors are computed.
    #[command(flatten)]
    pub sampling: SamplingArgs,
}

/// Line sampling methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// Uniformly distributed global lines.
    Global,
    /// Cosine-distributed local lines.
    Local,
    /// Global lines cast in bundles of parallel lines.
    Bundle,
}

impl Method {
    /// The core's sampling method.
    #[must_use]
    pub fn line_method(self) -> sceneinfo::tally::LineMethod {
        use sceneinfo::tally::LineMethod;
        match self {
            Method::Global => LineMethod::Global,
            Method::Local => LineMethod::Local,
            Method::Bundle => LineMethod::Bundle,
        }
    }
}

/// A line budget given on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinesArg {
    /// Exactly this many lines.
    Count(u64),
    /// `auto`: doubled until every patch has received a line
    /// ([`crate::lines::LineBudget::UntilSampled`]).
    Auto,
}

/// Parses `--lines`: a count ([`parse_count`]) or `auto`.
pub fn parse_lines(s: &str) -> Result<LinesArg, String> {
    if s.trim().eq_ignore_ascii_case("auto") {
        return Ok(LinesArg::Auto);
    }
    parse_count(s)
        .map(LinesArg::Count)
        .map_err(|e| format!("{e} (or auto)"))
}

/// Parses a count written as an integer (`10000000`) or in scientific notation (`1e7`).
///
/// Whole numbers beyond `u64` (`18446744073709551616`, `1e30`) saturate to `u64::MAX`: far
/// above `sceneinfo::lines::MAX_LINES`, so the command refuses them with the scene file's
/// name, like every other line budget it cannot run (`FILE: line budget exceeds the cap`).
pub fn parse_count(s: &str) -> Result<u64, String> {
    if let Ok(v) = s.parse::<u64>() {
        return Ok(v);
    }
    if !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit()) {
        return Ok(u64::MAX);
    }
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 && v.fract() == 0.0 => {
            // Saturating: 2^64 and above become u64::MAX
            Ok(v as u64)
        }
        _ => Err(format!("'{s}' is not a whole number of lines")),
    }
}

/// Arguments of `reproduce`.
#[derive(Debug, clap::Args)]
pub struct ReproduceArgs {
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Global lines per scene for the Monte Carlo tables (e.g. 1e6).
    #[arg(long, value_name = "N", value_parser = parse_count, default_value = "400000")]
    pub lines: u64,
    /// Seed of the line streams.
    #[arg(long, default_value_t = 2002)]
    pub seed: u64,
    /// Worker threads (default: all cores). Never changes the result.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Only the exact tables of chapter 3 (a second or so).
    #[arg(long)]
    pub chapter_3_only: bool,
    /// Only chapter 5, the radiosity channel (Tables 5.1–5.5; under a minute).
    #[arg(long, conflicts_with = "chapter_3_only")]
    pub chapter_5_only: bool,
    /// Only chapter 6 by the thesis' protocol: hierarchical Monte Carlo radiosity at the
    /// captions' rays and patch counts — Figs. 6.6 and 6.9 on the Cornell box (5 seeds), Figs.
    /// 6.7/6.8, 6.10, 6.11 on the cube room (scaled, below) — with the verdict per figure
    /// (release: ~10 minutes for the Cornell box, a few more for the room at 0.1;
    /// docs/chapter6-protocol.md).
    #[arg(long, conflicts_with_all = ["chapter_3_only", "chapter_5_only"])]
    pub chapter_6_mc: bool,
    /// With --chapter-6-mc: which scenes — the Cornell box (Figs. 6.6, 6.9), the cube room
    /// (Figs. 6.7/6.8, 6.10, 6.11), or both.
    #[arg(long, value_enum, default_value_t = McScenes::Both, requires = "chapter_6_mc")]
    pub mc_scenes: McScenes,
    /// With --chapter-6-mc: the cube room's rays and patch counts as a fraction of the
    /// thesis' (402,650 rays at ~13,900 patches; 2,684,260 at 18,338). 1 is the full size;
    /// in release 0.1 took 1.6 minutes of CPU, 0.3 about 4 (3 seeds; docs/chapter6-protocol.md).
    #[arg(
        long,
        value_name = "F",
        default_value_t = 0.1,
        requires = "chapter_6_mc"
    )]
    pub cube_room_scale: f64,
    /// With --chapter-6-mc: seeds per cube-room configuration.
    #[arg(long, value_name = "N", default_value_t = 3, requires = "chapter_6_mc")]
    pub cube_room_seeds: u64,
    /// With --chapter-6-mc: write the figures' pictures (each oracle's mesh and its
    /// Gouraud-shaded picture side by side, first seed) as PNG files into this directory.
    #[arg(long, value_name = "DIR", requires = "chapter_6_mc")]
    pub figures: Option<PathBuf>,
    /// Also the slow 3D rows: the 5,400-patch cube exactly and the cubes with the thesis'
    /// 10⁷ lines (a few minutes).
    #[arg(long)]
    pub full: bool,
}

/// The scenes of `reproduce --chapter-6-mc`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum McScenes {
    /// The Cornell box (Figs. 6.6, 6.9).
    Cornell,
    /// The cube room (Figs. 6.7/6.8, 6.10, 6.11).
    Room,
    /// Both.
    Both,
}

/// Arguments of `radiosity`.
#[derive(Debug, clap::Args)]
pub struct RadiosityArgs {
    /// The scene file: `.flat` (flatland) or `.obj` (3D, with its `.mtl`: `Kd` is the
    /// reflectance, above 0.99 clamped with a warning, `Ke` the emittance). When nothing
    /// emits, every radiosity is 0: a note on stderr says so, and the run goes on.
    pub file: PathBuf,
    /// For a .obj scene: a material without `Ke` emits its ambient colour `Ka` (old-style
    /// lamps, written as `Ka 20 20 20`). Off by default, as most exporters write `Ka` for
    /// every material (often `Ka 1 1 1`), which would then all glow.
    #[arg(long)]
    pub emit_from_ka: bool,
    /// The iterative solver of (2.6).
    #[arg(long, value_enum, default_value_t = SolverArg::GaussSeidel)]
    pub solver: SolverArg,
    /// Largest accepted max-norm of the residual E + ρFB − B relative to max E.
    #[arg(long, default_value_t = 1e-10)]
    pub tolerance: f64,
    /// Iteration cap (sweeps for Jacobi and Gauss–Seidel, shots for Southwell); reaching it
    /// is an error.
    #[arg(long, default_value_t = sceneinfo::radiosity::SolveOptions::DEFAULT_MAX_ITERATIONS)]
    pub max_iterations: u64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Write a .obj scene lit as an ASCII PLY mesh: shared vertices with Gouraud colours
    /// (area-weighted average of the patches around the vertex that share its plane and
    /// material) and per-face
    /// colours, both tone-mapped (linear exposure with white at the brightest non-emitting
    /// patch, then the sRGB curve).
    #[arg(long, value_name = "OUT.ply")]
    pub ply: Option<PathBuf>,
    /// How the form factors are computed; with --lines, also the continuous radiosity
    /// mutual information I_S^c (5.20) per colour channel.
    #[command(flatten)]
    pub sampling: SamplingArgs,
}

/// The radiosity solvers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum SolverArg {
    /// Jacobi relaxation (gathering).
    Jacobi,
    /// Gauss–Seidel relaxation (gathering).
    GaussSeidel,
    /// Southwell relaxation, progressive refinement (shooting).
    Southwell,
}

/// Arguments of `draw`.
#[derive(Debug, clap::Args)]
pub struct DrawArgs {
    /// The scene file: .flat (drawn as SVG with --svg) or .obj (written as a coloured PLY
    /// mesh with --ply).
    pub file: PathBuf,
    /// Where to write the picture of a .flat scene (required for .flat).
    #[arg(long, value_name = "OUT.svg")]
    pub svg: Option<PathBuf>,
    /// Where to write a .obj scene as an ASCII PLY mesh (required for .obj): one polygon per
    /// patch with its own vertices and a flat `red green blue` colour (viridis; cool–warm
    /// about 0 for `delta`), the quantity, its range and its sources in `comment` lines.
    #[arg(long, value_name = "OUT.ply")]
    pub ply: Option<PathBuf>,
    /// With --ply: colour I_i, I_i^c or I_i^c − I_i divided by the patch's relative area
    /// a_i = A_i / A_T, a density comparable across patch sizes (I_i and I_i^c are a patch's
    /// share of I_S and I_S^c, so they shrink with the patch). Not for `h` (H_i is a row
    /// entropy, not a share).
    #[arg(long)]
    pub per_area: bool,
    /// What colours the patches: I_i (6.8), I_i^c (6.37, Monte Carlo), H_i (3.2), or the
    /// discretisation error I_i^c − I_i (§6.5.2, Monte Carlo; its I_i from exact form factors
    /// up to 2000 patches, from the run's Monte Carlo form factors above).
    #[arg(long, value_enum, default_value_t = Colour::I)]
    pub color: Colour,
    /// Global lines for `ic` and `delta` (default 1e6). With `i` or `h`, estimate the form
    /// factors with this many lines instead of computing them exactly (a .obj scene whose
    /// patches may hide one another, or of more than 2000 patches, uses 1e6 lines anyway).
    #[arg(long, value_name = "N", value_parser = parse_count)]
    pub lines: Option<u64>,
    /// Seed of the line streams.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: all cores). Never changes the result.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Also draw the mutual information matrix I_ij (6.7) as a heat map (scenes of more than
    /// 400 patches are summed into 400 × 400 bins).
    #[arg(long, value_name = "M.svg")]
    pub matrix_svg: Option<PathBuf>,
    /// Logarithmic colours for the matrix (cells at or below the low end, negative ones
    /// included, take the lowest colour; pairs that do not see each other stay white).
    #[arg(long)]
    pub log: bool,
    /// Width of the pictures in pixels.
    #[arg(
        long,
        value_name = "PX",
        default_value_t = 800,
        value_parser = clap::value_parser!(u32).range(200..=20000)
    )]
    pub width: u32,
}

/// The per-patch quantity that colours a drawing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Colour {
    /// Information transfer of each patch I_i (6.8), discrete.
    I,
    /// Continuous information transfer I_i^c (6.37), by Monte Carlo.
    Ic,
    /// Patch entropy H_i (3.2).
    H,
    /// Discretisation error I_i^c − I_i (§6.5.2).
    Delta,
}

/// Arguments of `refine`.
#[derive(Debug, clap::Args)]
pub struct RefineArgs {
    /// The scene file: `.flat` (flatland refinement) or `.obj` (hierarchical radiosity).
    pub file: PathBuf,
    /// Which oracle decides what to split.
    #[arg(long, value_enum)]
    pub oracle: Oracle,
    /// Accuracy to stop at: for .flat, the relative discretisation error
    /// (I_S^c − I_S)/I_S^c; for .obj, the oracle's threshold ε.
    #[arg(long, value_name = "E")]
    pub eps: Option<f64>,
    /// Patch (element) count to stop at. For .flat the default is 8 times the starting mesh
    /// (26 → 208 as in the thesis' Table 6.2).
    #[arg(long, value_name = "N")]
    pub target: Option<usize>,
    /// Point pairs per oracle evaluation of the 3D oracles (default 10; the thesis' robustness
    /// experiment uses 4).
    #[arg(long, value_name = "K")]
    pub pairs: Option<u32>,
    /// Lines: for .flat, the global lines that tally I^c along the surfaces once (default
    /// 1e6); for .obj, the global lines that measure the final mesh's channel (I_S, H_S,
    /// H_J, I_S^c; default 2^20, doubled up to 2^25 until every leaf received a line).
    #[arg(long, value_name = "N", value_parser = parse_count)]
    pub lines: Option<u64>,
    /// Seed of the line streams: the result depends on the seed and the budgets only.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: all cores). Never changes the result.
    #[arg(long)]
    pub threads: Option<usize>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Write the refined flatland mesh as SVG, patches coloured by I_i^c − I_i.
    #[arg(long, value_name = "OUT.svg")]
    pub svg: Option<PathBuf>,
    /// Write the refined 3D mesh as a PLY with radiosity colours.
    #[arg(long, value_name = "OUT.ply")]
    pub ply: Option<PathBuf>,
    /// Render the refined 3D mesh (Gouraud-shaded radiosity, element edges) as PNG.
    #[arg(long, value_name = "OUT.png")]
    pub png: Option<PathBuf>,
    /// For .obj: the smallest element, as a fraction of the scene's total area (default
    /// 1e-6); no element is split into children smaller than this.
    #[arg(long, value_name = "A")]
    pub min_area: Option<f64>,
    /// A reference solution to report the RMS error against (3D): a PLY written by
    /// `refine FILE.obj --ply` (its faces carry their radiosities), typically a finer run.
    #[arg(long, value_name = "REF.ply")]
    pub reference: Option<PathBuf>,
    /// With --png: the camera's eye, `x,y,z` (default: in front of the scene, on its −z
    /// side, far enough to frame it).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_point)]
    pub eye: Option<[f64; 3]>,
    /// With --png: the point the camera looks at, `x,y,z` (default: the scene's centre).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_point)]
    pub look: Option<[f64; 3]>,
    /// With --png: vertical field of view in degrees.
    #[arg(long, value_name = "DEG", default_value = "40", value_parser = parse_fov)]
    pub fov: f64,
    /// With --png: image size in pixels, `WxH`, each 16 to 8192.
    #[arg(long, value_name = "WxH", default_value = "800x800", value_parser = parse_picture_size)]
    pub size: (u32, u32),
    /// Write the refined flatland mesh as a .flat file (it reads back bit for bit).
    #[arg(short, long, value_name = "OUT.flat")]
    pub output: Option<PathBuf>,
    /// Width of an SVG picture in pixels.
    #[arg(
        long,
        value_name = "PX",
        default_value_t = 800,
        value_parser = clap::value_parser!(u32).range(200..=20000)
    )]
    pub width: u32,
}

/// Picture sides accepted by `--size` (a 16-pixel picture shows nothing useful; 8192² RGB
/// pixels with their depths are about 1 GB).
pub const PICTURE_SIDES: std::ops::RangeInclusive<u32> = 16..=8192;

/// Parses a picture size `WxH` (`800x600`), each side in [`PICTURE_SIDES`]: refused while
/// the arguments are read, before any work, so `--size 0x0` never reaches the renderer.
pub fn parse_picture_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not a picture size WxH (e.g. 800x600)"))?;
    let side = |t: &str| {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| PICTURE_SIDES.contains(v))
    };
    match (side(w), side(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(format!(
            "'{s}': width and height must be whole numbers of pixels, {} to {}",
            PICTURE_SIDES.start(),
            PICTURE_SIDES.end()
        )),
    }
}

/// Parses a point `x,y,z` of three finite numbers (`--eye`, `--look`).
pub fn parse_point(s: &str) -> Result<[f64; 3], String> {
    let bad = || format!("'{s}' is not a point x,y,z of three finite numbers");
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|_| bad()))
        .collect::<Result<_, _>>()?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok([x, y, z]),
        _ => Err(bad()),
    }
}

/// Parses a field of view in degrees, strictly between 0 and 180 (`--fov`).
pub fn parse_fov(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v < 180.0 => Ok(v),
        _ => Err(format!(
            "'{s}' is not a field of view: degrees strictly between 0 and 180"
        )),
    }
}

/// Refinement oracles (thesis chapter 6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Oracle {
    /// Transported power (2.48): flatland splits the patch of largest I_i (the thesis'
    /// "power-based" rival); 3D refines links by B_j F_ij A_i.
    Power,
    /// Kernel smoothness (2.49), 3D.
    Ks,
    /// Kernel smoothness, average variant (2.50), 3D.
    KsAv,
    /// Mutual-information-based (6.29–6.30), 3D.
    Mi,
    /// Increase in mutual information (6.3–6.5), 3D.
    MiIncrease,
    /// Discretisation error I_i^c − I_i (§6.5.2), flatland.
    De,
    /// Regular meshing (halve the longest patch), flatland.
    Regular,
}

#[cfg(test)]
mod memory_size_tests {
    use super::{parse_bytes, parse_fov, parse_picture_size, parse_point};

    #[test]
    fn camera_arguments_are_checked_when_read() {
        assert_eq!(parse_picture_size("800x600"), Ok((800, 600)));
        assert_eq!(parse_picture_size("16X8192"), Ok((16, 8192)));
        for bad in ["0x0", "800", "x", "15x100", "100x8193", "-1x100", "axb", ""] {
            assert!(parse_picture_size(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_point("1,-2, 3.5"), Ok([1.0, -2.0, 3.5]));
        for bad in ["1,2", "1,2,3,4", "1,nan,3", "1,inf,3", "a,b,c", ""] {
            assert!(parse_point(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_fov("40"), Ok(40.0));
        for bad in ["0", "180", "-5", "nan", "inf", "wide"] {
            assert!(parse_fov(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn memory_sizes_take_binary_suffixes() {
        assert_eq!(parse_bytes("1000"), Ok(1000));
        assert_eq!(parse_bytes("1e9"), Ok(1_000_000_000));
        assert_eq!(parse_bytes("512M"), Ok(512 << 20));
        assert_eq!(parse_bytes("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_bytes("2g"), Ok(2 << 30));
        assert_eq!(parse_bytes("64kb"), Ok(64 << 10));
        for bad in ["", "M", "-1M", "lots", "1e30T", "nan"] {
            assert!(parse_bytes(bad).is_err(), "{bad}");
        }
    }
}
