"""Native module of dualspectra (Rust, pyo3). Use the public ``dualspectra`` package instead.

Arrays must already be contiguous float64 ``(n, 3)`` vertices and int64 ``(m, 3)`` faces
(``dualspectra`` converts array-likes).
"""

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union, final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "__version__",
    "MeshError",
    "Cancelled",
    "NumericalError",
    "Candidate",
    "Localization",
    "Localizer",
    "PreparedPartial",
    "Match",
    "Screen",
    "localize",
    "search",
    "rank",
    "search_confidences",
    "in_two_stages",
    "shapes_to_refine",
    "two_stage_order",
    "options_schema",
    "cotangent_stiffness",
    "lumped_mass",
    "gaussian_curvature",
    "spectrum",
    "read_mesh",
]

__version__: str

_Progress = Optional[Callable[[float, str], Optional[bool]]]
_Options = Optional[Dict[str, Union[int, float, str]]]

class MeshError(ValueError):
    """The mesh arrays or mesh file are invalid."""

class Cancelled(Exception):
    """The computation was cancelled: the progress callback returned False."""

class NumericalError(RuntimeError):
    """A numerical step failed."""

@final
class Candidate:
    """One optimised start of a localization."""

    @property
    def label(self) -> str:
        """Where it started: ``planeJ``, ``descriptor-fit``, ``descriptor-vote`` or ``given#i``."""
    @property
    def cost(self) -> float:
        """Final alignment cost."""
    @property
    def descriptor_score(self) -> Optional[float]:
        """Descriptor projection score (lower is better; ``None`` if not computed)."""
    @property
    def region_cost(self) -> Optional[float]:
        """Cost of the region's own step potential (lower is better; ``None`` if not computed)."""
    @property
    def boundary_misfit(self) -> Optional[float]:
        """Boundary-length misfit ``|ln(L_R / L_N)|`` (``None`` when a boundary length is 0)."""
    @property
    def partial_fit(self) -> Optional[float]:
        """Partial-to-region descriptor fit (lower is better; ``None`` for an empty region)."""
    @property
    def vote_share(self) -> Optional[float]:
        """Share of the partial's descriptor votes inside the region (higher is better; ``None`` without descriptors)."""
    @property
    def iterations(self) -> int:
        """Trust-region iterations of its run."""
    @property
    def evaluations(self) -> int:
        """Cost evaluations of its run."""
    @property
    def region(self) -> NDArray[np.bool_]:
        """Its region, one ``bool`` per vertex of the caller's full mesh."""

@final
class Localization:
    """Result of a localization. Per-vertex arrays are indexed by the caller's full-mesh
    vertices (vertices left out by the intake read ``False`` / ``0.0``)."""

    @property
    def region(self) -> NDArray[np.bool_]:
        """``True`` for full-mesh vertices in the matched region, shape ``(n_full,)``."""
    @property
    def score(self) -> NDArray[np.float64]:
        """Soft membership in [0, 1] per full-mesh vertex."""
    @property
    def potential(self) -> NDArray[np.float64]:
        """Optimised potential ``v >= 0`` per full-mesh vertex."""
    @property
    def eigenvalues_regular(self) -> NDArray[np.float64]:
        """Hamiltonian eigenvalues at the optimum, regular metric (empty in ``si`` mode)."""
    @property
    def eigenvalues_si(self) -> NDArray[np.float64]:
        """Hamiltonian eigenvalues at the optimum, scale-invariant metric (empty in ``lbo`` mode)."""
    @property
    def target_regular(self) -> NDArray[np.float64]:
        """Dirichlet spectrum of the partial shape, regular metric."""
    @property
    def target_si(self) -> NDArray[np.float64]:
        """Dirichlet spectrum of the partial shape, scale-invariant metric."""
    @property
    def cost(self) -> float:
        """Final alignment cost of the selected start."""
    @property
    def confidence(self) -> float:
        """How much to trust the region, in [0, 1]: the estimated probability that the partial
        is part of this full shape and the region overlaps the true one with IoU >= 0.5.
        Reject matches below a threshold of your choice."""
    @property
    def scale(self) -> float:
        """The factor the partial's coordinates were multiplied by: 1 with ``scale="same"``,
        the given factor, or the estimate with ``scale="auto"``."""
    @property
    def similarity_score(self) -> float:
        """How similar the partial is to this full shape, lower is more similar (``inf`` when
        unknown, e.g. empty regions): the core's ``Localization::similarity_score``, the best partial fit
        among the candidate regions (the mean distance from the partial's SHOT descriptors to
        the nearest descriptor in a region; docs/algorithm.md, "Searching several full shapes").
        Dimensionless, computed at unit full-shape area: it compares across full shapes of
        different size and meshing (:func:`search` ranks by it)."""
    @property
    def optimisation_vertices(self) -> int:
        """Vertices of the optimisation mesh the potential was optimised on: about
        ``resolution``, or twice that for a partial with holes."""
    @property
    def selected_start(self) -> int:
        """Index of the selected start in ``candidates``."""
    @property
    def n_starts(self) -> int:
        """Number of starts run."""
    @property
    def candidates(self) -> Tuple[Candidate, ...]:
        """Every optimised start; the chosen one is ``candidates[selected_start]``."""
    @property
    def warnings(self) -> Tuple[str, ...]:
        """What was repaired or skipped (the meshes' intake, a disconnected partial, ...)."""
    @property
    def timings(self) -> Dict[str, float]:
        """Wall-clock seconds per stage: preparation (0 when a prepared ``Localizer`` was
        reused), preprocessing, starts, optimisation, region, selection, total."""

@final
class PreparedPartial:
    """A partial shape taken in once to be located on several full shapes (the batch's)."""

    def __new__(cls, vertices: NDArray[np.float64], faces: NDArray[np.int64]) -> PreparedPartial: ...

@final
class Localizer:
    """A full shape prepared once for locating partials on it."""

    def __new__(
        cls,
        vertices: NDArray[np.float64],
        faces: NDArray[np.int64],
        options: _Options = None,
        progress: _Progress = None,
    ) -> Localizer: ...
    def locate(
        self, vertices: NDArray[np.float64], faces: NDArray[np.int64], progress: _Progress = None
    ) -> Localization: ...
    def locate_prepared(self, partial: PreparedPartial, quick: bool = False, progress: _Progress = None) -> Localization:
        """``locate`` of a prepared partial, as a search locates it (``quick``: its quick
        localization)."""
    @property
    def n_vertices(self) -> int:
        """Vertices of the caller's full mesh."""
    @property
    def optimisation_vertices(self) -> int:
        """Vertices of the optimisation mesh."""
    @property
    def warnings(self) -> Tuple[str, ...]:
        """Notes on the full mesh's intake and the preparation."""
    @property
    def options(self) -> Dict[str, Union[int, float, str]]:
        """The options it was prepared with."""
    @property
    def preparation_seconds(self) -> float:
        """Seconds the preparation took."""
    @property
    def intake_note(self) -> Optional[str]:
        """What the intake of the full mesh changed (``None``: nothing, or a loaded shape)."""
    def save(self, path: str) -> None: ...
    @staticmethod
    def load(path: str, threads: Optional[int] = None) -> Localizer: ...
    def to_bytes(self) -> bytes: ...
    @staticmethod
    def from_bytes(data: bytes, threads: Optional[int] = None, intake_note: Optional[str] = None) -> Localizer: ...

@final
class Match:
    """One full shape's answer for a partial (:func:`dualspectra.search`)."""

    @property
    def index(self) -> int:
        """Index of the full shape in the shapes searched."""
    @property
    def score(self) -> float:
        """The similarity score (``Localization.similarity_score``), lower is more similar;
        ``inf`` when the partial could not be located on this shape."""
    @property
    def localization(self) -> Optional[Localization]:
        """The localization on this shape, indexed by its vertices (``None`` when it failed)."""
    @property
    def error(self) -> Optional[str]:
        """Why the partial could not be located on this shape (``None`` when it was)."""
    @property
    def screen_score(self) -> Optional[float]:
        """The screen's score of this shape (lower is more similar) when the search was
        screened (``shortlist`` or ``screen``); a shape screened out has no localization and
        no error."""
    @property
    def quick(self) -> bool:
        """Whether ``localization`` is a screened search's quick one (fewer starts, iterations
        and eigenvalues, ranking the shortlist) rather than a full localization: the best of the
        shortlist (and the second best when its quick score is within 4 % of the best's) is
        localized again in full and ranked first."""
    @property
    def confidence(self) -> float:
        """How much to trust that the partial is a part of this shape rather than of another
        one searched, in [0, 1]: how far its score is behind (relative to the spread of the
        search's scores), or ahead of, the best other shape's, and the localization's own
        confidence; 0 when not located. What to threshold to reject a
        match (``localization.confidence`` says only whether the region fits)."""

@final
class Screen:
    """A library of full shapes described for screening (the core's ``Screen``)."""

    def __new__(
        cls,
        fulls: Sequence[Union[Localizer, Tuple[NDArray[np.float64], NDArray[np.int64]], str]],
        labels: Optional[List[str]] = None,
        progress: _Progress = None,
    ) -> Screen: ...
    def rank(
        self,
        vertices: NDArray[np.float64],
        faces: NDArray[np.int64],
        scale: Union[str, float, None] = None,
        progress: _Progress = None,
    ) -> Tuple[List[Tuple[int, float]], List[str]]: ...
    def save(self, path: str) -> None: ...
    @staticmethod
    def load(path: str) -> Screen: ...
    def to_bytes(self) -> bytes: ...
    @staticmethod
    def from_bytes(data: bytes) -> Screen: ...
    @property
    def labels(self) -> Tuple[str, ...]:
        """Each shape's label (empty strings unless given)."""
    @property
    def warnings(self) -> Tuple[str, ...]:
        """What the intake of the meshes changed (empty for a loaded screen)."""
    @property
    def nbytes(self) -> Tuple[int, int]:
        """Bytes held per shape and for the shared basis."""
    def __len__(self) -> int: ...

def localize(
    full_vertices: NDArray[np.float64],
    full_faces: NDArray[np.int64],
    partial_vertices: NDArray[np.float64],
    partial_faces: NDArray[np.int64],
    options: _Options = None,
    progress: _Progress = None,
) -> Localization: ...
def search(
    vertices: NDArray[np.float64],
    faces: NDArray[np.int64],
    fulls: Sequence[Union[Localizer, Tuple[NDArray[np.float64], NDArray[np.int64]]]],
    top: Optional[int] = None,
    progress: _Progress = None,
    shortlist: Optional[int] = None,
    screen: Optional[Screen] = None,
    options: _Options = None,
) -> Tuple[List[Match], List[List[str]]]: ...
def rank(scored: Sequence[Tuple[float, int]], top: Optional[int] = None) -> List[int]: ...
def search_confidences(located: Sequence[Tuple[float, float]]) -> List[float]: ...
def in_two_stages(shortlist: int, library: int) -> bool: ...
def shapes_to_refine(quick: Sequence[Tuple[float, int]]) -> List[int]: ...
def two_stage_order(full: Sequence[Tuple[float, int]], quick: Sequence[Tuple[float, int]]) -> List[Tuple[bool, int]]: ...
def options_schema() -> List[Dict[str, Any]]: ...
def spectrum(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], k: int, metric: str, alpha: float
) -> NDArray[np.float64]: ...
def gaussian_curvature(
    vertices: NDArray[np.float64], faces: NDArray[np.int64], smoothed: bool = False
) -> NDArray[np.float64]: ...
def cotangent_stiffness(
    vertices: NDArray[np.float64], faces: NDArray[np.int64]
) -> Tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], int]: ...
def lumped_mass(vertices: NDArray[np.float64], faces: NDArray[np.int64]) -> NDArray[np.float64]: ...
def read_mesh(path: str) -> Tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], List[str]]: ...
