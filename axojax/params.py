"""The parameter pytree: every traced, dimensionless quantity of a model.

``Params`` is an equinox Module, so it is a pytree: ``jax.vmap`` over a batch of
parameters, ``jax.grad`` with respect to any field, ``optax`` updates on it. Every
field is dimensionless (docs/model.md section 1); :class:`axojax.Units` converts from
physical values.
"""

from __future__ import annotations

import math
import re
from typing import Any

import equinox as eqx
import jax
import numpy as np
from jaxtyping import ArrayLike

MAX_MAGNITUDE = 1e9
"""Largest accepted |value| of every parameter. Beyond it float64 eigenvalues lose their
digits (tests/house/test_hostile_input.py: ks or kl = 1e10 already moves the seven-filament dominant
eigenvalue by 1e-8 relative to scipy's, cl = 1e12 gives NaN; p, gamma = 1e300 overflow),
so larger values are refused instead of answered wrongly."""
MIN_RATIO = 1e-9
"""Smallest accepted ``out_of_plane`` and ``imbalance`` (stiffness and force ratios: their
reciprocals are bounded by :data:`MAX_MAGNITUDE` too)."""

DEFAULT_CUBIC = 10.0
"""Default cubic stiffening kappa of the links (1/L^2; the nonlinear beat's only extra
constant, used by the time integrator, the limit cycles and their fits): at p = 1.04 p_c
of the seven-filament preset it saturates the beat at a tip amplitude of about 3 um (a
quarter of L; see tests/dynamics/test_simulate.py)."""

PARAM_NAMES = (
    "p",
    "ks",
    "kl",
    "cl",
    "gamma",
    "ktheta",
    "out_of_plane",
    "inactive_factor",
    "imbalance",
    "a0",
    "chi_re",
    "chi_im",
    "beta_re",
    "beta_im",
    "normal_re",
    "normal_im",
    "omega0",
    "kb",
    "xib",
    "m0",
)
BASAL_NAMES = ("kb", "xib")
"""The basal compliance (docs/model.md section 8, bases): used only by a model whose
base has ``compliance=True``."""
CB_FLOOR = 1.0 / MAX_MAGNITUDE
"""``cb = 0`` sets ``kb = 1 / CB_FLOOR``, the stiffest spring :data:`MAX_MAGNITUDE` allows."""
DERIVED_NAMES = ("cb",)
"""Names that set a field through a map, taken by :meth:`Params.replace`,
:meth:`Params.value_of` and fits like a field's: ``cb``, the basal compliance 1/k_b
(dimensionless EI / (k_b L^3)), sets ``kb = 1 / (cb + CB_FLOOR)``. ``cb = 0`` is a rigid
base: the base without compliance, inside a fit's range (issue 45's nested hypotheses;
the spring of 1e9 moves the eigenvalues by about 1e-9 of chi / kb's scale, far below any
fit's tolerance: tests/comparison/test_nested.py)."""
MECHANISM_NAMES = ("chi_re", "chi_im", "beta_re", "beta_im", "normal_re", "normal_im", "omega0")
"""The regulated-dynein coefficients (docs/model.md section 8); all 0 is the steady load."""
KNOT_NAMES = ("ei_knots", "drag_knots", "p_knots")
"""The non-uniform profiles (docs/model.md section 8): relative values at knots along x,
arrays whose last axis holds the K knots; None (default) is uniform."""
DYNAMIC_NAMES = ("chi_im", "beta_im", "normal_im")
"""The coefficients that act through d/dt (chi''/omega0, beta''/omega0, g''/omega0): non-zero
only with omega0 > 0."""
NORMAL_NAMES = ("normal_re", "normal_im")
"""The normal-force gain g = g' + i g'' (docs/model.md section 8): non-zero only through
:func:`axojax.assembly.normal_force.assemble_normal` (its own unknowns, the pairs'
regulated forces)."""

_KNOT_ELEMENT = re.compile(r"^(ei_knots|drag_knots|p_knots)\[(\d+)\]$")


def knot_element(name: str) -> tuple[str, int] | None:
    """``"ei_knots[2]"`` -> ``("ei_knots", 2)``: one knot value of a profile, a name that
    fits and :meth:`Params.replace` take like a field's; None for any other name."""
    m = _KNOT_ELEMENT.match(name) if isinstance(name, str) else None
    return None if m is None else (m.group(1), int(m.group(2)))


def is_parameter_name(name: str) -> bool:
    """A field of :class:`Params` (:data:`PARAM_NAMES`, :data:`KNOT_NAMES`) or one knot
    value (``"ei_knots[2]"``)."""
    return (
        name in PARAM_NAMES
        or name in KNOT_NAMES
        or name in DERIVED_NAMES
        or knot_element(name) is not None
    )


# (lower bound, inclusive?) of each field; gamma is unbounded below.
_BOUNDS = {
    "p": (0.0, True),
    "ks": (0.0, True),
    "kl": (0.0, True),
    "cl": (0.0, True),
    "ktheta": (0.0, True),
    "out_of_plane": (MIN_RATIO, True),
    "inactive_factor": (0.0, True),
    "imbalance": (MIN_RATIO, True),
    "a0": (0.0, True),
    "omega0": (0.0, True),
    "kb": (0.0, True),
    "xib": (0.0, True),
}


class Params(eqx.Module):
    """Dimensionless model parameters (defaults: paper figure 7, docs/model.md section 6).

    Attributes:
        p: dynein force per length on each active pair, p_dim L^3 / EI (for ``beck``,
            the tip load P L^2 / EI).
        ks: radial-spoke stiffness per length, k_dim L^4 / EI.
        kl: inter-doublet (nexin) link stiffness per length, k_dim L^4 / EI.
        cl: damping of every link and spoke, c_dim / c_n.
        gamma: dynein moment gain (paper section 2.3.1).
        ktheta: tangent-angle coupling, k_theta_dim L^2 / EI.
        out_of_plane: ratio of z- to y-bending stiffness (paper: 2).
        inactive_factor: stiffness factor of ring links that are not active pairs.
        imbalance: force ratio R of active group 0 to group 1, read as the model says
            (:attr:`axojax.models.Model.imbalance_kind`: by default a static couple
            p a0 (1 - 1/R) with balanced forces; "force": group 1 carries p / R).
        a0: dynein arm spacing / L: the static moment p a0 (the load b) and the lever arm
            of the regulated dynein force below.
        chi_re, chi_im: sliding control chi = chi' + i chi'' (docs/model.md, regulated
            dynein): the motor force per length responds to the pair's sliding Delta_a as
            chi' Delta_a + (chi''/omega0) dDelta_a/dt; dimensionless chi_dim L^4 / EI
            (:meth:`axojax.Units.chi_from_pn_per_um2`). chi' > 0 is a passive shear
            stiffness (stabilises). 0 (default): no sliding control.
        beta_re, beta_im: curvature control beta = beta' + i beta'': the motor force
            responds to the pair's curvature kappa_a as beta' kappa_a + (beta''/omega0)
            dkappa_a/dt; dimensionless beta_dim L^2 / EI
            (:meth:`axojax.Units.beta_from_pn`). 0 (default): no curvature control.
        normal_re, normal_im: normal-force control g = g' + i g'' (dimensionless; docs/model.md
            section 8): the motor force per length of each active pair responds to its
            normal force N_a = kappa_a,0 F_a + F_a,0 kappa_a about the static state (F_a the
            pair's integrated regulated force, kappa_a its curvature) as g' N_a +
            (g''/omega0) dN_a/dt. It needs its own unknowns (the pairs' forces): only
            :func:`axojax.assembly.normal_force.assemble_normal` and what is built on it
            take it (:func:`axojax.assemble` refuses a non-zero g). 0 (default): none.
        omega0: angular frequency at which chi and beta hold, omega0_dim tau (the observed
            beat's; :meth:`axojax.Units.omega0_from_hz`): at lambda = i omega0 the terms
            equal chi and beta exactly. Must be > 0 when chi_im or beta_im is non-zero;
            unused otherwise (default 0).
        kb, xib: basal compliance (docs/model.md section 8, bases): the basal sliding
            Delta_b,a of each active pair is resisted by kb Delta_b + xib dDelta_b/dt
            (chi_b = kb + i omega xib); dimensionless k_b L^3 / EI and xi_b / (c_n L)
            (:meth:`axojax.Units.kb_from_pn_per_um`, :meth:`axojax.Units.xib_from_pn_s_per_um`).
            Used only when the model's base has ``compliance=True``; then xib must be
            > 0 (:func:`axojax.assembly.check_base_params`; defaults 0).
        m0: static dynein moment per length (docs/model.md section 8, static moment): a
            constant net couple m0 on the cross-section, along the beat direction of
            active group 0 (the direction of the couple p a0 (1 - 1/R) of an imbalance
            R > 1), in the static load b; dimensionless m0_dim L^2 / EI with m0_dim in pN
            (pN um per um; :meth:`axojax.Units.moment_from_pn`). The static bend of an
            asymmetric regulated beat (p = 0, where the imbalance has nothing to act
            on). Either sign; 0 (default): none. A model without active pairs ignores it.
        ei_knots, drag_knots, p_knots: non-uniform bending stiffness EI(x), fluid drag
            c(x) and dynein force p(x) (docs/model.md section 8), each as relative values
            (1 = uniform; dimensionless multipliers of the filaments' EI, of their drag and
            of p) at K >= 2 knots along x, linear between them; shape (..., K), the
            batch axes first like every other field. The knots are the model's
            (:meth:`axojax.models.Model.with_knots`), K equally spaced ones from 0 to 1 when
            it has none. None (default): uniform. Traced and differentiable like the
            scalars; p_knots scales the steady load only (the regulated coefficients stay
            uniform).
    """

    p: ArrayLike = 300.0
    ks: ArrayLike = 1e6
    kl: ArrayLike = 1e3
    cl: ArrayLike = 1 / 200
    gamma: ArrayLike = 0.0
    ktheta: ArrayLike = 0.0
    out_of_plane: ArrayLike = 2.0
    inactive_factor: ArrayLike = 10.0
    imbalance: ArrayLike = 1.0
    a0: ArrayLike = 0.2 / 12
    chi_re: ArrayLike = 0.0
    chi_im: ArrayLike = 0.0
    beta_re: ArrayLike = 0.0
    beta_im: ArrayLike = 0.0
    normal_re: ArrayLike = 0.0
    normal_im: ArrayLike = 0.0
    omega0: ArrayLike = 0.0
    kb: ArrayLike = 0.0
    xib: ArrayLike = 0.0
    m0: ArrayLike = 0.0
    ei_knots: ArrayLike | None = None
    drag_knots: ArrayLike | None = None
    p_knots: ArrayLike | None = None

    def replace(self, **changes: Any) -> "Params":
        """A copy with some fields changed (unknown names raise ``ValueError``); a knot
        value ``"ei_knots[2]"`` sets one value of a profile that is set."""
        bad = sorted(k for k in changes if not is_parameter_name(k))
        if bad:
            raise ValueError(
                f"unknown parameter(s) {bad}; known: {', '.join(PARAM_NAMES + KNOT_NAMES)} and "
                "knot values such as ei_knots[0]"
            )
        out = self
        for k, v in changes.items():
            if k == "cb":
                k, v = "kb", 1.0 / (v + CB_FLOOR)
            element = knot_element(k)
            if element is not None:
                field, index = element
                values = out._knot_array(field, index)
                v = values.at[..., index].set(v)
                k = field
            out = eqx.tree_at(lambda prm, k=k: getattr(prm, k), out, v, is_leaf=_is_none)
        return out

    def _knot_array(self, field: str, index: int):
        import jax.numpy as jnp

        values = self.knot_values(field)
        if values is None or index >= np.shape(values)[-1]:
            n = 0 if values is None else np.shape(values)[-1]
            raise ValueError(
                f"parameter {field}[{index}]: {field} has {n} knot values; set the profile first (Params({field}=...))"
            )
        return jnp.asarray(values, dtype=float)

    def value_of(self, name: str) -> Any:
        """The value of a field, of one knot value (``"ei_knots[2]"``) or of a derived
        name (:data:`DERIVED_NAMES`: ``cb = 1 / kb - CB_FLOOR``, inf for kb = 0)."""
        if name == "cb":
            kb = np.asarray(self.kb, dtype=float) if not isinstance(self.kb, jax.Array) else self.kb
            with np.errstate(divide="ignore"):
                return 1.0 / kb - CB_FLOOR
        element = knot_element(name)
        if element is None:
            return getattr(self, name)
        field, index = element
        return self._knot_array(field, index)[..., index]

    def with_values(self, values: dict[str, Any], kl_ratio: Any = None) -> "Params":
        """A copy with ``values`` set; with ``kl_ratio`` R, kl is tied to ks / R (after
        the values are set, so a swept or fitted ks carries kl along)."""
        out = self.replace(**values)
        if kl_ratio is not None:
            out = out.replace(kl=out.ks / kl_ratio)
        return out

    def broadcast(self, shape: tuple[int, ...] | None = None) -> "Params":
        """Every field as a float64 array of a common ``shape`` (default: the broadcast
        of the fields' shapes; knot profiles, :data:`KNOT_NAMES`, get ``shape + (K,)``),
        ready for ``jax.vmap`` over the leading axis."""
        import jax.numpy as jnp

        leaves = [jnp.asarray(getattr(self, k), dtype=float) for k in PARAM_NAMES]
        knots = {k: self.knot_values(k) for k in KNOT_NAMES}
        knots = {k: jnp.asarray(v, dtype=float) for k, v in knots.items() if v is not None}
        if shape is None:
            shape = jnp.broadcast_shapes(
                *(x.shape for x in leaves), *(v.shape[:-1] for v in knots.values())
            )
        out = {k: jnp.broadcast_to(x, shape) for k, x in zip(PARAM_NAMES, leaves)}
        out.update({k: jnp.broadcast_to(v, tuple(shape) + v.shape[-1:]) for k, v in knots.items()})
        return Params(**out)

    def as_dict(self) -> dict[str, Any]:
        """The scalar fields (:data:`PARAM_NAMES`) by name; see :meth:`knot_dict`."""
        return {k: getattr(self, k) for k in PARAM_NAMES}

    def knot_dict(self) -> dict[str, Any]:
        """The knot profiles that are set (:data:`KNOT_NAMES`), by name."""
        return {k: getattr(self, k) for k in KNOT_NAMES if getattr(self, k) is not None}

    def knot_values(self, name: str) -> Any:
        """The knot profile ``name`` (None when uniform); a one-line ``ValueError`` when
        it has fewer than 2 knots (its last axis)."""
        value = getattr(self, name)
        if value is None:
            return None
        shape = np.shape(value)
        if len(shape) < 1 or shape[-1] < 2:
            raise ValueError(
                f"parameter {name} needs values at K >= 2 knots (its last axis), got shape {shape}"
            )
        return value

    def validate(self) -> "Params":
        """Check concrete values; raise a one-line ``ValueError`` naming the bad one.

        Limits: every value finite with ``|value| <=`` :data:`MAX_MAGNITUDE` (1e9);
        ``p, ks, kl, cl, ktheta, inactive_factor, a0 >= 0``; ``out_of_plane, imbalance >=``
        :data:`MIN_RATIO` (1e-9); gamma of either sign. Traced values (inside
        ``jit``/``vmap``) are not checked here (see :func:`axojax.eigen.mode.dominant_mode`
        for what happens to them). Returns ``self``.
        """
        for name in PARAM_NAMES:
            value = getattr(self, name)
            if isinstance(value, jax.core.Tracer):
                continue
            try:
                arr = np.asarray(value, dtype=float)
            except (TypeError, ValueError):
                raise ValueError(f"parameter {name} must be a number, got {value!r}") from None
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"parameter {name} must be finite, got {_show(value)}")
            if name in _BOUNDS:
                low, inclusive = _BOUNDS[name]
                ok = np.all(arr >= low) if inclusive else np.all(arr > low)
                if not bool(ok):
                    rel = ">=" if inclusive else ">"
                    raise ValueError(f"parameter {name} must be {rel} {low:g}, got {_show(value)}")
            if not bool(np.all(np.abs(arr) <= MAX_MAGNITUDE)):
                raise ValueError(
                    f"parameter {name} must be at most {MAX_MAGNITUDE:g} in magnitude (float64 "
                    f"loses the answer beyond), got {_show(value)}"
                )
        for name in KNOT_NAMES:
            value = self.knot_values(name)
            if value is None or isinstance(value, jax.core.Tracer):
                continue
            arr = np.asarray(value, dtype=float)
            if not (np.all(np.isfinite(arr)) and np.all(arr >= 0) and np.all(arr <= MAX_MAGNITUDE)):
                raise ValueError(
                    f"parameter {name} must be finite, >= 0 and at most {MAX_MAGNITUDE:g} at "
                    f"every knot, got {arr.tolist()!r}"
                )
        if not isinstance(self.omega0, jax.core.Tracer):
            for name in DYNAMIC_NAMES:
                value = getattr(self, name)
                if isinstance(value, jax.core.Tracer):
                    continue
                dynamic = np.asarray(value, dtype=float) != 0
                if bool(np.any(dynamic & (np.asarray(self.omega0, dtype=float) <= 0))):
                    raise ValueError(
                        f"parameter omega0 must be > 0 when {name} is non-zero (it is "
                        f"{_show(value)}), got {_show(self.omega0)}"
                    )
        return self


def valid(params: Params) -> Any:
    """Whether every value of ``params`` is within :meth:`Params.validate`'s limits, as a
    (traceable) boolean array of the parameters' broadcast shape: what ``jit``-ed code
    uses in place of the check it cannot make (:mod:`axojax.results`)."""
    import jax.numpy as jnp

    ok = jnp.asarray(True)
    for name in PARAM_NAMES:
        x = jnp.asarray(getattr(params, name), dtype=float)
        good = jnp.isfinite(x) & (jnp.abs(x) <= MAX_MAGNITUDE)
        if name in _BOUNDS:
            low, inclusive = _BOUNDS[name]
            good = good & ((x >= low) if inclusive else (x > low))
        ok = ok & good
    omega0 = jnp.asarray(params.omega0, dtype=float)
    for name in DYNAMIC_NAMES:
        ok = ok & ((jnp.asarray(getattr(params, name), dtype=float) == 0) | (omega0 > 0))
    for name in KNOT_NAMES:
        value = params.knot_values(name)
        if value is not None:
            x = jnp.asarray(value, dtype=float)
            ok = ok & jnp.all(jnp.isfinite(x) & (x >= 0) & (x <= MAX_MAGNITUDE), axis=-1)
    return ok


def require_scalars(params: Params, what: str) -> None:
    """Raise a one-line ``ValueError`` naming ``jax.vmap`` when a field is not a scalar
    (``what`` names the function): array-valued ``Params`` are batches, to be mapped."""
    knots = {k: np.shape(v)[:-1] for k, v in params.knot_dict().items()}
    for name in PARAM_NAMES + tuple(knots):
        shape = knots[name] if name in knots else np.shape(getattr(params, name))
        if shape != ():
            raise ValueError(
                f"{what} takes one parameter point, but {name} has shape {shape}: map over a batch of Params "
                f"with jax.vmap (e.g. jax.vmap(lambda prm: {what}(model, prm))(params)), or use ax.sweep for a grid"
            )


def _is_none(x: Any) -> bool:
    return x is None


def _show(value: Any) -> str:
    try:
        f = float(value)
        return f"{f:g}" if math.isfinite(f) else str(f)
    except (TypeError, ValueError):
        return repr(value)
