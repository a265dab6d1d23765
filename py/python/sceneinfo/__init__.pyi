"""Type stubs of sceneinfo (the extension module sceneinfo._sceneinfo, re-exported).

Equation numbers refer to Feixas (2002).
"""

import os
from typing import Any, Callable, Literal, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

_Path = Union[str, "os.PathLike[str]"]
_Floats = npt.ArrayLike
_Ints = npt.ArrayLike
_Method = Literal["global", "local", "bundle"]
_Progress = Callable[[int, int], Any]

__all__ = [
    "CHUNK_LINES",
    "SPARSE_ABOVE",
    "ChannelMeasures",
    "ExactRows",
    "Hierarchy",
    "Lighting",
    "Measurement",
    "Partial",
    "Refiner",
    "Scene",
    "SceneinfoError",
    "SceneinfoWarning",
    "channel",
    "exact_rows",
    "measure",
    "measure_partial",
    "merge",
    "merge_rows",
    "radiosity",
    "read_view3d",
    "refine",
    "refine_hierarchy",
    "view3d_surfaces",
]

CHUNK_LINES: int
"""Lines per seeded chunk (2¹⁶): partial results are ranges of chunks."""
SPARSE_ABOVE: int
"""Above this many states Measurement.form_factors() answers a scipy.sparse.csr_matrix."""

class SceneinfoError(ValueError):
    """A scene, job or array sceneinfo refuses."""

    file: Optional[str]
    """The file, or None (arrays, text)."""
    line: Optional[int]
    """The 1-based line of a text file, or row of an array, or None."""
    kind: str
    """The core's error kind, e.g. 'BadNumber', 'VertexIndex', 'MayBeOccluded'."""
    message: str
    """What was wrong."""

class SceneinfoWarning(UserWarning):
    """Numbers that cannot be trusted to full precision; what a loader skipped or repaired."""

@final
class Scene:
    """A flatland (segments) or 3D (planar convex patches) scene."""

    @staticmethod
    def load(path: _Path, emit_from_ka: bool = False) -> Scene:
        """Reads a .flat, .obj (MTL libraries from the OBJ's folder; Ka as emittance with
        emit_from_ka), .gltf/.glb or .ply file, its format told by content, then extension."""
    @staticmethod
    def from_text(text: str, format: Literal["flat", "obj"] = "flat") -> Scene: ...
    @staticmethod
    def from_segments(
        segments: _Floats,
        reflectance: Optional[_Floats] = None,
        emittance: Optional[_Floats] = None,
    ) -> Scene:
        """Flatland: segments (n, 4) rows [x0, y0, x1, y1]; materials (n,) or (n, 3)."""
    @staticmethod
    def from_triangles(
        vertices: _Floats,
        faces: _Ints,
        reflectance: Optional[_Floats] = None,
        emittance: Optional[_Floats] = None,
    ) -> Scene:
        """3D: vertices (n, 3) float64, faces (m, 3) indices, counter-clockwise fronts."""
    @staticmethod
    def from_polygons(
        vertices: _Floats,
        indices: _Ints,
        offsets: _Ints,
        reflectance: Optional[_Floats] = None,
        emittance: Optional[_Floats] = None,
    ) -> Scene:
        """3D: polygon k is indices[offsets[k]:offsets[k+1]] (planar, convex)."""
    @staticmethod
    def preset(name: str, grid: int = 10) -> Scene:
        """A 3D preset: 'cube' (grid 10: 600 patches), 'cornell', 'cornell-thesis', ..."""
    @staticmethod
    def catalogue(name: str, per_side: int = 1) -> Scene:
        """A flatland scene of the thesis' catalogue."""
    def save(self, path: _Path) -> None:
        """Writes .flat, or .obj with its .mtl beside it."""
    @property
    def n_patches(self) -> int: ...
    @property
    def is_flat(self) -> bool: ...
    @property
    def path(self) -> Optional[str]: ...
    @property
    def load_warnings(self) -> list[str]: ...
    @property
    def patch_sizes(self) -> npt.NDArray[np.float64]:
        """a_i = A_i / A_T (3.3)."""
    @property
    def reflectance(self) -> npt.NDArray[np.float64]:
        """(n, 3) reflectance ρ per patch."""
    @property
    def emittance(self) -> npt.NDArray[np.float64]:
        """(n, 3) emittance E per patch."""

@final
class Measurement:
    """What measure() returns. Discrete measures are None when some patch got no line."""

    @property
    def n_patches(self) -> int: ...
    @property
    def n_states(self) -> Optional[int]: ...
    @property
    def background(self) -> Optional[bool]: ...
    @property
    def max_row_deficit(self) -> Optional[float]: ...
    @property
    def h_p(self) -> Optional[float]:
        """Positional entropy H_P (3.5)."""
    @property
    def h_s(self) -> Optional[float]:
        """Scene visibility entropy H_S (3.1)."""
    @property
    def h_j(self) -> Optional[float]:
        """Joint entropy H_J (3.6)."""
    @property
    def i_s(self) -> Optional[float]:
        """Scene visibility mutual information I_S (3.8)."""
    @property
    def h_s_norm(self) -> Optional[float]:
        """H_S / H_P (3.12)."""
    @property
    def i_s_norm(self) -> Optional[float]:
        """I_S / H_P (3.13)."""
    @property
    def h_s_joint_norm(self) -> Optional[float]: ...
    @property
    def i_s_joint_norm(self) -> Optional[float]: ...
    @property
    def e_mse(self) -> Optional[float]:
        """E(MSE) of the form-factor estimates for one line (3.20)."""
    @property
    def fano(self) -> Optional[float]:
        """Fano's bound (3.21)."""
    @property
    def checks(self) -> Optional[dict[str, Union[float, bool]]]: ...
    def measures(self) -> Optional[dict[str, Union[float, int]]]:
        """The measures with the keys of the CLI's measure --json."""
    @property
    def patch_sizes(self) -> npt.NDArray[np.float64]: ...
    @property
    def patch_information(self) -> Optional[npt.NDArray[np.float64]]:
        """I_i (6.8), summing to I_S (6.9)."""
    @property
    def patch_entropies(self) -> Optional[npt.NDArray[np.float64]]:
        """H_i (3.2)."""
    @property
    def patch_continuous(self) -> Optional[npt.NDArray[np.float64]]:
        """I_i^c (6.37) of a line job."""
    @property
    def pair_continuous(self) -> Optional[npt.NDArray[np.float64]]:
        """I_ij^c (6.35, 6.36), (n, n), small scenes."""
    @property
    def i_s_continuous(self) -> Optional[float]:
        """I_S^c (4.8, 4.13) of a line job."""
    @property
    def i_s_continuous_stderr(self) -> Optional[float]: ...
    @property
    def samples(self) -> Optional[int]: ...
    @property
    def stderr_groups(self) -> Optional[int]: ...
    @property
    def lines(self) -> int: ...
    @property
    def requested_lines(self) -> Optional[int]: ...
    @property
    def seed(self) -> Optional[int]: ...
    @property
    def method(self) -> str: ...
    @property
    def unsampled_patches(self) -> int: ...
    @property
    def lines_to_sample_all(self) -> Optional[int]: ...
    @property
    def warnings(self) -> list[str]: ...
    def form_factors(self, sparse: Optional[bool] = None) -> Any:
        """F_ij (2.2): ndarray (n, n), or scipy.sparse.csr_matrix; None if unsampled."""
    def form_factors_csr(
        self,
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.int64]]:
        """(data, indices, indptr) of F without scipy."""
    @property
    def exact_errors(self) -> Optional[dict[str, Union[float, int]]]:
        """Error estimates of exact 3D form factors with occlusion (None: none integrated)."""
    def form_factor_errors(self) -> npt.NDArray[np.float64]:
        """Each F entry's error estimate, aligned with form_factors_csr()'s data (NaN: none)."""
    def zero_form_factor_errors(
        self,
    ) -> Tuple[npt.NDArray[np.int64], npt.NDArray[np.int64], npt.NDArray[np.float64]]:
        """(rows, cols, errors) of the entries 0 ± error (not in form_factors_csr())."""

@final
class ChannelMeasures:
    """The measures of a channel (w, P) (§3.1)."""

    @property
    def n_states(self) -> int: ...
    @property
    def h_p(self) -> float: ...
    @property
    def h_s(self) -> float: ...
    @property
    def h_j(self) -> float: ...
    @property
    def i_s(self) -> float: ...
    @property
    def h_s_norm(self) -> float: ...
    @property
    def i_s_norm(self) -> float: ...
    @property
    def h_s_joint_norm(self) -> float: ...
    @property
    def i_s_joint_norm(self) -> float: ...
    @property
    def e_mse(self) -> float: ...
    @property
    def fano(self) -> float: ...
    @property
    def checks(self) -> dict[str, Union[float, bool]]: ...
    def measures(self) -> dict[str, Union[float, int]]: ...
    @property
    def patch_entropies(self) -> npt.NDArray[np.float64]: ...
    @property
    def patch_information(self) -> npt.NDArray[np.float64]: ...

@final
class Partial:
    """The exact tally of chunks of a line job, to merge with others of the same job."""

    @staticmethod
    def load(path: _Path) -> Partial: ...
    @staticmethod
    def from_bytes(data: bytes) -> Partial: ...
    def to_bytes(self) -> bytes: ...
    def save(self, path: _Path) -> None: ...
    @property
    def chunks(self) -> Tuple[int, int]: ...
    @property
    def job_lines(self) -> int: ...
    @property
    def lines(self) -> int: ...
    @property
    def seed(self) -> int: ...
    @property
    def method(self) -> str: ...
    @property
    def is_complete(self) -> bool: ...
    def measurement(self) -> Measurement:
        """One run of the whole job, bit for bit (complete partials only)."""

@final
class ExactRows:
    """Rows of the exact 3D form factors with occlusion of a scene, to merge with others."""

    @staticmethod
    def load(path: _Path) -> ExactRows: ...
    @staticmethod
    def from_bytes(data: bytes) -> ExactRows: ...
    def to_bytes(self) -> bytes: ...
    def save(self, path: _Path) -> None: ...
    @property
    def rows(self) -> Tuple[int, int]: ...
    @property
    def n_patches(self) -> int: ...
    @property
    def pair_count(self) -> int: ...
    @property
    def tolerance(self) -> float: ...
    @property
    def is_complete(self) -> bool: ...
    def measurement(self) -> Measurement:
        """The whole job's form factors (sparse) and measures (complete rows only)."""

def exact_rows(
    scene: Union[Scene, _Path],
    tol: float = 1e-06,
    rows: Optional[Tuple[int, int]] = None,
    threads: Optional[int] = None,
    progress: Optional[_Progress] = None,
) -> ExactRows: ...
def merge_rows(parts: Sequence[Union[ExactRows, _Path]]) -> ExactRows: ...
def read_view3d(path: _Path) -> dict[str, Any]:
    """A View3D output file: areas, form_factors (N, N), emissivities, version, encl, emit."""

def view3d_surfaces(path: _Path, m: Measurement) -> dict[str, Any]:
    """View3D's output surfaces of a .vs3 file from a measurement of it: numbers, names,
    areas (N,), form_factors (N, N) (combined surfaces joined, subsurfaces and masks as
    View3D reports them, obstruction-only surfaces left out; the file's encl=1 and emit=1
    applied), emissivities (N,), encl, emit."""

def measure(
    scene: Union[Scene, _Path],
    lines: Union[None, int, Literal["auto"]] = None,
    method: _Method = "global",
    seed: int = 1,
    threads: Optional[int] = None,
    progress: Optional[_Progress] = None,
    max_lines: Optional[int] = None,
    tol: Optional[float] = None,
) -> Measurement:
    """Exact (lines=None) or Monte Carlo (2.36, 2.37) form factors and their measures."""

def measure_partial(
    scene: Union[Scene, _Path],
    lines: int,
    chunks: Optional[Tuple[int, int]] = None,
    method: _Method = "global",
    seed: int = 1,
    threads: Optional[int] = None,
    progress: Optional[_Progress] = None,
) -> Partial: ...
def merge(parts: Sequence[Union[Partial, _Path]]) -> Partial: ...
def channel(w: _Floats, p: Any) -> ChannelMeasures:
    """Measures of the channel (w, P): P dense (n, n) or scipy sparse."""

@final
class Lighting:
    """A lit scene: B = E + ρFB (2.6) per colour channel and its radiosity measures."""

    @property
    def radiosity(self) -> npt.NDArray[np.float64]:
        """B_i, (n_states, 3) (R, G, B)."""
    @property
    def visibility(self) -> Measurement: ...
    @property
    def h_p(self) -> npt.NDArray[np.float64]:
        """H_P (5.6) per channel, (3,)."""
    @property
    def h_s(self) -> npt.NDArray[np.float64]:
        """H_S (5.5) per channel, (3,)."""
    @property
    def h_j(self) -> npt.NDArray[np.float64]: ...
    @property
    def i_s(self) -> npt.NDArray[np.float64]:
        """I_S (5.7) per channel, (3,)."""
    @property
    def light_flows(self) -> list[bool]: ...
    @property
    def iterations(self) -> list[int]: ...
    @property
    def residuals(self) -> list[float]: ...
    @property
    def i_s_continuous(self) -> Optional[npt.NDArray[np.float64]]:
        """Radiosity I_S^c (5.20) per channel, from lines."""
    @property
    def i_s_continuous_stderr(self) -> Optional[npt.NDArray[np.float64]]: ...
    @property
    def visibility_i_s_continuous(self) -> Optional[float]: ...
    @property
    def lines(self) -> int: ...
    def measures(self) -> list[dict[str, Union[float, bool]]]: ...

def radiosity(
    scene: Union[Scene, _Path],
    lines: Union[None, int, Literal["auto"]] = None,
    method: _Method = "global",
    seed: int = 1,
    threads: Optional[int] = None,
    progress: Optional[_Progress] = None,
    max_lines: Optional[int] = None,
    solver: Literal["gauss-seidel", "jacobi", "southwell"] = "gauss-seidel",
    tolerance: float = 1e-10,
    max_iterations: int = 1_000_000,
) -> Lighting:
    """Lights the scene (2.6) on exact or line form factors; radiosity measures (5.5–5.7)."""

@final
class Refiner:
    """Flatland refinement one split at a time (§6.5.2)."""

    def __new__(
        cls,
        scene: Union[Scene, _Path],
        oracle: Literal["de", "power", "regular"] = "de",
        lines: int = 1_000_000,
        seed: int = 1,
    ) -> Refiner: ...
    def step(self) -> dict[str, Any]: ...
    def run_until(self, patches: int, eps: Optional[float] = None) -> dict[str, Any]: ...
    def report(self) -> dict[str, Any]: ...
    @property
    def scene(self) -> Scene: ...
    @property
    def patch_information(self) -> npt.NDArray[np.float64]:
        """I_i (6.8)."""
    @property
    def patch_continuous(self) -> npt.NDArray[np.float64]:
        """I_i^c (6.37)."""
    @property
    def patch_errors(self) -> npt.NDArray[np.float64]:
        """I_i^c − I_i."""

def refine(
    scene: Union[Scene, _Path],
    patches: int,
    oracle: Literal["de", "power", "regular"] = "de",
    lines: int = 1_000_000,
    seed: int = 1,
    eps: Optional[float] = None,
) -> Refiner:
    """Refines a flatland scene to `patches` patches or δ̄ ≤ eps."""

@final
class Hierarchy:
    """A 3D scene's hierarchical radiosity refined by an oracle (§6.4)."""

    @property
    def n_leaves(self) -> int:
        """Leaves: the elements of the refined mesh."""
    @property
    def n_links(self) -> int:
        """Links of the final hierarchy."""
    @property
    def rays(self) -> int:
        """Rays cast for link form factors and oracle decisions."""
    @property
    def epsilon(self) -> float:
        """The oracle's threshold the mesh was refined with."""
    @property
    def leaf_radiosity(self) -> npt.NDArray[np.float64]:
        """B per leaf and colour channel, shape (n_leaves, 3)."""
    @property
    def leaf_areas(self) -> npt.NDArray[np.float64]:
        """Area of each leaf."""
    @property
    def leaf_patches(self) -> list[int]:
        """The scene patch each leaf lies on."""
    def leaf_polygons(self) -> list[npt.NDArray[np.float64]]:
        """Each leaf's polygon as a (k, 3) array of vertices."""

def refine_hierarchy(
    scene: Union[Scene, _Path],
    oracle: Literal["power", "ks", "ks-av", "mi", "mi-increase", "regular"] = "mi",
    epsilon: Optional[float] = None,
    leaves: Optional[int] = None,
    pairs: int = 10,
    seed: int = 1,
) -> Hierarchy:
    """Hierarchical radiosity of a 3D scene, links refined by `oracle` with threshold
    `epsilon`, or the threshold giving about `leaves` leaves (§6.4)."""
