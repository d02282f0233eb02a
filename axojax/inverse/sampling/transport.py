"""Coordinates that straighten a curved posterior ridge before NUTS samples it.

A sloppy model's posterior is often a long, curved, thin ridge. On issue 31's synthetic
target (p and ks of the seven-filament model from a frequency and a wavelength) the
ridge follows ``p(ks)`` over five decades of ks, bending from p 150 to 420, with a width
of 0.7-1.5 % in p that changes along it. The affine whitening of :class:`NUTS` fits
one ellipse to that: the trajectories need small steps to stay on the ridge and many
to travel along it (25 gradients per draw measured).

:class:`ProfileTransport` removes the curve. Along one free parameter ``a`` (in the
sampler's unconstrained coordinate ``z``), it tabulates the *profile* of the log
density: for each of ``knots`` values of ``z_a`` the conditional maximum ``c(z_a)`` of
the log density over the other coordinates ``z_R`` (Gauss-Newton, by continuation from
the posterior's centre) and the Cholesky factor ``L(z_a)`` of the conditional Laplace
covariance there. The sampler then runs in ``y = (s, b)`` with

    z_a = g(s),        z_R = c(z_a) + L(z_a) b,

``c`` and ``L`` interpolated between the knots by cubic Hermite splines (``L`` by the
logarithm of its diagonal, so it stays positive), and ``g`` the monotone map that makes
``s`` standard normal under the profile's Laplace approximation of the marginal of
``z_a`` (mass ``exp(profile) det L`` per unit ``z_a``). This is a triangular
(Knothe-Rosenblatt-like) bijection of R^k with ``log |dz/dy| = log g'(s) + sum log
diag L(z_a)``, so the density sampled in ``y`` is exactly the problem's (Marzouk,
Moselhy, Parno & Spantini 2016, "Sampling via measure transport", in Handbook of
Uncertainty Quantification): only its shape changes, to about a standard normal. The
tables are as good as the knots are dense and the profile's Laplace approximation is;
an imperfect table costs efficiency, never correctness. The chains start from draws of
that approximation (standard normal in ``y``): spread along the whole ridge.

On the banana of ``tests/sampling/test_transport.py`` (u1 = u0^2 within 0.02) plain NUTS took 33
gradients per draw and reached an ESS of 12 in 4 x 400 draws (R-hat 1.27); in these
coordinates 4.3 gradients per draw and ESS 760-990, moments right.

On the bundled human sperm (p, ks; issue 31's command) the posterior lies on a ridge
0.2 % wide in p that climbs towards the ks bound, beside a cliff (another eigenmode
dominant) about 12 of its widths away: affinely whitened NUTS gave R-hat 1.05 and ESS 67 in
4 x 300 draws; along ks (with the tables below: knots reaching the bound, continuation
that predicts along the ridge) R-hat 1.003 and ESS 636.
:func:`~axojax.inverse.suggest_transport` makes that choice from a fit.

The parameter to go along is the one the ridge is a graph over: every value of it has
one conditional maximum of the others nearby (on the synthetic target: ks, not p, for
p stays at 150 for every ks below 1e3). Where the valley forks (two conditional maxima
at one value), each knot keeps the branch of larger conditional mass, found by
continuation or by a search across the other coordinates' ranges
(:data:`SEARCH_POINTS`): on a frequency and wavelength made at p 279, ks 6.4e3 the
continued branch (p ~ 225) holds a fifth of the mass of the one through the truth. The
mass of the other branch at the same value is sampled only as far as NUTS crosses to
it from the map's: a separated mode, as with any gradient sampler started in one mode
(on the synthetic target one at p ~ 280, ks < 1e3, another eigenmode matching the
targets, holds about 13 % of the mass: ``scripts/check_synthetic_posterior.py``).
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

DEFAULT_KNOTS = 96
"""Knots of the profile: uniform in the fitted coordinate u of the parameter along which
it goes, between its bounds."""
GAUSS_NEWTON_STEPS = 5
"""Gauss-Newton steps at each knot, from the neighbouring knot's maximum (one evaluation each)."""
TAIL_KNOTS = 4
"""Knots beyond the uniform ones at each end (:func:`knot_positions`)."""
PROFILE_DROP = 50.0
"""A knot whose conditional maximum lies this far (log density) below the best one is
past the ridge's end: the map stays constant from its neighbour on."""
MIN_PRECISION = 1e-2
"""Floor of the conditional precision's eigenvalues in z (an sd of at most 10)."""
SEARCH_POINTS = 128
"""Points of a knot's search across the other coordinates' ranges (per coordinate,
uniform in its fitted coordinate between the bounds): the best is a second start of the
knot's Gauss-Newton (:func:`build_map`)."""
SEARCH_EVERY = 4
"""Every this many knots (in the scan's order, outwards from the centre) are searched;
the others are continued from their neighbours (a quarter of the search's cost: ~13000
evaluations per profile at every knot)."""


class ProfileTransport(eqx.Module):
    """Sample in coordinates straightened along ``along``'s profile (module docstring).

    Attributes:
        along: the free parameter the ridge is a graph over (e.g. ``"ks"``).
        knots: profile points between the parameter's bounds (at least 8; half as if
            uniform in its fitted coordinate, half uniform in the sampler's, and
            :data:`TAIL_KNOTS` more towards each bound: :func:`knot_positions`).
        profile: the map already tabulated for this problem (``along``'s index, ``knots``
            knots), e.g. by :func:`~axojax.inverse.suggest_transport`, which builds every
            candidate's: the posterior then samples with it instead of tabulating the
            profile again from its own centre (used only with the problem's own prior).
            Either way the posterior is the same: the map only changes coordinates.
    """

    along: str
    knots: int = DEFAULT_KNOTS
    profile: ProfileMap | None = eqx.field(default=None, repr=False)

    def __check_init__(self):
        if self.profile is not None and not isinstance(self.profile, ProfileMap):
            raise ValueError(
                f"ProfileTransport: profile must be a ProfileMap or None, got {type(self.profile).__name__}"
            )
        if not isinstance(self.along, str) or not self.along:
            raise ValueError(
                f"ProfileTransport: along must be a parameter name, got {self.along!r}"
            )
        if not (isinstance(self.knots, (int, np.integer)) and 8 <= self.knots <= 4096):
            raise ValueError(
                f"ProfileTransport: knots must be an integer in 8..4096, got {self.knots!r}"
            )

    def index(self, names) -> int:
        """Position of ``along`` among the free parameters; one-line error if absent."""
        names = tuple(names)
        if self.along not in names:
            raise ValueError(
                f"ProfileTransport: along={self.along!r} is not a free parameter; choose from {', '.join(names)}"
            )
        if len(names) < 2:
            raise ValueError("ProfileTransport: needs at least two free parameters")
        return names.index(self.along)


class ProfileMap(eqx.Module):
    """The tabulated map ``y -> z`` of a :class:`ProfileTransport` (module docstring).

    Along the ridge the sampler's coordinate is ``s``, standard normal under the
    profile's Laplace approximation of the marginal of ``z_along``: ``z_along = g(s)``,
    ``g`` the monotone cubic (Fritsch-Carlson) through the knots' normal quantiles
    ``(s_j, z_j)``, linear beyond the end knots. The marginal's mass at knot j is
    ``exp(profile_j) det L_j`` times its cell width, mixed with ``MIX`` of a uniform mass
    per knot (so that ``g`` maps R onto R, past the ridge's end too).

    Attributes:
        along: index of the coordinate the profile goes along.
        rest: indices of the other k - 1 coordinates.
        z_knots: (n,) increasing knots in ``z_along``.
        s_knots: (n,) their quantiles in ``s`` (increasing).
        centre: (n, k-1) the conditional maximum of ``z_rest`` at each knot.
        log_diag: (n, k-1) log of the diagonal of the conditional covariance's Cholesky
            factor at each knot.
        lower: (n, k-1, k-1) its strictly lower part.
        log_density: (n,) the profile: the log density at each knot's maximum (-inf
            past the ridge's end).
    """

    along: int = eqx.field(static=True)
    rest: tuple[int, ...] = eqx.field(static=True)
    z_knots: Float[Array, " n"]
    s_knots: Float[Array, " n"]
    centre: Float[Array, "n r"]
    log_diag: Float[Array, "n r"]
    lower: Float[Array, "n r r"]
    log_density: Float[Array, " n"]

    def _tables(self, za: Float[Array, ""]):
        x = self.z_knots
        # the centre goes on along its end slopes past the end knots (the ridge keeps
        # moving, e.g. towards a bound); the widths stay those of the end knots
        c = _hermite(x, self.centre, _central_slopes(x, self.centre), za, clamp=False)
        flat = jnp.concatenate([self.log_diag, self.lower.reshape(x.shape[0], -1)], axis=1)
        v = _hermite(x, flat, _central_slopes(x, flat), za, clamp=True)
        r = self.centre.shape[1]
        logd, low = v[:r], v[r:].reshape(r, r)
        L = jnp.tril(low, -1) + jnp.diag(jnp.exp(logd))
        return c, L, jnp.sum(logd)

    def _along(self, s: Float[Array, ""]) -> Float[Array, ""]:
        x, y = self.s_knots, self.z_knots
        return _hermite(x, y[:, None], _monotone_slopes(x, y)[:, None], s, clamp=False)[0]

    def to_z(self, y: Float[Array, " k"]) -> Float[Array, " k"]:
        """Sampler coordinates ``y`` (``s`` along, ``b`` across) -> the problem's ``z``."""
        za = self._along(y[self.along])
        c, L, _ = self._tables(za)
        zr = c + L @ y[jnp.asarray(self.rest)]
        return y.at[self.along].set(za).at[jnp.asarray(self.rest)].set(zr)

    def to_y(self, z: Float[Array, " k"]) -> Float[Array, " k"]:
        """The problem's ``z`` -> sampler coordinates ``y`` (inverse of :meth:`to_z`; ``s``
        by bisection on the monotone ``g``)."""
        za = z[self.along]
        x, y = self.s_knots, self.z_knots
        slopes = _monotone_slopes(x, y)  # g is linear with these beyond the end knots
        lo = jnp.minimum(x[0], x[0] + (za - y[0]) / slopes[0]) - 1.0
        hi = jnp.maximum(x[-1], x[-1] + (za - y[-1]) / slopes[-1]) + 1.0

        def bisect(_, bounds):
            a, b = bounds
            m = 0.5 * (a + b)
            below = self._along(m) < za
            return jnp.where(below, m, a), jnp.where(below, b, m)

        a, b = jax.lax.fori_loop(0, 80, bisect, (lo, hi))
        c, L, _ = self._tables(za)
        b_rest = jax.scipy.linalg.solve_triangular(L, z[jnp.asarray(self.rest)] - c, lower=True)
        return z.at[self.along].set(0.5 * (a + b)).at[jnp.asarray(self.rest)].set(b_rest)

    def log_det(self, y: Float[Array, " k"]) -> Float[Array, ""]:
        """``log |dz/dy|`` at ``y``."""
        za, slope = jax.jvp(self._along, (y[self.along],), (jnp.ones_like(y[self.along]),))
        return jnp.log(slope) + self._tables(za)[2]

    def draw_y(self, key, count: int) -> Float[Array, "count k"]:
        """``count`` points in ``y`` from the profile's Laplace approximation of the
        posterior (standard normal in ``y``): starts spread along the whole ridge."""
        return jax.random.normal(key, (count, len(self.rest) + 1))


def profile_ends(profile: ProfileMap, to_u, log_coordinate: bool) -> list[float]:
    """Where the profile was lost (its log density fell by more than
    :data:`PROFILE_DROP` from its best: a cliff such as another eigenmode becoming the
    dominant one), as values of the parameter along which it goes: the last knot kept on
    each side that has lost knots beyond it (none, one or two values). ``to_u`` maps a
    point in z to u (the problem's)."""
    kept = np.isfinite(np.asarray(profile.log_density))
    if not kept.any():
        return []
    idx = np.flatnonzero(kept)
    ends = []
    for j, lost in ((idx[0], idx[0] > 0), (idx[-1], idx[-1] < kept.size - 1)):
        if lost:
            z = jnp.zeros(len(profile.rest) + 1).at[profile.along].set(profile.z_knots[j])
            u = float(to_u(z)[profile.along])
            ends.append(float(np.exp(u)) if log_coordinate else u)
    return ends


MIX = 1e-5
"""Share of the along coordinate's marginal spread uniformly over the knots (so that
``g`` maps R onto R). Small: where the profile is lost or far below its best, the true
density is far below any uniform share, and the share's knots would make a wall in
``s`` (a divergence) wherever the sampler visits them: 1e-5 puts them beyond
``|s| ~ 4.3``. (0.02 put them at ``|s| ~ 2.1`` and cost 13 % divergent draws on the
human sperm.)"""


def _quantiles(z_knots, log_density, log_diag) -> Float[Array, " n"]:
    """Normal quantiles ``s_j`` of the knots under the profile's Laplace marginal of
    ``z_along`` (:class:`ProfileMap`), mixed with :data:`MIX` uniform per knot."""
    x = z_knots
    width = jnp.concatenate([x[1:2] - x[:1], 0.5 * (x[2:] - x[:-2]), x[-1:] - x[-2:-1]])
    w = log_density + jnp.sum(log_diag, axis=1) + jnp.log(width)
    finite = jnp.isfinite(w)
    p = jax.nn.softmax(jnp.where(finite, w, -jnp.inf))
    p = jnp.where(jnp.any(finite), p, 1.0 / x.shape[0])  # no profile at all: uniform
    p = (1.0 - MIX) * p + MIX / x.shape[0]
    cdf = jnp.cumsum(p) - 0.5 * p
    return jax.scipy.special.ndtri(cdf)


def _nonzero(x):
    """``x`` with zeros replaced by ones (a denominator in a branch not taken)."""
    return jnp.where(x == 0, 1.0, x)


def _central_slopes(x, v):
    """Slopes of ``v`` (n, d) at knots ``x``: central differences, one-sided at the
    ends (a zero end slope bends the interpolant flat in the end cells)."""
    first = (v[1:2] - v[:1]) / (x[1] - x[0])
    last = (v[-1:] - v[-2:-1]) / (x[-1] - x[-2])
    return jnp.concatenate([first, (v[2:] - v[:-2]) / (x[2:] - x[:-2])[:, None], last])


def _monotone_slopes(x, y):
    """Fritsch-Carlson slopes of an increasing ``y`` (n,) at knots ``x``: the cubic
    Hermite interpolant stays increasing; the ends take their cell's secant."""
    h = x[1:] - x[:-1]
    d = (y[1:] - y[:-1]) / h
    w1, w2 = 2 * h[1:] + h[:-1], h[1:] + 2 * h[:-1]
    inner = (w1 + w2) / (w1 / d[:-1] + w2 / d[1:])
    return jnp.concatenate([d[:1], inner, d[-1:]])


def _hermite(x, v, slopes, t, clamp: bool):
    """Cubic Hermite interpolation of the rows ``v`` (n, d) with ``slopes`` at knots
    ``x`` (increasing) at ``t``: beyond the ends constant (``clamp``; end slopes 0) or
    linear with the end slopes."""
    n = x.shape[0]
    tc = jnp.clip(t, x[0], x[-1])
    i = jnp.clip(jnp.searchsorted(x, tc) - 1, 0, n - 2)
    h = x[i + 1] - x[i]
    s = (tc - x[i]) / h
    h00, h10 = (1 + 2 * s) * (1 - s) ** 2, s * (1 - s) ** 2
    h01, h11 = s**2 * (3 - 2 * s), s**2 * (s - 1)
    inside = h00 * v[i] + h10 * h * slopes[i] + h01 * v[i + 1] + h11 * h * slopes[i + 1]
    if clamp:
        return inside
    below, above = jnp.minimum(t - x[0], 0.0), jnp.maximum(t - x[-1], 0.0)
    return inside + below * slopes[0] + above * slopes[-1]


def knot_positions(n: int) -> np.ndarray:
    """(n + 2 TAIL_KNOTS,) increasing knots in z. ``n`` knots uniform in
    ``t = sigmoid(z) + (z - z_0) / (z_1 - z_0)`` between ``z_0, z_1 = -+logit(0.5 / n)``:
    half of them as if uniform in u between the bounds, half uniform in z (a cell at most
    ``2 (z_1 - z_0) / n`` wide in z, where a posterior piled against a bound needs them);
    then :data:`TAIL_KNOTS` at each end, each halving the distance to the bound in u."""
    z1 = float(np.log(2 * n - 1))
    grid = np.linspace(-z1, z1, 64 * n + 1)
    t = 1 / (1 + np.exp(-grid)) + (grid + z1) / (2 * z1)
    inner = np.interp(np.linspace(t[0], t[-1], n), t, grid)
    frac = 0.5 / n * 0.5 ** np.arange(1, TAIL_KNOTS + 1)
    tail = np.log(frac) - np.log1p(-frac)  # below -z1, further out each time
    return np.concatenate([tail[::-1], inner, -tail])


def build_map(settings: tuple[int, int], target, z_c: Float[Array, " k"]) -> ProfileMap:
    """Tabulate the profile of ``target`` (the log density in z) along coordinate
    ``settings[0]`` at the knots of :func:`knot_positions` (``settings[1]`` of them
    between the bounds, :data:`TAIL_KNOTS` more towards each bound), by
    continuation outwards from the knot nearest ``z_c`` (the posterior's centre): at each
    knot, :data:`GAUSS_NEWTON_STEPS` Gauss-Newton steps on the other coordinates from a
    prediction along the ridge (tangent, secant, then parabola: comments below) (a step
    that does not raise the log density is halved instead), and, every
    :data:`SEARCH_EVERY` knots, as many from the best of a search across each other
    coordinate's range (:data:`SEARCH_POINTS` points), the maximum of larger conditional
    Laplace mass kept;
    past the ridge's end (:data:`PROFILE_DROP`) the neighbour's entry is copied. Traceable
    (one compiled program, one model evaluation and its Jacobian per step)."""
    a, n = settings
    k = z_c.shape[0]
    rest_idx = np.array([i for i in range(k) if i != a])
    z_knots = jnp.asarray(knot_positions(n), dtype=z_c.dtype)
    n = z_knots.shape[0]
    r_dim = k - 1
    r, rest = target.split()

    def assemble(za, zr):
        return jnp.zeros(k, dtype=z_c.dtype).at[a].set(za).at[rest_idx].set(zr)

    def parts(za, zr):
        """The Gauss-Newton step on z_rest, the conditional covariance and the log
        density at (za, zr), from one residual evaluation and its Jacobian."""

        def rr(x):
            return r(assemble(za, x))

        def other(x):
            return rest(assemble(za, x))

        res, J = rr(zr), jax.jacfwd(rr)(zr)
        H = J.T @ J - jax.hessian(other)(zr)
        lam, vec = jnp.linalg.eigh(0.5 * (H + H.T))
        lam = jnp.maximum(lam, MIN_PRECISION)
        step = vec @ ((vec.T @ (jax.grad(other)(zr) - J.T @ res)) / lam)
        f = -0.5 * jnp.sum(res**2) + other(zr)
        return step, (vec / lam) @ vec.T, jnp.where(jnp.isfinite(f), f, -jnp.inf)

    def maximise(za, zr):
        """Gauss-Newton on z_rest at fixed za from zr: one evaluation per step (a step
        that does not raise the log density is halved, not taken); the maximum, the
        Cholesky factor of the conditional covariance there and the log density."""

        def one(_, state):
            zr, f, step, cov, t = state
            trial = zr + t * step
            step_t, cov_t, f_t = parts(za, trial)
            better = f_t > f
            return (
                jnp.where(better, trial, zr),
                jnp.where(better, f_t, f),
                jnp.where(better, step_t, step),
                jnp.where(better, cov_t, cov),
                jnp.where(better, 1.0, 0.5 * t),
            )

        state = (zr, -jnp.inf, jnp.zeros(r_dim), jnp.eye(r_dim), 0.0)
        zr, f, _, cov, _ = jax.lax.fori_loop(0, GAUSS_NEWTON_STEPS + 1, one, state)
        return zr, jnp.linalg.cholesky(cov), f

    # The search's points: each other coordinate in turn across its whole range (uniform
    # in u between the bounds), the rest at the prediction.
    t_grid = (jnp.arange(SEARCH_POINTS, dtype=z_c.dtype) + 0.5) / SEARCH_POINTS
    z_grid = jnp.log(t_grid) - jnp.log1p(-t_grid)
    one_hot = jnp.eye(r_dim, dtype=bool)[:, None, :]

    def search(za, zr):
        """The best of the search's points by log density (zr if none is finite)."""
        points = jnp.where(one_hot, z_grid[None, :, None], zr[None, None, :]).reshape(-1, r_dim)
        f = jax.vmap(lambda x: target(assemble(za, x)))(points)
        f = jnp.where(jnp.isfinite(f), f, -jnp.inf)
        i = jnp.argmax(f)
        return jnp.where(jnp.isfinite(f[i]), points[i], zr)

    def mass(m):
        """The conditional Laplace mass (log): ``f + log det L``."""
        logdet = jnp.sum(jnp.log(jnp.diagonal(m[1])))
        return jnp.where(jnp.isfinite(m[2]) & jnp.isfinite(logdet), m[2] + logdet, -jnp.inf)

    def conditional(za, zr, searched):
        """The knot's conditional maximum: Gauss-Newton from the prediction ``zr`` and,
        when ``searched``, from the search's best point, the one of larger conditional
        Laplace mass: where two branches of a valley part, the profile follows the one
        holding more of the posterior, not the one it was continued along."""
        from_prediction = maximise(za, zr)

        def with_search(_):
            found = maximise(za, search(za, zr))
            better = mass(found) > mass(from_prediction)
            return jax.tree_util.tree_map(
                lambda x, y: jnp.where(better, y, x), from_prediction, found
            )

        return jax.lax.cond(searched, with_search, lambda _: from_prediction, None)

    # one scan over the n knots: outwards from the knot j0 nearest the centre, first up
    # (j0 .. n-1), then down (j0-1 .. 0, restarting from j0's entry); a knot whose
    # maximum falls more than PROFILE_DROP below the best so far (past the ridge's end:
    # another mode, a failed evaluation) copies its neighbour's entry, so the map is
    # constant beyond the ridge. Each knot starts from a prediction along the ridge
    # (predict): from the centre its tangent (-H_rr^-1 H_ra, the full Gauss-Newton
    # Hessian there), then the secant of the last two knots' maxima, then the parabola
    # through the last three. A narrow ridge moves many of its widths between knots, and
    # can run beside a cliff (another eigenmode dominant): a start from the neighbour's
    # maximum can fall off it (tests/sampling/test_transport.py, NarrowCliffRidge).
    j0 = jnp.clip(jnp.searchsorted(z_knots, z_c[a]), 0, n - 1)
    tables0 = (jnp.zeros((n, r_dim)), jnp.tile(jnp.eye(r_dim), (n, 1, 1)), jnp.full((n,), -jnp.inf))
    J = jax.jacfwd(r)(z_c)
    H = J.T @ J - jax.hessian(rest)(z_c)
    tangent = -jnp.linalg.solve(H[np.ix_(rest_idx, rest_idx)], H[rest_idx, a])
    tangent = jnp.where(jnp.all(jnp.isfinite(tangent)), tangent, 0.0)

    def predict(pa, pr, count, x):
        """The ridge's z_rest at ``x`` from the last ``count`` maxima ``(pa, pr)``, newest
        first: the tangent from one, the secant of two, the parabola through three; in
        ``t = sigmoid(z)`` (u between its bounds, affinely: the ridge is smooth there up
        to the bounds, where the tail knots are far apart in z)."""
        ta, tr, tx = jax.nn.sigmoid(pa), jax.nn.sigmoid(pr), jax.nn.sigmoid(x)
        dt = ta[0] * (1 - ta[0])  # the tangent d zr / d za in t
        tan = tr[0] + tangent * tr[0] * (1 - tr[0]) / dt * (tx - ta[0])
        sec = tr[0] + (tr[0] - tr[1]) * ((tx - ta[0]) / _nonzero(ta[0] - ta[1]))
        weights = [
            (tx - ta[1]) * (tx - ta[2]) / _nonzero((ta[0] - ta[1]) * (ta[0] - ta[2])),
            (tx - ta[0]) * (tx - ta[2]) / _nonzero((ta[1] - ta[0]) * (ta[1] - ta[2])),
            (tx - ta[0]) * (tx - ta[1]) / _nonzero((ta[2] - ta[0]) * (ta[2] - ta[1])),
        ]
        quad = sum(w * r for w, r in zip(weights, tr))
        t = jnp.where(count >= 3, quad, jnp.where(count == 2, sec, tan))
        t = jnp.clip(t, 1e-15, 1 - 1e-15)
        return jnp.log(t) - jnp.log1p(-t)

    def body(carry, i):
        pa, pr, count, L, best, gone, tables = carry
        C, Ls, V = tables
        restart = i == n - j0  # back to the centre knot, then down
        back = jnp.minimum(j0 + jnp.arange(3), n - 1)  # the centre knot and two above it
        pa = jnp.where(restart, z_knots[back], pa)
        pr = jnp.where(restart, C[back], pr)
        count = jnp.where(restart, jnp.minimum(n - j0, 3), count)
        L = jnp.where(restart, Ls[j0], L)
        gone = gone & ~restart
        j = jnp.where(i < n - j0, j0 + i, n - 1 - i)
        searched = (i % SEARCH_EVERY == 0) | (i == n - j0)  # and the restart at the centre
        zr_new, L_new, f = conditional(z_knots[j], predict(pa, pr, count, z_knots[j]), searched)
        gone = gone | ((i > 0) & ~(f > best - PROFILE_DROP)) | ~jnp.all(jnp.isfinite(L_new))
        zr_new = jnp.where(gone, pr[0], zr_new)
        L_new = jnp.where(gone, L, L_new)
        f = jnp.where(gone, -jnp.inf, f)
        # the knot's maximum becomes the newest of the history (the first replaces z_c)
        pa = jnp.where(i == 0, pa.at[0].set(z_knots[j]), jnp.roll(pa, 1).at[0].set(z_knots[j]))
        pr = jnp.where(i == 0, pr.at[0].set(zr_new), jnp.roll(pr, 1, axis=0).at[0].set(zr_new))
        count = jnp.where(i == 0, 1, jnp.minimum(count + 1, 3))
        tables = (C.at[j].set(zr_new), Ls.at[j].set(L_new), V.at[j].set(f))
        return (pa, pr, count, L_new, jnp.maximum(best, f), gone, tables), None

    pa0 = jnp.zeros(3, dtype=z_c.dtype).at[0].set(z_c[a])
    pr0 = jnp.zeros((3, r_dim), dtype=z_c.dtype).at[0].set(z_c[rest_idx])
    carry0 = (pa0, pr0, jnp.array(1), jnp.eye(r_dim), -jnp.inf, jnp.array(False), tables0)
    (*_, (C, Ls, V)), _ = jax.lax.scan(body, carry0, jnp.arange(n))
    log_diag = jnp.log(jnp.diagonal(Ls, axis1=1, axis2=2))
    return ProfileMap(
        along=a,
        rest=tuple(int(i) for i in rest_idx),
        z_knots=z_knots,
        s_knots=_quantiles(z_knots, V, log_diag),
        centre=C,
        log_diag=log_diag,
        lower=jnp.tril(Ls, -1),
        log_density=V,
    )
