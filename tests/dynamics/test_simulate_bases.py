"""The time domain on bases that move (issue 30: pivot, free, head, basal compliance):
the linear integration against scipy's matrix exponential of the dense system, the cubic
link force that leaves the border alone, the nonlinear integration against scipy's Radau
on the dense vector field, and ``simulate``'s body frame (the base's rigid motion taken
out of psi and the tip)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.integrate
import scipy.linalg as sl

import axojax as ax
from axojax.dynamics.integrate import integrate
from axojax.dynamics.nonlinear import cubic_links
from axojax.dynamics.simulate import tip_deflection
from axojax.models import Base

BASES = {
    "pivot": Base("pivot", rotational_drag=0.05),
    "free": Base("free"),
    "head": Base("head", False, 1.0, 0.2),
    "clamped+compliance": Base("clamped", True),
}
PARAMS = ax.Params(p=300.0, kb=50.0, xib=0.5)


def _start(model, rng):
    """A bent start with the border's unknowns moved too."""
    q0 = np.concatenate([tip_deflection(model), np.zeros(model.n_border)]) * 0.02
    return q0 + 0.002 * rng.normal(size=model.n_unknowns)


def _dense(model, params):
    """A, C and b of ``C dq/dt = b - A q`` (b: the static couple of the imbalance)."""
    s = ax.assemble(model, params)
    return np.asarray(s.A), np.asarray(s.C), np.asarray(s.b)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
@pytest.mark.parametrize("name", list(BASES))
def test_linear_integration_is_the_matrix_exponential(name):
    model = ax.models.seven(n_elements=4, base=BASES[name])
    A, C, b = _dense(model, PARAMS)
    q0 = _start(model, np.random.default_rng(0))
    n = q0.shape[0]
    # the affine system as a linear one in (q, 1): d/dt (q, 1) = [[G, C^-1 b], [0, 0]] (q, 1)
    G = np.zeros((n + 1, n + 1))
    G[:n, :n] = -np.linalg.solve(C, A)
    G[:n, n] = np.linalg.solve(C, b)
    lam = np.linalg.eigvals(G[:n, :n])
    rate = np.max(np.abs(lam.real[np.abs(lam) < 1e4]))
    t = np.linspace(0.0, 2.0 / rate, 5)
    traj = integrate(model, PARAMS, 0.0, jnp.asarray(q0), jnp.asarray(t), rtol=1e-10, atol=1e-13)
    assert bool(traj.ok)
    for ti, qi in zip(t, np.asarray(traj.q)):
        ref = (sl.expm(G * ti) @ np.append(q0, 1.0))[:n]
        assert np.linalg.norm(qi - ref) <= 1e-6 * np.linalg.norm(ref), (name, ti)


@pytest.mark.parametrize("name", ["free", "clamped+compliance"])
def test_the_cubic_links_leave_the_border_alone(name):
    """The links stretch with the node unknowns only (node 0 is shared by every filament;
    basal sliding is no spacing): the force on a bordered state is the clamped model's on
    its node part, zero on the border, and the tangent is the force's Jacobian."""
    model = ax.models.seven(n_elements=4, base=BASES[name])
    clamped = ax.models.seven(n_elements=4)
    q = jnp.asarray(_start(model, np.random.default_rng(1)))
    links = cubic_links(model, PARAMS, 2.0e3)
    f = links.force(q)
    n = model.n_dof
    ref = cubic_links(clamped, PARAMS, 2.0e3).force(q[:n])
    assert np.array_equal(np.asarray(f[:n]), np.asarray(ref))
    assert not np.any(np.asarray(f[n:]))
    np.testing.assert_allclose(links.tangent(q), jax.jacfwd(links.force)(q), rtol=1e-10, atol=1e-8)


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_nonlinear_integration_on_a_free_base_matches_radau():
    """The chord's bordered block Jacobian against scipy's Radau (its own finite-difference
    Jacobian) on the dense vector field C^-1 (b - A q - f_nl(q)), cubic links on."""
    model = ax.models.seven(n_elements=4, base="free")
    A, C, b = _dense(model, PARAMS)
    links = cubic_links(model, PARAMS, 2.0e3)
    # Columns at once: Radau's finite-difference Jacobian perturbs every unknown, one call
    # (vectorized=True) instead of one jax dispatch and one dense solve per column.
    force = jax.jit(jax.vmap(links.force, in_axes=1, out_axes=1))
    lu = scipy.linalg.lu_factor(C)
    q0 = _start(model, np.random.default_rng(2)) * 5
    t = np.linspace(0.0, 2e-3, 4)

    def rhs(_, q):
        cols = q.reshape(q.shape[0], -1)
        f = scipy.linalg.lu_solve(lu, b[:, None] - A @ cols - np.asarray(force(jnp.asarray(cols))))
        return f.reshape(q.shape)

    ref = scipy.integrate.solve_ivp(
        rhs, (0, t[-1]), q0, "Radau", t_eval=t, rtol=1e-10, atol=1e-13, vectorized=True
    )
    traj = integrate(model, PARAMS, 2.0e3, jnp.asarray(q0), jnp.asarray(t), rtol=1e-10, atol=1e-13)
    assert bool(traj.ok) and ref.success
    scale = np.linalg.norm(ref.y, axis=0)
    err = np.linalg.norm(np.asarray(traj.q) - ref.y.T, axis=1)
    assert np.all(err <= 1e-6 * scale), err / scale
    assert np.linalg.norm(ref.y[:, -1] - q0) > 0.1 * np.linalg.norm(q0)  # it moved


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_simulate_on_a_head_base_reports_the_body_frame():
    """The tip is from the base's tangent line (the lab-frame centreline's u(L) - u(0) -
    L u'(0)); psi stays the lab frame's, the slope of the lab-frame centreline along the
    beat direction (the psi of modes, orbits and data), the head's own rotation in it; the
    linear frequency is the head model's dominant mode's."""
    model = ax.models.seven(n_elements=4, base=BASES["head"])
    sim = ax.simulate(model, ax.Params(p=300.0), 0.05)
    assert sim.state in ("decaying", "limit_cycle", "growing", "settling", "divergent")
    u = sim.centreline_um
    x = sim.x_um
    slope0 = (u[:, :, 1] - u[:, :, 0]) / (x[1] - x[0])  # a first difference: loose checks
    tip = u[:, :, -1] - u[:, :, 0] - x[-1] * slope0
    big = np.abs(sim.tip_um).max()
    assert np.abs(tip - sim.tip_um).max() <= 0.05 * big
    e = np.array([np.cos(sim.beat_angle_rad), np.sin(sim.beat_angle_rad)])
    slope = np.gradient(np.einsum("tds,d->ts", u, e), x, axis=1)
    assert np.abs(slope - sim.psi_rad).max() <= 0.05 * np.abs(sim.psi_rad).max()
    assert np.abs(sim.psi_rad[:, 0]).max() > 0.05 * np.abs(sim.psi_rad).max()  # the head turns
    mode = ax.dominant_mode(model, ax.Params(p=300.0))
    assert sim.linear["frequency_hz"] == pytest.approx(float(mode.frequency_hz()))
