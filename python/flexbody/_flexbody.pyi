"""Type stubs of flexbody's Rust extension (python/src). Use the package
`flexbody`, which wraps these with scipy.sparse matrices."""

from typing import Any, Dict, List, Optional, Tuple

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]
I64 = npt.NDArray[np.int64]
CscParts = Tuple[I64, I64, F64, int]

class Error(ValueError):
    """An input or request flexbody cannot use; the message names the
    file, line, node, DOF or set."""

class Model:
    @property
    def path(self) -> str: ...
    @property
    def dof_count(self) -> int: ...
    @property
    def dofs(self) -> I64: ...
    @property
    def warnings(self) -> List[str]: ...
    def stiffness_csc(self) -> CscParts: ...
    def mass_csc(self) -> CscParts: ...
    def damping_csc(self) -> Optional[CscParts]: ...
    def nodes(self) -> Tuple[I64, F64]: ...
    def node_sets(self) -> Dict[str, I64]: ...
    def element_sets(self) -> Dict[str, I64]: ...
    def couplings(self) -> List[Dict[str, Any]]: ...
    def fixed(self) -> I64: ...
    def default_interface(self) -> Optional[Tuple[I64, str]]: ...
    def modes(
        self, count: Optional[int] = None, fmax: Optional[float] = None
    ) -> Tuple[F64, F64, F64, F64, Optional[str]]: ...
    def reduce(
        self,
        method: str,
        interface: Optional[str] = None,
        interface_dofs: Optional[I64] = None,
        modes: Optional[int] = None,
        fmax: Optional[float] = None,
        orthonormalize: bool = False,
    ) -> Body: ...
    def study_json(self) -> str: ...

class Body:
    """A reduced flexible body u = T q."""

    @property
    def method(self) -> str: ...
    @property
    def r(self) -> int: ...
    @property
    def dofs(self) -> I64:
        """The DOF of each row of the basis, (n, 2): node id, 1..6."""
    @property
    def basis(self) -> F64:
        """T (n x r), Fortran order."""
    @property
    def mass(self) -> F64:
        """M_red = T^T M T (r x r)."""
    @property
    def stiffness(self) -> F64:
        """K_red = T^T K T (r x r)."""
    @property
    def damping(self) -> Optional[F64]:
        """D_red = T^T D T (r x r), or None."""
    @property
    def mode_kinds(self) -> List[str]:
        """What each column of T is: "rigid ux", "constraint node 3 uz", "eigen 12.5 Hz", ..."""
    @property
    def interface(self) -> I64:
        """The interface DOFs, (k, 2)."""
    @property
    def interface_source(self) -> Optional[str]:
        """Where a default interface came from, else None."""
    @property
    def interface_rows(self) -> F64:
        """The interface rows of T (k x r)."""
    def frequencies_hz(self) -> F64:
        """Natural frequencies of K_red, M_red (Hz), lowest first."""
    def nodes(self) -> Tuple[I64, F64]:
        """Node ids and coordinates (k, 3)."""
    def invariants(self) -> Dict[str, Any]:
        """The floating-frame description (the SID's content); needs the
        model the body was reduced from."""
    def recovery(self) -> F64:
        """Stress (solids; shells per surface) or section-force (beams) rows
        over q; needs the mesh."""
    def write(self, path: str, format: str = "json") -> None:
        """Writes json, sid, mtx (a folder) or mbdyn, atomically."""

class Sid:
    """A SID file's floating-frame description."""

    @property
    def dialect(self) -> str: ...
    @property
    def mass(self) -> float: ...
    @property
    def coordinates(self) -> List[str]: ...
    def term(self, name: str) -> Tuple[F64, List[F64]]:
        """A Taylor term (mdcm, j, ct, cr, me, gr, ge, oe, ksigma, ke, de) as (m0, [m1_k])."""
    def nodes(self) -> List[Dict[str, Any]]: ...

def read(
    path: str,
    mass: Optional[str] = None,
    dofs: Optional[str] = None,
    coords: Optional[str] = None,
    allow_unknown: bool = False,
) -> Model: ...
def from_matrices(
    n: int,
    k: Tuple[I64, I64, F64],
    m: Tuple[I64, I64, F64],
    dofs: I64,
    node_ids: Optional[I64] = None,
    coords: Optional[F64] = None,
    d: Optional[Tuple[I64, I64, F64]] = None,
) -> Model: ...
def load(path: str) -> Any: ...
