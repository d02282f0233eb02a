"""Exact derivatives of growth rate, frequency and wavelength against finite differences.

Derivatives are taken with respect to log-parameters (log p, log ks, ..., and gamma
itself), so every component has the scale of the metric; the error of each component
is measured relative to the norm of the metric's gradient. The reference is a
five-point central difference in float64 (truncation O(h^4)), evaluated with the same
jitted forward model. Forward and reverse mode are checked, under jit and vmap.
"""

import zlib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import axojax as ax

# preset -> (free parameters, sampling box); log-uniform except gamma (uniform)
CASES = {
    "single": (["p"], {"p": (100.0, 600.0)}),
    "beck": (["p"], {"p": (40.0, 60.0)}),
    "two": (
        ["p", "kl", "cl", "gamma"],
        {"p": (250.0, 600.0), "kl": (1e2, 1e4), "cl": (1e-3, 1e-1), "gamma": (-1.0, 0.5)},
    ),
    "four": (
        ["p", "ks", "kl", "cl", "gamma"],
        {
            "p": (300.0, 700.0),
            "ks": (1e4, 1e6),
            "kl": (10.0, 1e3),
            "cl": (1e-3, 0.1),
            "gamma": (-1.0, 0.3),
        },
    ),
    "seven": (
        ["p", "ks", "kl", "cl", "gamma"],
        {
            "p": (350.0, 800.0),
            "ks": (1e4, 1e6),
            "kl": (10.0, 1e3),
            "cl": (1e-3, 0.1),
            "gamma": (-1.0, 0.3),
        },
    ),
    "nine": (
        ["p", "ks", "kl", "cl", "gamma"],
        {
            "p": (350.0, 800.0),
            "ks": (1e4, 1e6),
            "kl": (10.0, 1e3),
            "cl": (1e-3, 0.1),
            "gamma": (-1.0, 0.3),
        },
    ),
}
POINTS_PER_PRESET = {"nine": 2}  # 4 elsewhere: 22 points in all
H = 1e-3


def to_params(names, z):
    return ax.Params().with_values(
        {n: (z[i] if n == "gamma" else jnp.exp(z[i])) for i, n in enumerate(names)}
    )


def make_metrics(model, names):
    def metrics(z):
        mode = ax.dominant_mode(model, to_params(names, z))
        return jnp.stack([mode.growth_rate_per_s(), mode.frequency_hz(), mode.wavelength_um()])

    return metrics


def sample_points(name, rng):
    """Random flutter points whose dominant eigenvalue is well separated (no mode switch
    within the finite-difference stencil)."""
    names, box = CASES[name]
    model = ax.models.preset(name)
    points = []
    while len(points) < POINTS_PER_PRESET.get(name, 4):
        z = np.array(
            [
                rng.uniform(*box[n])
                if n == "gamma"
                else rng.uniform(np.log(box[n][0]), np.log(box[n][1]))
                for n in names
            ]
        )
        params = to_params(names, jnp.asarray(z))
        lam = np.asarray(ax.spectrum(model, params, 4))
        upper = lam[lam.imag >= 0]
        if (
            lam[0].real > 0
            and abs(lam[0].imag) > 1e-3 * abs(lam[0])
            and abs(upper[0] - upper[1]) > 0.05 * abs(upper[0])
        ):
            points.append(z)
    return model, names, jnp.asarray(np.array(points))


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("name", list(CASES))
def test_gradients_match_finite_differences(name):
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    model, names, Z = sample_points(name, rng)
    metrics = make_metrics(model, names)
    k = len(names)

    fwd = jax.jit(jax.vmap(jax.jacfwd(metrics)))(Z)  # (P, 3, k)
    rev = jax.jit(jax.vmap(jax.jacrev(metrics)))(Z)
    # Reverse mode through a scalar loss with jax.grad as well.
    grad_freq = jax.jit(jax.vmap(jax.grad(lambda z: metrics(z)[1])))(Z)

    batched = jax.jit(jax.vmap(metrics))  # one program for both stencils

    def five_point(h):
        steps = jnp.eye(k) * h  # (k, k)
        offsets = jnp.array([-2.0, -1.0, 1.0, 2.0])
        shifted = (
            Z[:, None, None, :] + offsets[None, :, None, None] * steps[None, None, :, :]
        )  # (P, 4, k, k)
        vals = batched(shifted.reshape(-1, k)).reshape(Z.shape[0], 4, k, 3)
        fd = (vals[:, 0] - 8 * vals[:, 1] + 8 * vals[:, 2] - vals[:, 3]) / (12 * h)  # (P, k, 3)
        return jnp.swapaxes(fd, 1, 2)  # (P, 3, k)

    fd, fd_wide = five_point(H), five_point(2 * H)
    scale = jnp.linalg.norm(fd, axis=2, keepdims=True)
    # The reference itself must be trustworthy: drop points where the stencil straddles
    # a near-singularity of a metric (e.g. the wavelength as k -> 0 close by in gamma),
    # seen as the H and 2H differences disagreeing (O(h^4) truncation predicts 16x apart
    # and tiny). Which points are kept depends on finite differences only.
    smooth = np.asarray(jnp.max(jnp.abs(fd - fd_wide) / scale, axis=(1, 2))) < 1e-6
    assert smooth.sum() >= max(2, Z.shape[0] - 1), smooth
    fwd, rev, grad_freq, fd, scale = (x[smooth] for x in (fwd, rev, grad_freq, fd, scale))
    assert float(jnp.max(jnp.abs(fwd - fd) / scale)) < 1e-6
    assert float(jnp.max(jnp.abs(rev - fd) / scale)) < 1e-6
    assert float(jnp.max(jnp.abs(grad_freq - fd[:, 1, :]) / scale[:, 1, :])) < 1e-6


def test_velocity_and_out_of_plane_differentiable(seven):
    model = seven

    def f(logp):
        mode = ax.dominant_mode(model, ax.Params(p=jnp.exp(logp), ks=1e5, kl=100.0))
        return jnp.stack([mode.velocity_um_per_s(), mode.out_of_plane_ratio])

    z = jnp.log(500.0)
    g = jax.jacfwd(f)(z)
    fd = (f(z + 1e-4) - f(z - 1e-4)) / 2e-4
    np.testing.assert_allclose(g, fd, rtol=1e-6)


def test_degenerate_isotropic_never_nan():
    """out_of_plane = 1 on the four-filament ring at p = 0 gives a multiple (here
    triple) dominant eigenvalue; its derivative is the cluster mean's: finite, and equal
    to the finite-difference derivative of the mean of the cluster's branches."""
    model = ax.models.four()

    def growth(oop, p):
        return ax.dominant_mode(
            model, ax.Params(p=p, out_of_plane=oop, kl=100.0, ks=100.0)
        ).growth_rate

    g = jax.grad(growth, argnums=(0, 1))(1.0, 0.0)
    assert all(np.isfinite(float(x)) for x in g)
    lam = np.asarray(ax.spectrum(model, ax.Params(p=0.0, out_of_plane=1.0, kl=100.0, ks=100.0), 4))
    m = int(np.sum(np.abs(lam - lam[0]) < 1e-8 * abs(lam[0])))
    assert m >= 2  # it is degenerate
    h = 1e-4
    up = np.asarray(
        ax.spectrum(model, ax.Params(p=0.0, out_of_plane=1.0 + h, kl=100.0, ks=100.0), m)
    ).real
    down = np.asarray(
        ax.spectrum(model, ax.Params(p=0.0, out_of_plane=1.0 - h, kl=100.0, ks=100.0), m)
    ).real
    branch_mean = (np.mean(up) - np.mean(down)) / (2 * h)
    assert float(g[0]) == pytest.approx(branch_mean, rel=1e-5)
    # Also under vmap and reverse mode of a metric through the eigenvector.
    wl = jax.vmap(
        jax.grad(
            lambda p: ax.dominant_mode(model, ax.Params(p=p, out_of_plane=1.0)).out_of_plane_ratio
        )
    )(jnp.array([0.0, 1.0]))
    assert np.all(np.isfinite(np.asarray(wl)))
