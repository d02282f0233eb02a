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
from test_posterior import LinearGaussian

from axojax.inverse import ProfileTransport, posterior
from axojax.inverse._densities import _Target
from axojax.inverse._nuts import _compiled
from axojax.inverse.transport import build_map

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
    target = _Target(problem)
    z_c = problem.to_z(jnp.array([M0, M0**2]))
    return problem, target, _compiled(build_map, (0, knots), (target, z_c))[0]


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


def test_map_is_a_bijection_with_its_log_jacobian():
    _, _, profile = _map()
    rng = np.random.default_rng(0)
    for y in rng.normal(scale=[3.0, 2.0], size=(12, 2)).tolist() + [[-9.0, 0.5], [9.0, -1.0], [-40.0, 0.0], [40.0, 3.0]]:
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
        )
    assert post.transport == "u0" and post.to_json()["transport"] == "u0"
    ref = _reference_moments()
    for n, (mean, sd) in ref.items():
        err = 4.0 * post.sd_u[n] / np.sqrt(post.ess[n])
        assert abs(post.mean_u[n] - mean) < err, (n, post.mean_u[n], mean, err)
        assert abs(post.sd_u[n] / sd - 1) < 0.15, (n, post.sd_u[n], sd)
        assert post.rhat[n] < 1.05, (n, post.rhat[n])
    assert post.gradients_per_draw < 8, post.gradients_per_draw


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
    from axojax.inverse.transport import profile_ends

    problem = CliffBanana()
    target = _Target(problem)
    profile = _compiled(build_map, (0, 48), (target, problem.to_z(jnp.array([M0, M0**2]))))[0]
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
