"""flexbody from Python: reduce a linear FE model to a flexible body for
multibody simulation, with numpy arrays and scipy.sparse matrices in and
out. SI units throughout (m, kg, s, N, Pa).

    import flexbody
    model = flexbody.read("examples/side_beam.toml")
    modes = model.modes(count=6)                 # frequencies, shapes
    body = model.reduce("craig-bampton", modes=4)
    body.write("side_beam.sid", format="sid")

Every call is the command line's job on the same input and gives the same
numbers (the tests check it). Errors are :class:`flexbody.Error`, a
``ValueError`` with the command line's message (the file, line, node, DOF
or set it is about). Long work releases the GIL and shows a spinner on a
terminal.
"""

from __future__ import annotations

import json as _json
import os as _os
from dataclasses import dataclass as _dataclass
from typing import TYPE_CHECKING, Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as _np

if TYPE_CHECKING:
    import scipy.sparse as _sp

from . import _flexbody
from ._flexbody import Error

__all__ = [
    "Error",
    "Model",
    "Modes",
    "Body",
    "Sid",
    "StudyResult",
    "read",
    "load",
    "DOF_NAMES",
]

#: DOF numbers 1..6 of the ``dofs`` arrays, by name.
DOF_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")

Body = _flexbody.Body
Sid = _flexbody.Sid

PathLike = Union[str, "_os.PathLike[str]"]


def _sparse():
    """scipy.sparse, imported on first use: reading a model and its modes
    need no scipy, and importing it takes a quarter of a second."""
    import scipy.sparse

    return scipy.sparse


def _csc(parts: Tuple[_np.ndarray, _np.ndarray, _np.ndarray, int]) -> "_sp.csc_array":
    indptr, indices, data, n = parts
    return _sparse().csc_array((data, indices, indptr), shape=(n, n), copy=False)


def _csc_parts(name: str, a: Any) -> Tuple[Tuple[_np.ndarray, _np.ndarray, _np.ndarray], Tuple[int, int]]:
    """A matrix (scipy.sparse or dense) as CSC arrays with int64 indices."""
    _sp = _sparse()
    if _sp.issparse(a):
        a = _sp.csc_array(a)
    else:
        dense = _np.asarray(a)
        if dense.ndim != 2:
            raise Error(f"{name} must be a 2-D matrix; got an array of shape {dense.shape}")
        a = _sp.csc_array(dense)
    if not _np.issubdtype(a.dtype, _np.number) or _np.iscomplexobj(a.data):
        raise Error(f"{name} must hold real numbers; got {a.dtype}")
    a = a.astype(_np.float64)
    a.sum_duplicates()
    a.sort_indices()
    parts = (
        _np.ascontiguousarray(a.indptr, dtype=_np.int64),
        _np.ascontiguousarray(a.indices, dtype=_np.int64),
        _np.ascontiguousarray(a.data, dtype=_np.float64),
    )
    return parts, a.shape


def _dof_array(dofs: Any) -> _np.ndarray:
    """``(n, 2)`` DOFs (node, 1..6 or a name such as "uz") as flat int64."""
    rows = _np.asarray(dofs, dtype=object) if not isinstance(dofs, _np.ndarray) else dofs
    if rows.ndim != 2 or rows.shape[1] != 2:
        raise Error(f"dofs must be an (n, 2) array of node id and DOF (1..6 or 'ux'..'rz'); got shape {rows.shape}")
    out = _np.empty((rows.shape[0], 2), dtype=_np.int64)
    for i, (node, dof) in enumerate(rows):
        if isinstance(dof, str):
            name = dof.strip().lower()
            if name not in DOF_NAMES:
                raise Error(f"dofs row {i}: unknown DOF '{dof}'; expected one of {', '.join(DOF_NAMES)} or 1..6")
            dof = DOF_NAMES.index(name) + 1
        try:
            out[i] = (int(node), int(dof))
        except (TypeError, ValueError, OverflowError):
            raise Error(f"dofs row {i}: ({node!r}, {dof!r}) is not a node id and a DOF") from None
        if out[i, 0] != node or out[i, 1] != dof:
            raise Error(f"dofs row {i}: ({node!r}, {dof!r}) is not a whole node id and DOF")
    return out.reshape(-1)


@_dataclass(frozen=True)
class Modes:
    """Natural modes of a model, lowest first.

    ``shapes`` is ``(n, k)``, M-orthonormal (``shapes.T @ M @ shapes = I``),
    rows in the model's DOF order (``Model.dofs``); ``residuals`` are
    ``||K phi - lambda M phi|| / ||K phi||``; ``mechanism`` is the warning
    the command line prints when the zero frequencies show a mechanism,
    else ``None``.
    """

    eigenvalues: _np.ndarray
    frequencies_hz: _np.ndarray
    shapes: _np.ndarray
    residuals: _np.ndarray
    mechanism: Optional[str]


@_dataclass(frozen=True)
class StudyResult:
    """A study's error table: ``records`` has one dict per case (``method``,
    ``r``, ``omega`` in rad/s, the relative errors ``err_w``, ``err_force``
    and, where they apply, ``err_m``, ``err_q``, ``err_vm``); ``failed`` the
    cases that could not run, with the reason."""

    records: List[Dict[str, Any]]
    failed: List[Dict[str, Any]]

    def to_dataframe(self):
        """The records as a pandas DataFrame (needs pandas)."""
        import pandas

        return pandas.DataFrame.from_records(self.records)


class Model:
    """A component: K, M (and D) over its DOFs, node coordinates and, for a
    mesh, its sets and couplings. Make one with :func:`read` or
    :meth:`Model.from_matrices`."""

    __slots__ = ("_m",)

    def __init__(self, inner: "_flexbody.Model"):
        self._m = inner

    @classmethod
    def from_matrices(
        cls,
        K: Any,
        M: Any,
        dofs: Any,
        coords: Any = None,
        D: Any = None,
    ) -> "Model":
        """A model of stiffness ``K`` and mass ``M`` (scipy.sparse or dense,
        symmetric to 1e-10 of the largest entry) over ``dofs``, an ``(n, 2)``
        array of node id and DOF (1..6 or ``"ux"``..``"rz"``). ``coords``,
        needed by free-body reductions and the floating-frame invariants,
        maps node id to ``(x, y, z)`` (a dict, or a pair ``(ids, xyz)``).
        ``D`` is an optional damping matrix."""
        k, k_shape = _csc_parts("K", K)
        m, m_shape = _csc_parts("M", M)
        if k_shape != m_shape:
            raise Error(f"K is {k_shape[0]} x {k_shape[1]} but M is {m_shape[0]} x {m_shape[1]}")
        if k_shape[0] != k_shape[1]:
            raise Error(f"K is {k_shape[0]} x {k_shape[1]}; it must be square")
        d = None
        if D is not None:
            d, d_shape = _csc_parts("D", D)
            if d_shape != k_shape:
                raise Error(f"D is {d_shape[0]} x {d_shape[1]} but K is {k_shape[0]} x {k_shape[1]}")
        ids = xyz = None
        if coords is not None:
            if isinstance(coords, dict):
                ids = _np.fromiter((int(n) for n in coords), dtype=_np.int64, count=len(coords))
                xyz = _np.array([coords[n] for n in coords], dtype=_np.float64).reshape(len(coords), -1)
            else:
                ids, xyz = coords
                ids = _np.asarray(ids, dtype=_np.int64)
                xyz = _np.asarray(xyz, dtype=_np.float64)
            if xyz.ndim != 2 or xyz.shape[1] != 3 or xyz.shape[0] != ids.shape[0]:
                raise Error(f"coords must give (x, y, z) for each of {ids.shape[0]} nodes; got shape {xyz.shape}")
            ids = _np.ascontiguousarray(ids)
            xyz = _np.ascontiguousarray(xyz).reshape(-1)
        inner = _flexbody.from_matrices(k_shape[0], k, m, _dof_array(dofs), ids, xyz, d)
        return cls(inner)

    # -- what the model is ------------------------------------------------

    @property
    def path(self) -> str:
        """The file the model was read from (``"matrices"`` for matrices)."""
        return self._m.path

    @property
    def K(self) -> _sp.csc_array:
        """Stiffness (N/m, N, N m), over the free DOFs."""
        return _csc(self._m.stiffness_csc())

    @property
    def M(self) -> _sp.csc_array:
        """Mass (kg, kg m, kg m^2), over the free DOFs."""
        return _csc(self._m.mass_csc())

    @property
    def D(self) -> Optional[_sp.csc_array]:
        """Damping, or ``None`` where the model has none."""
        parts = self._m.damping_csc()
        return None if parts is None else _csc(parts)

    @property
    def dofs(self) -> _np.ndarray:
        """The DOF of each equation, ``(n, 2)``: node id, 1..6 (ux..rz)."""
        return self._m.dofs

    @property
    def node_ids(self) -> _np.ndarray:
        """Node ids, ascending (every node of a mesh)."""
        return self._m.nodes()[0]

    @property
    def coords(self) -> _np.ndarray:
        """Node coordinates ``(k, 3)`` (m), in the order of ``node_ids``."""
        return self._m.nodes()[1]

    @property
    def node_sets(self) -> Dict[str, _np.ndarray]:
        """Node sets by name."""
        return self._m.node_sets()

    @property
    def element_sets(self) -> Dict[str, _np.ndarray]:
        """Element sets by name (decks)."""
        return self._m.element_sets()

    @property
    def couplings(self) -> List[Dict[str, Any]]:
        """Couplings: ``name``, ``kind``, ``point`` (reference node), ``nodes``."""
        return self._m.couplings()

    @property
    def fixed(self) -> _np.ndarray:
        """DOFs held by boundary conditions, ``(k, 2)`` as ``dofs``."""
        return self._m.fixed()

    @property
    def warnings(self) -> List[str]:
        """What reading the model noted and warned, as the command line prints it."""
        return self._m.warnings

    @property
    def default_interface(self) -> Optional[Tuple[_np.ndarray, str]]:
        """The interface a reduction takes when none is given, ``(dofs, where
        it comes from)``, or ``None``."""
        return self._m.default_interface()

    def __len__(self) -> int:
        return self._m.dof_count

    def __repr__(self) -> str:
        return repr(self._m)

    # -- jobs -------------------------------------------------------------

    def modes(self, count: Optional[int] = None, fmax: Optional[float] = None) -> Modes:
        """The lowest ``count`` modes (10 by default), every mode below
        ``fmax`` Hz, or the lowest ``count`` below ``fmax``: what ``flexbody
        modes`` computes."""
        values, hz, shapes, residuals, mechanism = self._m.modes(count, fmax)
        return Modes(values, hz, shapes, residuals, mechanism)

    def reduce(
        self,
        method: str,
        interface: Union[None, str, Sequence[Union[int, str]], _np.ndarray] = None,
        modes: Optional[int] = None,
        fmax: Optional[float] = None,
        orthonormalize: bool = False,
    ) -> Body:
        """A reduced body, as ``flexbody reduce`` makes it.

        ``method``: ``free``, ``craig-bampton``, ``elastic-residual``,
        ``free-residual`` or ``guyan``. ``modes``: the eigenmodes e as the
        method counts them (for ``free`` the total r); or ``fmax``: every
        eigenmode below it (Hz). ``interface``: node sets and node numbers
        (a comma-separated string or a list; all DOFs of each node), or an
        ``(k, 2)`` array of DOFs; by default the model file's interface or
        the reference nodes of the model's couplings.
        ``orthonormalize`` rotates the basis so that ``M_red = I`` and
        ``K_red`` is diagonal."""
        names = dofs = None
        if interface is None:
            pass
        elif isinstance(interface, str):
            names = interface
        elif isinstance(interface, _np.ndarray) and interface.ndim == 2:
            dofs = _dof_array(interface)
        else:
            items = list(interface)
            if items and all(isinstance(i, (tuple, list)) for i in items):
                dofs = _dof_array(items)
            else:
                names = ",".join(str(i) for i in items)
        return self._m.reduce(method, names, dofs, modes, fmax, orthonormalize)

    def study(self) -> StudyResult:
        """The study of a model file's ``[study]`` table: every method and
        mode count against the full model (``flexbody study``)."""
        doc = _json.loads(self._m.study_json())
        return StudyResult(doc["cases"], doc["failed"])


def read(
    path: PathLike,
    mass: Optional[PathLike] = None,
    dofs: Optional[PathLike] = None,
    coords: Optional[PathLike] = None,
    allow_unknown: bool = False,
) -> Model:
    """Reads a model: a model file (``.toml``), a CalculiX/Abaqus deck
    (``.inp``), CalculiX's matrices (``job.sti`` with ``job.mas`` and
    ``job.dof``) or a Matrix Market stiffness (``.mtx``, with ``mass`` and
    ``dofs`` files). ``coords`` gives node coordinates to matrices;
    ``allow_unknown`` skips unknown deck keywords (listed in ``warnings``)."""
    def opt(p):
        return None if p is None else _os.fspath(p)

    return Model(_flexbody.read(_os.fspath(path), opt(mass), opt(dofs), opt(coords), allow_unknown))


def load(path: PathLike) -> Union[Body, Sid]:
    """Reads a body file: a JSON body or a Matrix Market folder gives a
    :class:`Body` (its basis, reduced matrices, interface), a SID file (any
    dialect) a :class:`Sid`."""
    return _flexbody.load(_os.fspath(path))
