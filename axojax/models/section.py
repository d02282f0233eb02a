"""Cross-sections and models: the static structure of an axoneme model.

A :class:`CrossSection` says where the filaments sit, how they are linked and which
pairs carry dynein. A :class:`Model` adds the mesh and the filament-level matrices, and
precomputes the small "truss" matrices over (filament, direction) pairs that the
assembly Kronecker-multiplies with filament-level matrices (docs/model.md sections 2-3).
Nothing here is traced: a model is built once with numpy and is hashed by value (its
arrays' bytes, see :meth:`Model.__hash__`), so it can be a static argument of
``jax.jit``, and two models built alike (``ax.models.seven()`` called twice) share their
compiled programs.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from ..fem import FilamentMatrices, Mesh, Profiles, filament_matrices, make_mesh
from ..fem.hermite import interpolation_matrix
from ..fem.knots import check_knots, equally_spaced
from .base import Base, as_base

LinkKind = Literal["spoke", "link"]
LoadKind = Literal["pairs", "distributed", "tip"]
LOADS = ("pairs", "distributed", "tip")
KINDS = ("spoke", "link")
ImbalanceKind = Literal["moment", "force"]
IMBALANCE_KINDS = ("moment", "force")
DEFAULT_IMBALANCE_KIND: ImbalanceKind = "moment"
"""The paper's reading (section 3.7.1: "a constant distributed moment"; docs/model.md
section 3, asymmetric beats): fig. 12 is reproduced with it."""


@dataclasses.dataclass(frozen=True)
class Link:
    """A distributed elastic/viscous link between filaments ``i`` and ``j``.

    ``kind="spoke"`` takes stiffness k_s; ``kind="link"`` takes k_l, times
    ``inactive_factor`` when (i, j) is not an active pair.
    """

    i: int
    j: int
    kind: LinkKind = "link"


@dataclasses.dataclass(frozen=True)
class ActivePair:
    """Dynein between ``i`` (pulled baseward) and ``j`` (pulled tipward).

    ``group`` 0 carries force p, group 1 carries p / imbalance (``Params.imbalance``)
    in the *force* reading of the imbalance; in the *moment* reading (the default) both
    carry p and the imbalance is a static couple only (:attr:`Model.imbalance_kind`).
    """

    i: int
    j: int
    group: int = 0


@dataclasses.dataclass(frozen=True, eq=False)
class CrossSection:
    """Filament layout of a model.

    Attributes:
        name: label used in outputs.
        positions: (F, 2) cross-section positions (y, z), y = beat-plane direction.
            Only the directions between linked filaments matter; units are arbitrary.
        links: the elastic/viscous links.
        active_pairs: the dynein-loaded pairs.
        n_dirs: transverse directions, 1 (planar, y only) or 2 (y and z).
        ei: (F,) relative flexural rigidity of each filament (1 = EI of the unit).
        drag: (F,) relative resistive coefficient of each filament (1 = c_n).
        load: "pairs" (balanced dynein on active pairs), "distributed" (unbalanced
            distributed follower load on every filament, the ``single`` preset) or
            "tip" (Beck's tip follower load on every filament).
    """

    name: str
    positions: ArrayLike
    links: tuple[Link, ...] = ()
    active_pairs: tuple[ActivePair, ...] = ()
    n_dirs: int = 2
    ei: ArrayLike | None = None
    drag: ArrayLike | None = None
    load: LoadKind = "pairs"

    def __post_init__(self) -> None:
        pos = np.array(
            self.positions, dtype=float
        )  # a copy: the model freezes its arrays (Model.__post_init__)
        if pos.ndim == 1:
            pos = np.stack([pos, np.zeros_like(pos)], axis=1)
        if pos.ndim != 2 or pos.shape[1] != 2 or pos.shape[0] < 1:
            raise ValueError(f"positions must have shape (F, 2), got {np.shape(self.positions)}")
        if not np.all(np.isfinite(pos)):
            raise ValueError(f"positions of cross-section {self.name!r} must be finite")
        n = pos.shape[0]
        object.__setattr__(self, "positions", pos)
        for field, default in (("ei", 1.0), ("drag", 1.0)):
            val = getattr(self, field)
            arr = (
                np.full(n, default) if val is None else np.array(val, dtype=float).reshape(-1)
            )  # a copy, as positions
            if arr.shape != (n,):
                raise ValueError(
                    f"{field} must have one value per filament ({n}), got {arr.shape[0]}"
                )
            if not np.all(np.isfinite(arr)) or np.any(arr <= 0):
                raise ValueError(f"{field} must be finite and positive, got {arr.tolist()}")
            object.__setattr__(self, field, arr)
        if not _is_int(self.n_dirs) or self.n_dirs not in (1, 2):
            raise ValueError(
                f"n_dirs (a model file's 'dimensions') must be the integer 1 or 2, got {self.n_dirs!r}"
            )
        if self.load not in LOADS:
            raise ValueError(f"load must be one of {LOADS}, got {self.load!r}")
        links = tuple(l if isinstance(l, Link) else Link(*l) for l in self.links)
        pairs = tuple(a if isinstance(a, ActivePair) else ActivePair(*a) for a in self.active_pairs)
        object.__setattr__(self, "links", links)
        object.__setattr__(self, "active_pairs", pairs)
        for what, items in (("link", links), ("active pair", pairs)):
            for it in items:
                for idx in (it.i, it.j):
                    if (
                        isinstance(idx, bool)
                        or not isinstance(idx, (int, np.integer))
                        or not 0 <= idx < n
                    ):
                        raise ValueError(
                            f"{what} ({it.i}, {it.j}) of {self.name!r} names filament {idx!r}, "
                            f"but filaments are 0..{n - 1}"
                        )
                if it.i == it.j:
                    raise ValueError(
                        f"{what} ({it.i}, {it.j}) of {self.name!r} joins a filament to itself"
                    )
                if self.n_dirs == 2 and np.allclose(pos[it.i], pos[it.j]):
                    raise ValueError(
                        f"{what} ({it.i}, {it.j}) of {self.name!r} joins coincident filaments"
                    )
        for l in links:
            if l.kind not in KINDS:
                raise ValueError(
                    f"link ({l.i}, {l.j}) has kind {l.kind!r}; expected one of {KINDS}"
                )
        for a in pairs:
            if not _is_int(a.group) or a.group not in (0, 1):
                raise ValueError(
                    f"active pair ({a.i}, {a.j}) has group {a.group!r}; expected 0 or 1"
                )
        if self.load == "pairs" and self.n_dirs == 1:
            ys = pos[:, 0]
            for it in links + pairs:
                if ys[it.j] == ys[it.i]:
                    raise ValueError(f"planar link ({it.i}, {it.j}) joins filaments at the same y")

    @property
    def n_filaments(self) -> int:
        return self.positions.shape[0]

    def rotated(self, angle_rad: float) -> "CrossSection":
        """The same cross-section with every position rotated by ``angle_rad``."""
        c, s = math.cos(angle_rad), math.sin(angle_rad)
        rot = np.array([[c, -s], [s, c]])
        return dataclasses.replace(self, positions=self.positions @ rot.T)

    def relabelled(self, order: ArrayLike) -> "CrossSection":
        """The same cross-section with filament ``order[k]`` renamed ``k``."""
        order = list(order)
        new = {old: k for k, old in enumerate(order)}
        return dataclasses.replace(
            self,
            positions=self.positions[order],
            ei=self.ei[order],
            drag=self.drag[order],
            links=tuple(Link(new[l.i], new[l.j], l.kind) for l in self.links),
            active_pairs=tuple(ActivePair(new[a.i], new[a.j], a.group) for a in self.active_pairs),
        )


def _is_int(x) -> bool:
    return isinstance(x, (int, np.integer)) and not isinstance(x, bool)


def _unit(v: np.ndarray, n_dirs: int) -> np.ndarray:
    if n_dirs == 1:
        return np.sign(v[:1])
    return v / np.linalg.norm(v)


@dataclasses.dataclass(frozen=True, eq=False)
class Model:
    """A cross-section discretised on a mesh, with precomputed static truss matrices.

    Unknowns are ordered filament-major, ``q[f, a, r]`` flattened: filament f,
    direction a (0 = y, 1 = z), filament dof r (2 N_e of them). ``n_fd = F * d``.

    Truss arrays (all numpy, static):
        link_B: (E, n_fd) rows B_e (-n_e at i, +n_e at j).
        link_is_spoke, link_is_active: (E,) booleans.
        link_D: (E, n_fd) rows (e_j - e_i) for each direction (tangent-angle coupling),
            stacked as (E * d, n_fd) in ``theta_laplacian``.
        pair_B: (P, n_fd) B_a of each active pair; pair_w: (P, n_fd) w_a (n_a/2 at i, j).
        pair_follow: (P, n_fd, n_fd) the matrices (e_j - e_i)(e_i + e_j)^T / 2 (x) I_d.
        pair_sign: (P, n_fd) -1 at i, +1 at j in every direction (axial force sign).
        pair_group: (P,) 0 or 1.

    Static choice:
        imbalance_kind: how ``Params.imbalance`` R is read (docs/model.md section 3,
            asymmetric beats). ``"moment"`` (default, the paper's reading): every active
            pair carries p, so A and C are the balanced ones, and the static load b gains
            the net couple of an R : 1 force ratio, p a0 (1 - 1/R) per unit length.
            ``"force"``: group 1 carries p / R, which also changes A (K_G, P_follow,
            P_gain); b is the same couple. Set with :meth:`with_imbalance_kind`.
    """

    section: CrossSection
    mesh: Mesh
    matrices: FilamentMatrices
    profiles: Profiles
    link_B: np.ndarray
    link_is_spoke: np.ndarray
    link_is_active: np.ndarray
    theta_laplacian: np.ndarray
    pair_B: np.ndarray
    pair_w: np.ndarray
    pair_follow: np.ndarray
    pair_sign: np.ndarray
    pair_group: np.ndarray
    imbalance_kind: str = (
        DEFAULT_IMBALANCE_KIND  # an ImbalanceKind; any other string is a ValueError (__post_init__)
    )
    base: Base = Base()
    base_matrices: FilamentMatrices | None = None
    knots: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.base, Base):
            raise ValueError(f"base must be an axojax Base, got {self.base!r}")
        if (self.base_matrices is None) != (self.base.kind == "clamped"):
            raise ValueError("base_matrices must be given exactly when the base is not clamped")
        if self.imbalance_kind not in IMBALANCE_KINDS:
            raise ValueError(
                f"imbalance_kind must be one of {', '.join(IMBALANCE_KINDS)}, got {self.imbalance_kind!r}"
            )
        _freeze(self)  # compiled programs hold these values: an edit in place would not reach them

    def _value_key(self) -> tuple:
        """What the model is, as a hashable tuple (computed once): every field, numpy
        arrays by shape, dtype and a digest of their bytes; callables (profiles) by
        identity."""
        key = self.__dict__.get("_key")
        if key is None:
            key = _key_of(self)
            object.__setattr__(self, "_key", key)
        return key

    def __hash__(self) -> int:
        return hash(self._value_key())

    def __getstate__(self) -> dict:
        """Pickled and copied without the cached key (a copy may be edited before it is
        frozen again; profile functions' identities differ in another process)."""
        state = dict(self.__dict__)
        state.pop("_key", None)
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        _freeze(self)

    def __eq__(self, other) -> bool:
        """Equal when built alike (same section, mesh, matrices, profiles and imbalance
        reading): a model is a static argument of ``jax.jit``, and equal models share
        compiled programs."""
        if self is other:
            return True
        if not isinstance(other, Model):
            return NotImplemented
        return self._value_key() == other._value_key()

    def with_imbalance_kind(self, kind: str) -> "Model":
        """The same model with the imbalance read as ``kind`` ("moment" or "force"); a
        new model (unequal to ``self``), ``self`` when unchanged."""
        if kind == self.imbalance_kind:
            return self
        return dataclasses.replace(self, imbalance_kind=kind)

    def with_base(self, base: Base | str) -> "Model":
        """The same model with another base condition (a :class:`Base` or a kind's name:
        ``"clamped"``, ``"pivot"``, ``"free"``, ``"head"``; a head needs its drags, so
        pass a Base); ``self`` when unchanged."""
        base = as_base(base)
        if base == self.base:
            return self
        return dataclasses.replace(
            self, base=base, base_matrices=_base_matrices(self.mesh, self.profiles, base)
        )

    def with_knots(self, knots) -> "Model":
        """The same model with the knots of its non-uniform profiles at ``knots`` (x / L,
        strictly increasing from 0 to 1; ``Params.ei_knots`` etc. must then have one value
        per knot); ``None``: K equally spaced knots for a profile of K values (the
        default). ``self`` when unchanged."""
        knots = None if knots is None else check_knots(knots)
        if knots == self.knots:
            return self
        return dataclasses.replace(self, knots=knots)

    def knot_positions(self, name: str, n_values: int) -> tuple[float, ...]:
        """The knots of a profile of ``n_values`` values (``name`` is its parameter, for
        the one-line ``ValueError`` when the count does not match :attr:`knots`)."""
        if self.knots is None:
            return equally_spaced(n_values)
        if n_values != len(self.knots):
            raise ValueError(
                f"parameter {name} has {n_values} values but the model has {len(self.knots)} "
                f"knots at {list(self.knots)}"
            )
        return self.knots

    def rigid_modes(self) -> np.ndarray:
        """(n_unknowns, r) rigid-body motions the base leaves free, one column per
        direction and motion, built from the node positions: a translation (u = 1) and a
        rotation about x = 0 (u = x, u' = 1) for ``free`` and ``head``, the rotation for
        a ``pivot`` without a spring, none otherwise (r = 0). The basal slidings are 0."""
        kind = self.base.kind
        motions = {"free": ("t", "r"), "head": ("t", "r")}.get(kind, ())
        if kind == "pivot" and self.base.rotational_stiffness == 0:
            motions = ("r",)
        N, F, d = self.n_elements, self.n_filaments, self.n_dirs
        xs = np.arange(1, N + 1) / N
        cols = []
        for a in range(d):
            for motion in motions:
                node = np.zeros((F, d, N, 2))
                base = np.zeros((d, 2))
                if motion == "t":
                    node[:, a, :, 0], base[a, 0] = 1.0, 1.0
                else:
                    node[:, a, :, 0], node[:, a, :, 1], base[a, 1] = xs, 1.0, 1.0
                rest = np.zeros(self.n_border - self.n_base_dofs)
                cols.append(
                    np.concatenate([node.ravel(), base[:, list(self.base.dofs)].ravel(), rest])
                )
        return np.array(cols).T.reshape(self.n_unknowns, len(cols))

    def require_held(self, what: str) -> None:
        """Raise a one-line ``ValueError`` when the base lets the axoneme move rigidly
        (:meth:`rigid_modes`: free, head, a pivot without a spring): for code paths whose
        equations leave a rigid motion undetermined (``what`` names them, e.g.
        "limit_cycle")."""
        if self.rigid_modes().shape[1]:
            raise ValueError(
                f"{what} needs a base that holds the axoneme (clamped, with or without basal "
                f"compliance, or a pivot with a rotational spring); this model's "
                f"{self.base.kind!r} base lets it move rigidly"
            )

    @property
    def n_base_dofs(self) -> int:
        """Node 0's kept unknowns, (direction, dof): the border's first part. Node 0 is
        shared by every filament (a rigid basal body: u_f(0), u_f'(0) are the same for
        all f), so it holds d * len(base.dofs) unknowns."""
        return self.n_dirs * len(self.base.dofs)

    @property
    def n_border(self) -> int:
        """Unknowns after the node unknowns: node 0's kept dofs, then (with basal
        compliance) one basal sliding per active pair; 0 for the clamped base."""
        pairs = self.pair_B.shape[0] if self.base.compliance else 0
        return self.n_base_dofs + pairs

    @property
    def n_unknowns(self) -> int:
        """Length of a state or eigenvector: ``n_dof + n_border``."""
        return self.n_dof + self.n_border

    def interpolation(self, x: ArrayLike, derivative: int = 0) -> np.ndarray:
        """(S, r) matrix from one filament direction's dofs (:meth:`filament_dofs`) to u
        (or its ``derivative``-th x-derivative) at the points ``x`` in [0, 1]: the one
        place that knows which base dofs exist."""
        return interpolation_matrix(
            self.n_elements, np.asarray(x, dtype=float), derivative, self.base.dofs
        )

    def filament_dofs(self, q):
        """(..., F, d, r) per-filament dofs (node 0's kept ones first, then nodes 1..N_e)
        of a state or eigenvector ``q`` (..., n_unknowns) (numpy or jax): the columns of
        :meth:`interpolation`. The basal sliding unknowns are left out."""
        xp = np if isinstance(q, np.ndarray) else _jnp()
        shape = q.shape[:-1]
        F, d = self.n_filaments, self.n_dirs
        nodes = xp.reshape(q[..., : self.n_dof], shape + (F, d, self.mesh.n_dof))
        if not self.base.dofs:
            return nodes
        k = len(self.base.dofs)
        base = xp.reshape(q[..., self.n_dof : self.n_dof + self.n_base_dofs], shape + (1, d, k))
        base = xp.broadcast_to(base, shape + (F, d, k))  # node 0 is shared (n_base_dofs)
        return xp.concatenate([base, nodes], axis=-1)

    @property
    def name(self) -> str:
        return self.section.name

    @property
    def n_filaments(self) -> int:
        return self.section.n_filaments

    @property
    def n_dirs(self) -> int:
        return self.section.n_dirs

    @property
    def n_elements(self) -> int:
        return self.mesh.n_elements

    @property
    def n_fd(self) -> int:
        return self.n_filaments * self.n_dirs

    @property
    def n_dof(self) -> int:
        """Total unknowns, F * d * 2 N_e."""
        return self.n_fd * self.mesh.n_dof

    def __repr__(self) -> str:
        return (
            f"Model({self.name!r}, filaments={self.n_filaments}, dirs={self.n_dirs}, "
            f"elements={self.n_elements}, n_dof={self.n_dof}, load={self.section.load!r}"
            + (
                f", imbalance_kind={self.imbalance_kind!r}"
                if self.imbalance_kind != DEFAULT_IMBALANCE_KIND
                else ""
            )
            + (f", base={self.base!r}" if self.base != Base() else "")
            + (f", knots={list(self.knots)})" if self.knots is not None else ")")
        )


def _jnp():
    import jax.numpy as jnp

    return jnp


def _base_matrices(mesh: Mesh, profiles: Profiles, base: Base) -> FilamentMatrices | None:
    """Filament-level matrices with node 0's kept dofs first (None for a clamped base)."""
    if not base.dofs:
        return None
    n_per = len(mesh.x) // mesh.n_elements
    return filament_matrices(make_mesh(mesh.n_elements, n_per, base.dofs), profiles)


def _freeze(obj) -> None:
    """Make every numpy array of a model (and of its section, mesh and matrices) read-only."""
    if isinstance(obj, np.ndarray):
        obj.flags.writeable = False
    elif dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        for f in dataclasses.fields(obj):
            _freeze(getattr(obj, f.name))
    elif isinstance(obj, (tuple, list)):
        for x in obj:
            _freeze(x)


def _key_of(obj) -> object:
    """A hashable stand-in for ``obj`` that is equal exactly when ``obj``'s values are
    (see :meth:`Model._value_key`)."""
    if isinstance(obj, np.ndarray):
        return (
            "array",
            obj.shape,
            obj.dtype.str,
            hashlib.blake2b(obj.tobytes(), digest_size=16).digest(),
        )
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return (type(obj).__qualname__,) + tuple(
            (f.name, _key_of(getattr(obj, f.name))) for f in dataclasses.fields(obj)
        )
    if isinstance(obj, (tuple, list)):
        return (type(obj).__name__,) + tuple(_key_of(x) for x in obj)
    if obj is None or isinstance(obj, (str, int, float, bool, complex, np.generic)):
        return obj
    return ("id", id(obj))  # a profile function: by identity (the model keeps it alive)


def build_model(
    section: CrossSection,
    n_elements: int = 10,
    profiles: Profiles = Profiles(),
    imbalance_kind: str = DEFAULT_IMBALANCE_KIND,
    base: Base | str = "clamped",
) -> Model:
    """Discretise ``section`` with ``n_elements`` cubic Hermite elements per filament
    (``imbalance_kind``, ``base``: see :class:`Model`)."""
    base = as_base(base)
    mesh = make_mesh(n_elements)
    mats = filament_matrices(mesh, profiles)
    F, d = section.n_filaments, section.n_dirs
    nfd = F * d
    pos = section.positions

    def dirvec(i: int, j: int) -> np.ndarray:
        return _unit(pos[j] - pos[i], d)

    def spread(values_i: np.ndarray, i: int, values_j: np.ndarray, j: int) -> np.ndarray:
        row = np.zeros((F, d))
        row[i] += values_i
        row[j] += values_j
        return row.ravel()

    active = {frozenset((a.i, a.j)) for a in section.active_pairs}
    link_B = np.array(
        [spread(-dirvec(l.i, l.j), l.i, dirvec(l.i, l.j), l.j) for l in section.links]
    ).reshape(-1, nfd)
    is_spoke = np.array([l.kind == "spoke" for l in section.links], dtype=bool)
    is_active = np.array([frozenset((l.i, l.j)) in active for l in section.links], dtype=bool)
    eye_d = np.eye(d)
    lap = np.zeros((nfd, nfd))
    for l in section.links:
        diff = np.zeros(F)
        diff[l.j], diff[l.i] = 1.0, -1.0
        lap += np.kron(np.outer(diff, diff), eye_d)

    pair_B, pair_w, pair_follow, pair_sign = [], [], [], []
    for a in section.active_pairs:
        n = dirvec(a.i, a.j)
        pair_B.append(spread(-n, a.i, n, a.j))
        pair_w.append(spread(n / 2, a.i, n / 2, a.j))
        e_i, e_j = np.eye(F)[a.i], np.eye(F)[a.j]
        pair_follow.append(np.kron(np.outer(e_j - e_i, e_i + e_j) / 2, eye_d))
        pair_sign.append(spread(-np.ones(d), a.i, np.ones(d), a.j))
    P = len(section.active_pairs)
    return Model(
        section=section,
        mesh=mesh,
        matrices=mats,
        profiles=profiles,
        link_B=link_B,
        link_is_spoke=is_spoke,
        link_is_active=is_active,
        theta_laplacian=lap,
        pair_B=np.array(pair_B).reshape(P, nfd),
        pair_w=np.array(pair_w).reshape(P, nfd),
        pair_follow=np.array(pair_follow).reshape(P, nfd, nfd),
        pair_sign=np.array(pair_sign).reshape(P, nfd),
        pair_group=np.array([a.group for a in section.active_pairs], dtype=int),
        imbalance_kind=imbalance_kind,
    ).with_base(base)
