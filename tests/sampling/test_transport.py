"""Profile transport (issue 31): the straightened coordinates of a curved posterior
ridge. On a banana-shaped posterior known in closed form (a truncated normal along u0,
u1 = u0^2 within 0.02 across), the tabulated profile is the conditional maximum
(scipy's scalar minimiser, independently), the map is a bijection whose log-Jacobian is
the determinant of its derivative, and NUTS in those coordinates gives the posterior's
moments (scipy.stats.truncnorm); the warm-state cache keeps the map; bad input is one
line."""

import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.optimize
import scipy.stats

from axojax.inverse import ProfileTransport, posterior
from axojax.inverse.sampling._densities import LogDensity
from axojax.inverse.sampling.programs import compiled
from axojax.inverse.sampling.transport import build_map
from tests.sampling.test_nuts import LinearGaussian

M0, S0, S1 = 0.5, 1.0, 0.02
LOWER, UPPER = np.array([-3.0, -3.0]), np.array([3.0, 12.0])


class Banana(LinearGaussian):
    """Residuals ``((u0 - M0) / S0, (u1 - u0^2) / S1)``, a uniform prior in u within the
    bounds (the logistic map and log density of ``test_posterior.LinearGaussian``): u0 is
    a normal truncated to [-3, 3], u1 | u0 ~ N(u0^2, S1) (its bounds are more than 4 S1
    from every u0^2 with u0 in [-3, 3] but the ends)."""

    def __init__(self):
        super().__init__(np.zeros((2, 2)), np.zeros(2), 1.0, LOWER, UPPER, ["u0", "u1"])

    def residuals(self, u):
        return jnp.stack([(u[0] - M0) / S0, (u[1] - u[0] ** 2) / S1])

    def fingerprint(self):
        """What the warm-state cache keys on."""
        return "banana-test"


def _map(knots=48):
    problem = Banana()
    target = LogDensity(problem)
    z_c = problem.to_z(jnp.array([M0, M0**2]))
    return problem, target, compiled(build_map, (0, knots), (target, z_c))[0]


def test_profile_is_the_conditional_maximum():
    problem, target, profile = _map()
    for j in (3, 12, 24, 40):
        za = float(profile.z_knots[j])
        ref = scipy.optimize.minimize_scalar(
            lambda x: -float(target(jnp.array([za, x]))), bracket=(-2.0, 2.0), tol=1e-12
        )
        assert abs(float(profile.centre[j, 0]) - ref.x) < 1e-6, (j, profile.centre[j, 0], ref.x)
        # the conditional sd: the inverse curvature of -log density at the maximum
        h = 1e-4
        f = [-float(target(jnp.array([za, ref.x + d]))) for d in (-h, 0.0, h)]
        sd = (max((f[0] - 2 * f[1] + f[2]) / h**2, 1e-300)) ** -0.5
        assert abs(float(jnp.exp(profile.log_diag[j, 0])) / sd - 1) < 1e-3, j


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_map_is_a_bijection_with_its_log_jacobian():
    _, _, profile = _map()
    rng = np.random.default_rng(0)
    for y in rng.normal(scale=[3.0, 2.0], size=(12, 2)).tolist() + [
        [-9.0, 0.5],
        [9.0, -1.0],
        [-40.0, 0.0],
        [40.0, 3.0],
    ]:
        y = jnp.asarray(y)
        z = profile.to_z(y)
        assert np.allclose(profile.to_y(z), y, atol=1e-9), (y, profile.to_y(z))
        jac = jax.jacfwd(profile.to_z)(y)
        assert abs(float(jnp.linalg.slogdet(jac)[1] - profile.log_det(y))) < 1e-9


def _reference_moments():
    """Mean and sd of u0 and u1 under the banana posterior: u0 a normal truncated to the
    bounds, u1 = u0^2 + S1 eps (scipy.stats.truncnorm's moments)."""
    a, b = (LOWER[0] - M0) / S0, (UPPER[0] - M0) / S0
    u0 = scipy.stats.truncnorm(a, b, loc=M0, scale=S0)
    m1, m2, m3, m4 = (u0.moment(i) for i in (1, 2, 3, 4))
    return {"u0": (m1, u0.std()), "u1": (m2, np.sqrt(m4 - m2**2 + S1**2))}


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_transported_nuts_samples_the_banana():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        post = posterior(
            Banana(),
            draws=400,
            chains=4,
            warmup=200,
            seed=1,
            transport=ProfileTransport("u0", knots=64),
            vectorize=True,  # see test_the_suggested_map_is_sampled_as_built
        )
    assert post.transport == "u0" and post.to_json()["transport"] == "u0"
    ref = _reference_moments()
    for n, (mean, sd) in ref.items():
        err = 4.0 * post.sd_u[n] / np.sqrt(post.ess[n])
        assert abs(post.mean_u[n] - mean) < err, (n, post.mean_u[n], mean, err)
        assert abs(post.sd_u[n] / sd - 1) < 0.15, (n, post.sd_u[n], sd)
        assert post.rhat[n] < 1.05, (n, post.rhat[n])
    assert post.gradients_per_draw < 8, post.gradients_per_draw


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_warm_cache_keeps_the_map(tmp_path):
    kw = dict(draws=20, chains=2, warmup=60, seed=3, transport=ProfileTransport("u0", knots=32))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        first = posterior(Banana(), cache=tmp_path, **kw)
        second = posterior(Banana(), cache=tmp_path, **kw)
        plain = posterior(Banana(), cache=tmp_path, **{**kw, "transport": None})
    assert (first.warm_cache, second.warm_cache, plain.warm_cache) == ("stored", "loaded", "stored")
    assert np.array_equal(first.u, second.u)
    assert not np.array_equal(first.u, plain.u)


def test_bad_transport_is_one_line():
    with pytest.raises(
        ValueError, match="along='nope' is not a free parameter; choose from u0, u1"
    ):
        posterior(Banana(), draws=4, chains=1, warmup=0, transport=ProfileTransport("nope"))
    with pytest.raises(TypeError, match="transport"):
        posterior(Banana(), draws=4, chains=1, warmup=0, transport="u0")
    with pytest.raises(ValueError, match="profile must be a ProfileMap or None, got str"):
        ProfileTransport("u0", profile="map")
    _, _, along_u0 = _map(knots=16)
    with pytest.raises(ValueError, match="its profile map goes along coordinate 0 of 2"):
        posterior(
            Banana(), draws=4, chains=1, warmup=0, transport=ProfileTransport("u1", 16, along_u0)
        )
    for bad in (0, 7, 5000):
        with pytest.raises(ValueError, match="knots must be an integer in 8..4096"):
            ProfileTransport("u0", knots=bad)
    with pytest.raises(ValueError, match="along must be a parameter name"):
        ProfileTransport("")


class CliffBanana(Banana):
    """The banana with its density falling off a cliff at u0 = 1.5 (a residual of 1e3
    beyond: as where another eigenmode becomes the dominant one)."""

    def residuals(self, u):
        return super().residuals(u) + jnp.where(u[0] > 1.5, 1e3, 0.0)


def test_profile_ends_at_a_cliff():
    from axojax.inverse.sampling.transport import profile_ends

    problem = CliffBanana()
    target = LogDensity(problem)
    profile = compiled(build_map, (0, 48), (target, problem.to_z(jnp.array([M0, M0**2]))))[0]
    kept = np.isfinite(np.asarray(profile.log_density))
    assert kept[:20].all() and not kept[-10:].any()  # knots 0.125 apart in u0 over [-3, 3]
    (end,) = profile_ends(profile, problem.to_u, log_coordinate=False)
    assert 1.5 - 0.125 <= end <= 1.5, end
    # the map is constant past the cliff (the last kept knot's entry)
    last = int(np.flatnonzero(kept)[-1])
    assert np.allclose(profile.centre[last:], profile.centre[last])
    # no cliff, no end
    _, _, plain = _map()
    assert profile_ends(plain, Banana().to_u, log_coordinate=False) == []


W = 0.002
"""Width of :class:`NarrowCliffRidge`'s ridge across."""


class NarrowCliffRidge(Banana):
    """A ridge u1 = 3 u0 + 0.1 u0^2, W wide across, above a cliff 10 W below it, past
    which the density is flat (a constant residual of 1e3: as where another eigenmode
    becomes the dominant one, unrelated to this one's targets). Between two knots the
    ridge moves about 200 of its widths: a knot's Gauss-Newton started from the
    neighbour's maximum lands past the cliff, where nothing leads back (as on the human
    sperm, whose mode runs beside such a cliff)."""

    def __init__(self):
        LinearGaussian.__init__(
            self, np.zeros((2, 2)), np.zeros(2), 1.0, [-3.0, -10.0], [3.0, 12.0], ["u0", "u1"]
        )

    @staticmethod
    def ridge(u0):
        return 3.0 * u0 + 0.1 * u0**2

    def residuals(self, u):
        across = (u[1] - self.ridge(u[0])) / W
        return jnp.stack([(u[0] - M0) / S0, jnp.where(across < -10, 1e3, across)])


def test_profile_follows_a_narrow_ridge_beside_a_cliff():
    problem = NarrowCliffRidge()
    target = LogDensity(problem)
    z_c = problem.to_z(jnp.array([M0, problem.ridge(M0)]))
    profile = compiled(build_map, (0, 48), (target, z_c))[0]
    assert np.isfinite(np.asarray(profile.log_density)).all()  # no false cliff
    z = jnp.stack([profile.z_knots, profile.centre[:, 0]], axis=1)
    u = np.asarray(jax.vmap(problem.to_u)(z))
    # the conditional maximum is on the ridge (to a small fraction of its width)
    assert np.max(np.abs(u[:, 1] - problem.ridge(u[:, 0]))) < 0.01 * W


class AtTheBound(Banana):
    """The banana with u0's normal centred on its upper bound: half the mass lies within
    one sd of the bound, beyond the last of the knots uniform in u."""

    def residuals(self, u):
        return jnp.stack([(u[0] - UPPER[0]) / S0, (u[1] - u[0] ** 2) / S1])


def test_map_holds_up_to_a_bound():
    problem = AtTheBound()
    target = LogDensity(problem)
    z_c = problem.to_z(jnp.array([2.5, 6.25]))
    profile = compiled(build_map, (0, 48), (target, z_c))[0]
    # in the sampler's coordinates the density is about a standard normal, past the
    # uniform knots too (s up to 2.5: z_a up to 7.4, within 2e-3 of the bound in u0)
    s = np.linspace(-2.0, 2.5, 19)
    b = np.linspace(-2.0, 2.0, 5)
    y = jnp.asarray(np.stack(np.meshgrid(s, b, indexing="ij"), -1).reshape(-1, 2))
    y = y[:, ::-1] if profile.along == 1 else y  # (u0 along, u1 across)
    logp = jax.vmap(lambda y: target(profile.to_z(y)) + profile.log_det(y))(y)
    dev = np.asarray(logp + 0.5 * jnp.sum(y**2, axis=1))
    assert np.ptp(dev) < 1.0, np.ptp(dev)
    assert float(profile.to_z(jnp.array([2.5, 0.0]))[0]) > float(profile.z_knots[-1 - 4])


class ForkedValley(Banana):
    """Two valleys that part at u0 = 0: A along u1 = 0 and B along u1 = u0^2 (the second
    residual vanishes on both), with a third residual u1 - u0^2 that lowers A's density
    by u0^4 / 2 and leaves B's: beyond |u0| ~ 1 B holds nearly all the mass. A profile
    continued from a centre on A stays on A."""

    def residuals(self, u):
        return jnp.stack([(u[0] - M0) / S0, u[1] * (u[1] - u[0] ** 2) / S1, u[1] - u[0] ** 2])


def test_profile_takes_the_branch_with_the_mass():
    problem = ForkedValley()
    target = LogDensity(problem)
    z_c = problem.to_z(jnp.array([M0, 0.0]))  # on A
    profile = compiled(build_map, (0, 48), (target, z_c))[0]
    z = jnp.stack([profile.z_knots, profile.centre[:, 0]], axis=1)
    u = np.asarray(jax.vmap(problem.to_u)(z))
    far = np.abs(u[:, 0]) >= 1.5
    assert far.sum() >= 10
    # on B (u1 = u0^2, to a small fraction of the valley's width S1 / u0^2), not on A
    np.testing.assert_allclose(u[far, 1], u[far, 0] ** 2, atol=1e-3)
    # and the conditional maximum there is the global one (a dense scan across u1)
    for j in np.flatnonzero(far)[::4]:
        grid = jnp.linspace(-2.9, 11.9, 20001)
        f = jax.vmap(lambda x: target(problem.to_z(jnp.array([u[j, 0], x]))))(grid)
        assert abs(float(grid[jnp.argmax(f)]) - u[j, 1]) < 2e-3, (j, u[j])


class _Fit:
    """The parts of a FitResult that suggest_transport reads."""

    def __init__(self, corr, se_u, values=(0.5, 0.25), optima=()):
        self.names = ("u0", "u1")
        self.correlation = np.array([[1.0, corr], [corr, 1.0]])
        self.stderr_fitted = dict(zip(self.names, se_u))
        self.params = dict(zip(self.names, values))
        self.coordinate = {"u0": "linear", "u1": "linear"}
        self.loss = 0.0
        self.optima = list(optima)


def test_suggest_transport_goes_along_the_widest_in_z():
    from axojax.inverse import suggest_transport

    problem = Banana()  # u0 in [-3, 3], u1 in [-3, 12]: dz/du = 1 / (span t (1 - t))
    # a ridge: along the parameter of the largest standard error in z, not in u
    t0, t1 = (0.5 + 3) / 6, (0.25 + 3) / 15
    sd_z = np.array([0.3 / (6 * t0 * (1 - t0)), 1.0 / (15 * t1 * (1 - t1))])
    chosen = suggest_transport(problem, _Fit(0.995, (0.3, 1.0)))
    assert chosen.along == ("u0", "u1")[int(np.argmax(sd_z))]
    assert suggest_transport(problem, _Fit(-0.999, (1.0, 0.01))).along == "u0"
    # a single parameter: none
    single = _Fit(0.999, (0.3, 1.0))
    single.names, single.correlation = ("u0",), np.eye(1)
    assert suggest_transport(problem, single) is None


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_suggest_transport_sees_what_the_optimum_does_not():
    """Uncorrelated at the optimum (the banana's tip is round: the curvature there is
    all its Laplace approximation sees), yet a banana: importance sampling through each
    map finds it. The Laplace whitening misses mass, the profile along u0 (the banana is
    a graph over u0) makes it nearly standard normal, the one along u1 (two arms,
    u0 = +-sqrt(u1)) does worse. A normal posterior keeps the Laplace whitening."""
    from axojax.inverse import suggest_transport
    from axojax.inverse.sampling.transport_choice import importance_scores

    problem = Banana()
    u = jnp.array([M0, M0**2])
    scores = importance_scores(problem, u)
    (m_laplace, e_laplace, _), (m0, e0, d0), (_, e1, _) = scores[None], scores[0], scores[1]
    # the banana's exact mass in z: the truncated normal of u0 times the u1 | u0 normal's
    # normaliser, times the uniform prior's Jacobian, integrated: by quadrature in u
    assert abs(m0 - _banana_log_mass(problem)) < 0.05, (m0, _banana_log_mass(problem))
    assert e0 > 0.8 and e0 > 2 * e_laplace and e0 > e1 and d0 < 0.5
    assert m_laplace < m0 - 0.1  # the Laplace draws miss the banana's arms
    assert suggest_transport(problem, _Fit(0.0, (1.0, 0.3))).along == "u0"
    normal = LinearGaussian(
        np.array([[1.0, 0.3], [0.0, 1.0]]), np.array([0.4, -0.2]), 0.1, LOWER, UPPER, ["u0", "u1"]
    )
    fit = _Fit(0.3, (0.1, 0.1), values=(0.46, -0.2))
    assert suggest_transport(normal, fit) is None


@pytest.mark.slow  # long end-to-end (issue 53: the quick suite within 20 CPU-minutes)
def test_the_suggested_map_is_sampled_as_built(monkeypatch):
    """suggest_transport hands over the map it built: the posterior samples with it
    (tabulating nothing again: build_map is switched off), and the draws have the
    banana's moments. With another prior it tabulates its own (the call is refused here)."""
    import sys

    from axojax.inverse import suggest_transport

    kernels = sys.modules["axojax.inverse.sampling._nuts_kernels"]  # where NUTS tabulates maps
    transport = suggest_transport(Banana(), _Fit(0.0, (1.0, 0.3)))
    assert transport.along == "u0" and transport.profile is not None

    def refuse(*args, **kwargs):
        raise AssertionError("the profile was tabulated again")

    monkeypatch.setattr(kernels, "build_map", refuse)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # vmapped chains, as this test was written for (the default on a CPU is one after
        # another; at the suite's XLA optimisation level 0 those adapt a step size of ~0.002
        # on this density, their R-hat ~3, where default-level code samples it well)
        post = posterior(
            Banana(), draws=300, chains=4, warmup=150, seed=2, transport=transport, vectorize=True
        )
    for n, (mean, sd) in _reference_moments().items():
        err = 4.0 * post.sd_u[n] / np.sqrt(post.ess[n])
        assert abs(post.mean_u[n] - mean) < err, (n, post.mean_u[n], mean, err)
        assert abs(post.sd_u[n] / sd - 1) < 0.15, (n, post.sd_u[n], sd)
    with pytest.raises(AssertionError, match="tabulated again"):
        posterior(
            Banana(), draws=4, chains=1, warmup=0, transport=transport, prior={"u0": (0.0, 2.0)}
        )


def _banana_log_mass(problem) -> float:
    """log of the integral over z of exp(log density in z) = the integral over u of
    exp(-|r(u)|^2 / 2) (the uniform prior's log-Jacobian turns dz into du)."""
    import scipy.integrate

    def inner(u0):
        return scipy.integrate.quad(
            lambda u1: np.exp(-0.5 * float(jnp.sum(problem.residuals(jnp.array([u0, u1])) ** 2))),
            max(LOWER[1], u0**2 - 12 * S1),
            min(UPPER[1], u0**2 + 12 * S1),
            points=[u0**2],
        )[0]

    return float(np.log(scipy.integrate.quad(inner, LOWER[0], UPPER[0], limit=200)[0]))


def test_suggest_transport_beyond_the_profiles_reads_the_optima():
    """Beyond MAX_PROFILES parameters no profile is tried: another start that stopped as
    low, many standard errors away (fit.optima), makes the transport; one far above the
    best loss, or none, does not."""
    from axojax.inverse import suggest_transport

    names = ["u0", "u1", "u2", "u3"]
    problem = LinearGaussian(np.eye(4), np.zeros(4), 0.1, -3 * np.ones(4), 3 * np.ones(4), names)
    fit = _Fit(0.0, (0.1, 0.1), values=(0.0, 0.0))
    fit.names = tuple(names)
    fit.correlation = np.eye(4)
    fit.stderr_fitted = {"u0": 0.1, "u1": 0.1, "u2": 0.1, "u3": 0.4}
    fit.params = dict.fromkeys(names, 0.0)
    fit.coordinate = dict.fromkeys(names, "linear")
    assert suggest_transport(problem, fit) is None
    fit.optima = [({"u0": 2.0, "u1": 0.0, "u2": 0.0, "u3": 0.0}, 50.0)]
    assert suggest_transport(problem, fit) is None
    fit.optima = [({"u0": 2.0, "u1": 0.0, "u2": 0.0, "u3": 0.0}, 0.5)]
    assert suggest_transport(problem, fit).along == "u3"  # the widest in z


def test_the_choice_of_map():
    """suggest_transport's rule on importance-sampling scores (log mass, efficiency,
    barrier): the mass first, then no barrier, then efficiency; the Laplace whitening
    (None) unless a profile is GAIN times as efficient; None when no map reached the
    posterior."""
    import math

    from axojax.inverse.sampling.transport_choice import GAIN, _best

    inf = math.inf
    assert _best({None: (-inf, 0.0, 0.0), 0: (-inf, 0.0, 0.0)}) is None
    assert _best({None: (-2.0, 0.1, 0.0), 0: (-1.9, 0.9, 0.0)}) == 0
    assert _best({None: (-2.0, 0.8, 0.0), 0: (-1.9, 0.8 * GAIN * 0.99, 0.0)}) is None
    # the Laplace draws miss mass: a profile even when it is less efficient
    assert _best({None: (-3.0, 0.9, 0.0), 1: (-2.0, 0.5, 0.0)}) == 1
    # a barrier loses to a smooth profile of enough mass, not to one that misses mass
    assert _best({None: (-9.0, 0.9, 0.0), 0: (-2.0, 0.9, 40.0), 1: (-2.1, 0.5, 0.0)}) == 1
    assert _best({None: (-9.0, 0.9, 0.0), 0: (-2.0, 0.9, 40.0), 1: (-3.0, 0.5, 0.0)}) == 0
