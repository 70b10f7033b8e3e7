"""Native module of dualspectra (Rust, pyo3). Use the public ``dualspectra`` package instead.

Arrays must already be contiguous float64 ``(n, 3)`` vertices and int64 ``(m, 3)`` faces
(``dualspectra`` converts array-likes).
"""

from typing import Callable, Optional, Tuple, final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "__version__",
    "MeshError",
    "Cancelled",
    "NumericalError",
    "Localization",
    "localize",
    "cotangent_stiffness",
    "lumped_mass",
    "gaussian_curvature",
    "spectrum",
    "read_mesh",
]

__version__: str

class MeshError(ValueError):
    """The mesh arrays or mesh file are invalid."""

class Cancelled(Exception):
    """The computation was cancelled: the progress callback returned False."""

class NumericalError(RuntimeError):
    """A numerical step failed."""

@final
class Localization:
    """Result of ``localize``. Per-vertex arrays are indexed by the full mesh's vertices."""

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
    def selected_start(self) -> int:
        """Index of the selected start."""
    @property
    def n_starts(self) -> int:
        """Number of starts run."""
    @property
    def timings(self) -> dict[str, float]:
        """Wall-clock seconds per stage: preprocessing, starts, optimisation, selection, region, total."""

def localize(
    full_vertices: NDArray[np.float64],
    full_faces: NDArray[np.int64],
    partial_vertices: NDArray[np.float64],
    partial_faces: NDArray[np.int64],
    mode: str,
    k: int,
    alpha: float,
    seed: int,
    resolution: Optional[int] = None,
    centers: Optional[int] = None,
    max_iterations: Optional[int] = None,
    threads: Optional[int] = None,
    selection: Optional[str] = None,
    starts: Optional[str] = None,
    spectral_cuts: Optional[int] = None,
    plane_cuts: Optional[int] = None,
    progress: Optional[Callable[[float, str], Optional[bool]]] = None,
) -> Localization: ...
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
def read_mesh(path: str) -> Tuple[NDArray[np.float64], NDArray[np.int64]]: ...
