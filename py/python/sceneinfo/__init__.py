"""sceneinfo: information-theoretic measures of scene complexity for light transport.

After M. Feixas, *An Information-Theory Framework for the Study of the Complexity of
Visibility and Radiosity in a Scene* (2002); equation numbers refer to it.

    >>> import sceneinfo
    >>> m = sceneinfo.measure(sceneinfo.Scene.preset("cube", grid=4), lines=200_000)
    >>> m.i_s, m.patch_information        # I_S (3.8) and I_i (6.8) as a numpy array

Scenes come from files (``.flat``, ``.obj``), numpy arrays (``Scene.from_segments``,
``Scene.from_triangles``, ``Scene.from_polygons``) or presets. ``measure`` gives exact or
Monte Carlo form factors and the channel measures; ``channel`` measures any ``(w, P)``;
``measure_partial`` and ``merge`` split a line job across processes or machines, exactly,
and ``exact_rows`` and ``merge_rows`` an exact 3D job with occlusion (sparse form factors
with error estimates); ``read_view3d`` reads View3D's output files, ``view3d_surfaces``
gives a ``.vs3`` file's View3D output surfaces from a measurement of it; ``radiosity``
lights a scene (2.6) and measures its radiosity channel (5.5–5.7); ``refine``
refines a flatland mesh by an oracle (§6.5.2), ``refine_hierarchy`` a 3D scene's
hierarchical radiosity (§6.4).
"""

from ._sceneinfo import (
    CHUNK_LINES,
    SPARSE_ABOVE,
    ChannelMeasures,
    ExactRows,
    Hierarchy,
    Lighting,
    Measurement,
    Partial,
    Refiner,
    Scene,
    SceneinfoError,
    SceneinfoWarning,
    channel,
    exact_rows,
    measure,
    measure_partial,
    merge,
    merge_rows,
    radiosity,
    read_view3d,
    refine,
    refine_hierarchy,
    view3d_surfaces,
)

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
