"""Partial shape localization by multi-metric Hamiltonian spectra matching.

Given a full triangle mesh M and a partial, possibly deformed copy N of a part of it,
:class:`Localizer` (prepare M once, locate many partials) and :func:`localize` (one call)
find the region of M that N is (Bensaïd, Bracha, Kimmel: "Partial Shape Similarity by
Multi-metric Hamiltonian Spectra Matching", SSVM 2023). The operators it is built on (cotangent
stiffness, lumped mass, Gaussian curvature, Dirichlet spectra) are exposed too.

Partial shape similarity: :func:`search` ranks several full shapes for one partial ("which
of these models is this fragment part of, and where?") by the core's similarity score
(:attr:`Localization.similarity_score`, lower is more similar), and
:func:`dualspectra.batch.search_batch` (also here as :func:`search_batch`) does so for many
partials, locally or on a Dask cluster. A :class:`Screen` describes a library of full shapes
once (a few descriptors per shape, saved as ``.dsscreen`` files) so that both locate a partial
on the shapes it ranks best only (``shortlist=``). A prepared :class:`Localizer` is saved and loaded
(:meth:`Localizer.save`, :meth:`Localizer.load`: the core's versioned ``.dsprep`` files) and
pickled (as the same bytes), so a library of full shapes is prepared once.

Meshes are passed as two array-likes: vertices ``V`` of shape ``(n, 3)`` (anything
convertible to float64) and faces ``F`` of shape ``(m, 3)`` (integers, 0-based). Every
computation runs in the Rust core ``dualspectra`` with the GIL released; this module only
converts arrays. The localizer takes meshes as editors and scanners hold them: faces that
repeat a vertex or have zero area, and vertices in no face, are left out, and non-manifold
edges and vertices are split (a :class:`DualspectraWarning` and :attr:`Localization.warnings`
say so), and every per-vertex result is indexed by the caller's vertices (a split vertex is
in the region if any of its copies is). The operators need clean meshes (their results are indexed by every
given vertex) and raise :class:`MeshError` instead.

The localizer's options (``k``, ``mode``, ...) are keyword arguments named as in the core's
table, :func:`options_schema` (names, types, ranges, defaults, docs); unknown names and
values out of range raise ``ValueError`` with the core's message.

Errors: :class:`MeshError` (a ``ValueError``) for invalid meshes or mesh files (and
prepared-shape files that are foreign, stale, truncated or corrupted),
:class:`Cancelled` when a progress callback returns ``False``, :class:`NumericalError`
(a ``RuntimeError``) when a numerical step fails, ``ValueError`` for bad arguments,
``OSError`` for unreadable files, ``TypeError`` for arrays or values of the wrong kind.

Warnings: what the core repaired or skipped (dropped faces and vertices, split non-manifold
edges and vertices, a disconnected partial reduced to its largest component, a decimation
that fell back to the full resolution) is kept in :attr:`Localization.warnings` and
:attr:`Localizer.warnings`, and emitted once through :func:`warnings.warn` as
:class:`DualspectraWarning`: by :class:`Localizer` for the full mesh and its preparation, by
:meth:`Localizer.locate` for what concerns that partial, by :func:`localize` for all of them
(and by :func:`read_mesh` for its split). Silence them with
``warnings.simplefilter("ignore", dualspectra.DualspectraWarning)``.
"""

from . import batch
from ._api import (
    DualspectraWarning,
    FullShape,
    Localizer,
    OptionValue,
    ProgressCallback,
    _unpickle_localizer,  # pickles of a Localizer made before 0.3.0 name it here
    cotangent_stiffness,
    cotangent_stiffness_csc,
    gaussian_curvature,
    localize,
    lumped_mass,
    options_schema,
    Screen,
    read_mesh,
    search,
    spectrum,
)
from ._dualspectra import Cancelled, Candidate, Localization, Match, MeshError, NumericalError, __version__
from .batch import BatchMatch, search_batch

__all__ = [
    "__version__",
    "batch",
    "BatchMatch",
    "Cancelled",
    "Candidate",
    "DualspectraWarning",
    "FullShape",
    "Localization",
    "Localizer",
    "Match",
    "MeshError",
    "NumericalError",
    "OptionValue",
    "ProgressCallback",
    "cotangent_stiffness",
    "cotangent_stiffness_csc",
    "gaussian_curvature",
    "localize",
    "lumped_mass",
    "options_schema",
    "read_mesh",
    "Screen",
    "search",
    "search_batch",
    "spectrum",
]
