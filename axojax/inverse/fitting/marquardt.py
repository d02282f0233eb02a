"""Levenberg-Marquardt for fits through a periodic orbit: a statistical stopping rule,
a trust region that widens, and unknowns scaled by their Jacobian's columns.

Why (issue 54 item 3): a whole-beat fit of a real recording (a model that cannot
reproduce the beat to its noise) ran into optimistix's step limit every time, at an
optimum it had already reached. Traced on a Chlamydomonas stand-in
(docs/fitting.md, "Convergence of whole-beat fits"):

- the unknowns' scales differ by four decades in the logistic coordinate z (a static
  moment bounded by +-10^4, a saturation force on a log scale): the first fifteen steps
  were rejected while the damping grew from 1 to 10^9;
- in the flat valley of the saturation force (chi^2 falling by 10^-3 per step) the
  trust region never widened (optimistix's default widens only where the quadratic model
  predicts the reduction to 1 %) and the Cauchy test (the step below 10^-5 of z) never
  held: 25 steps crept along a valley whose whole depth was 0.02 in chi^2.

:class:`StatisticalLevenbergMarquardt` is optimistix's Levenberg-Marquardt (damped Newton
descent, classical trust region) with the trust region widened where the model predicts
the reduction to 25 % (Moré's 0.75 cut-off instead of 0.99) and one more way to stop:
when the Gauss-Newton step from the last accepted point is shorter than
``standard_errors`` standard errors, i.e. ``|P_J r|^2 <= standard_errors^2`` (``r`` the
residuals, already divided by their sigmas, and ``P_J`` the projection on the range of
their Jacobian: the step's length in the metric J^T J, the inverse of the parameters'
covariance, and twice the chi^2 the quadratic model says is left to gain), in the
standard errors the fit reports (the sigmas' own, floor included: a bound scaled down by
a chi^2/dof below 1 never held on a synthetic recording whose sigmas psi_1's floor sets,
chi^2/dof 0.0025, where the full Gauss-Newton step, half a standard error long, leaves
the region where the orbit exists). This does not depend on how the unknowns are
parametrised, and it is the precision a fit can claim anyway (:data:`STANDARD_ERRORS`).

:func:`column_scales` gives the diagonal scaling (Marquardt's, fixed at the start) that
makes the damping treat every unknown alike; :class:`~axojax.inverse.fitting.
least_squares.LevenbergMarquardt` applies it as a change of variables y = D z.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import jax
import jax.numpy as jnp
import lineax as lx
import optimistix as optx
from jaxtyping import Array, Float, PyTree

WIDEN_AT = 0.75
"""The trust region widens where the actual reduction is at least this fraction of the
predicted one (Moré 1978; optimistix's default 0.99 rarely widens on a curved valley)."""
STANDARD_ERRORS = 0.3
"""Stop when the Gauss-Newton step is within this many standard errors: what is left of
the optimisation then adds at most 0.3^2 = 9 % in quadrature to a standard error's
square (5 % to the error itself), far below what its own uncertainty is known to. A
stricter rule buys nothing a user can see: on a curved valley (a sloppy direction of
the saturation force) Levenberg-Marquardt's steps shrink to the valley's curvature, and
the stand-in of the module docstring needs about 230 more steps to reach 0.03."""


def gauss_newton_gain(f_info: optx.FunctionInfo.ResidualJac) -> Float[Array, ""]:
    """``|P_J r|^2``: the squared length of the Gauss-Newton step from ``f_info``'s point
    in the metric J^T J (twice the chi^2 the quadratic model says is left), by a thin
    QR of the Jacobian (an upper bound when J is rank deficient)."""
    r, J = _residuals_and_jacobian(f_info)
    q, _ = jnp.linalg.qr(J)
    return jnp.sum((q.T @ r) ** 2)


def _residuals_and_jacobian(f_info):
    r = jnp.concatenate([jnp.ravel(x) for x in jax.tree_util.tree_leaves(f_info.residual)])
    return r, f_info.jac.as_matrix().reshape(r.size, -1)


class StatisticalLevenbergMarquardt(optx.AbstractGaussNewton):
    """optimistix's Levenberg-Marquardt with the widening trust region and the
    statistical stopping rule of the module docstring (either rule stops it: the Cauchy
    one of ``rtol``/``atol``, or the Gauss-Newton step within ``standard_errors``)."""

    rtol: float
    atol: float
    norm: Callable[[PyTree], Array]
    descent: optx.DampedNewtonDescent
    search: optx.ClassicalTrustRegion
    verbose: Callable[..., None]
    standard_errors: float

    def __init__(
        self,
        rtol: float,
        atol: float,
        standard_errors: float = STANDARD_ERRORS,
        widen_at: float = WIDEN_AT,
        norm: Callable[[PyTree], Array] = optx.max_norm,
    ):
        self.rtol = rtol
        self.atol = atol
        self.norm = norm
        self.descent = optx.DampedNewtonDescent(linear_solver=lx.QR())
        self.search = optx.ClassicalTrustRegion(high_cutoff=widen_at)
        self.verbose = lambda **_: None
        self.standard_errors = standard_errors

    def terminate(self, fn, y, args, options: dict[str, Any], state, tags):
        close = (state.num_accepted_steps > 0) & (
            gauss_newton_gain(state.f_info) <= self.standard_errors**2
        )
        done = state.terminate | close
        return done, optx.RESULTS.where(close, optx.RESULTS.successful, state.result)


def column_scales(
    fn: Callable[[Float[Array, " k"]], Float[Array, " m"]], z0: Float[Array, " k"]
) -> Float[Array, " k"]:
    """(k,) the Euclidean norms of the columns of ``fn``'s Jacobian at ``z0`` (forward
    mode), floored at 10^-8 of the largest (an unknown the residuals do not feel at the
    start keeps a finite scale): y = D z makes every column of dfn/dy unit-length."""
    J = jax.jacfwd(fn)(z0)
    d = jnp.linalg.norm(J.reshape(-1, z0.size), axis=0)
    d = jnp.where(jnp.isfinite(d), d, 0.0)
    return jnp.maximum(d, 1e-8 * jnp.maximum(jnp.max(d), 1e-300))
