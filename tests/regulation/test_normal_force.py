"""Normal-force control (issue 55, first step; docs/model.md section 8): the augmented
pencil of :func:`axojax.assembly.assemble_normal` against independent references.

- ``axojax modes --mechanism normal-force`` against scipy's QZ on the assembled matrices;
- the two-filament continuum limit (issue 55 item 3): preset ``two`` at kl = ks = 1e6,
  p = 0, a uniform static moment m0, against a Chebyshev collocation of the continuum
  equations written here. With psi = psi_1, the static curvature c0(s) = C_0 L =
  mu (1 - s) (mu = m0 / 2: kappa = 2 EI), Phi = a F_1 L / kappa and phi = Phi' (the
  scaled force per length), Sartori's first mode at lambda is::

      lambda psi = -psi'''' + phi'',   phi = g c0 (Phi + psi')   (f_perp,1 = C_0 (F_1 + kappa psi'/a)),

  clamped at s = 0 (psi = 0, psi''' - phi' = 0) and free at s = 1 (psi' = 0,
  psi'' - phi = 0, Phi = 0). As a first-order system in y = (psi, psi', psi'' - phi,
  psi''' - phi', Phi) it needs first derivatives only (well conditioned); at
  lambda = i Sp the complex gains g at which i Sp is an eigenvalue are the eigenvalues of
  a linear pencil in g.
"""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg as sl
from scipy.integrate import solve_ivp
from scipy.interpolate import BarycentricInterpolator

import axojax as ax
from axojax.assembly import assemble_normal
from axojax.assembly.normal_force import static_curvature, static_forces
from axojax.assembly.terms import static_couple
from axojax.eigen import normal_force_mode
from axojax.fem import interpolation_matrix


# -- independent continuum reference ----------------------------------------------------
def _cheb(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev points s in [0, 1] (ascending) and d/ds (Trefethen's cheb)."""
    x = np.cos(np.pi * np.arange(n + 1) / n)
    c = np.hstack([2, np.ones(n - 1), 2]) * (-1) ** np.arange(n + 1)
    dx = x[:, None] - x[None, :]
    D = np.outer(c, 1 / c) / (dx + np.eye(n + 1))
    D -= np.diag(D.sum(axis=1))
    return (1 - x) / 2, -2 * D


def _hopf_gains(sp: float, mu: float, n: int = 40):
    """Gains g (ascending |g|) at which i sp is an eigenvalue of the continuum problem, the
    null vectors y (5 (n + 1),) and the points s."""
    s, D = _cheb(n)
    m = n + 1
    I, Z = np.eye(m), np.zeros((m, m))
    c0 = np.diag(mu * (1 - s))
    T0 = np.block(
        [
            [D, -I, Z, Z, Z],
            [Z, D, -I, Z, Z],
            [Z, Z, D, -I, Z],
            [1j * sp * I, Z, Z, D, Z],
            [Z, Z, Z, Z, D],
        ]
    ).astype(complex)
    T1 = np.block([[Z] * 5, [Z, -c0, Z, Z, -c0], [Z] * 5, [Z] * 5, [Z, -c0, Z, Z, -c0]])
    T1 = T1.astype(complex)

    def at(k, i):
        r = np.zeros(5 * m)
        r[k * m + i] = 1
        return r

    # y1(0) = y4(0) = 0 replace rows at s = 1; y2(1) = y3(1) = y5(1) = 0 rows at s = 0
    for row, bc in (
        (n, at(0, 0)),
        (3 * m + n, at(3, 0)),
        (m, at(1, n)),
        (2 * m, at(2, n)),
        (4 * m, at(4, n)),
    ):
        T0[row], T1[row] = bc, 0
    g, V = sl.eig(T0, -T1)
    keep = np.isfinite(g)
    g, V = g[keep], V[:, keep]
    order = np.argsort(np.abs(g))
    return g[order], V[:, order], s


def _shooting_residual(g: complex, sp: float, mu: float) -> float:
    """|det| of the tip conditions of the three solutions that meet the base's (scipy
    DOP853 on the same first-order system), columns normalised: 0 at a Hopf gain."""

    def rhs(s, y):
        phi = g * mu * (1 - s) * (y[4] + y[1])
        return [y[1], y[2] + phi, y[3], -1j * sp * y[0], phi]

    cols = []
    for k in (1, 2, 4):
        y0 = np.zeros(5, complex)
        y0[k] = 1
        end = solve_ivp(rhs, (0, 1), y0, method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
        cols.append([end[1], end[2], end[4]])
    M = np.array(cols).T
    return abs(np.linalg.det(M / np.linalg.norm(M, axis=0)))


def _r2(model_psi, ref):
    """Sartori's R^2 with a free complex amplitude on the model's psi_1."""
    c = np.vdot(model_psi, ref) / np.vdot(model_psi, model_psi)
    return 1 - np.sum(np.abs(ref - c * model_psi) ** 2) / np.sum(np.abs(ref - ref.mean()) ** 2)


SP, M0 = 200.0, 10.0


def test_reference_hopf_gain_is_a_shooting_root_and_converged():
    """The collocation's Hopf gain does not move with the number of points and zeroes the
    shooting determinant (an independent integration); a gain beside it does not."""
    g40 = _hopf_gains(SP, M0 / 2, 40)[0][0]
    g30 = _hopf_gains(SP, M0 / 2, 30)[0][0]
    assert abs(g40 - g30) < 1e-8 * abs(g40)
    assert _shooting_residual(g40, SP, M0 / 2) < 1e-3 * _shooting_residual(g40 * 1.05, SP, M0 / 2)


# -- the static state ----------------------------------------------------------------------
def test_static_state_of_a_uniform_moment_is_sartoris_balance():
    """``two`` at p = 0 with m0: kappa_0 = m0 (1 - x) / 2 (kappa = 2 EI) at every quadrature
    point, and the pairs' static forces carry the static couple (a0 F_0 = kappa C_0)."""
    model = ax.models.two(n_elements=6)
    params = ax.Params(p=0.0, kl=1e6, ks=1e6, m0=M0)
    x = np.asarray(model.mesh.x)
    np.testing.assert_allclose(
        np.asarray(jax.jit(static_curvature, static_argnums=0)(model, params))[0],
        M0 * (1 - x) / 2,
        rtol=1e-9,
        atol=1e-9,
    )
    seven = ax.models.seven(n_elements=4)
    prm = ax.Params(p=200.0, imbalance=3.0, m0=-5.0)
    forces = jax.jit(static_forces, static_argnums=0)(seven, prm)
    couple = prm.a0 * np.asarray(forces) @ np.asarray(seven.pair_w)
    expected = jax.jit(static_couple, static_argnums=0)(seven, prm)
    np.testing.assert_allclose(couple, expected, rtol=1e-12, atol=1e-12)


# -- the continuum limit (issue 55 item 3) -------------------------------------------------
def test_two_filament_limit_is_the_continuum_normal_force_hopf_point():
    """At the continuum's Hopf gain g (i Sp an eigenvalue, Sp = 200, m0 = 10) axojax's
    eigenvalue nearest i omega0 is within 0.5 % of it (here ~1e-4 at N_e = 20, converging
    like h^4), with the continuum's psi_1 (R^2 > 0.999)."""
    g, V, s_c = _hopf_gains(SP, M0 / 2)
    g = g[0]
    errors = []
    for n in (10, 20):
        model = ax.models.two(n_elements=n)
        params = ax.Params(
            p=0.0, kl=1e6, ks=1e6, m0=M0, normal_re=g.real, normal_im=g.imag, omega0=SP
        )
        mode = normal_force_mode(model, params, 1j * SP)
        errors.append(abs(complex(mode.eigenvalue) - 1j * SP) / SP)
    assert errors[-1] < 5e-3
    assert errors[0] > 8 * errors[1]
    s = np.linspace(0, 1, 201)
    v = np.asarray(mode.eigenvector)
    psi = interpolation_matrix(20, s, 1) @ ((v[:40] + v[40:80]) / 2)
    ref = BarycentricInterpolator(s_c, V[: s_c.size, 0])(s)
    assert _r2(psi, ref) > 0.999


# -- the command line against a dense independent eigen-solve ------------------------------
def _scipy_eigenvalues(model, params):
    system = assemble_normal(model, params)
    lam = sl.eig(-np.asarray(system.A), np.asarray(system.C), right=False)
    return lam[np.abs(lam) < 1e12]  # the infinite ones of g'' = 0 come out ~ 1e20 or inf


@pytest.mark.parametrize("gain,hz", [("-0.3256,-1.1576", "37.2"), ("0.4,0", None)])
def test_cli_modes_agrees_with_scipy_on_the_assembled_pencil(gain, hz, capsys):
    """``axojax modes --mechanism normal-force --normal-gain RE,IM --static-moment-pn PN``:
    its beat (with --omega0-hz) and dominant eigenvalues (a shift-and-invert in JAX) are
    those of scipy's QZ on the same assembled matrices to 1e-8, also with g'' = 0 (the
    force rows algebraic, C' singular)."""
    from axojax.cli.main import main

    argv = ["modes", "--model", "two", "--elements", "8", "--p", "0", "--kl", "1e6"]
    argv += ["--mechanism", "normal-force", "--normal-gain", gain, "--static-moment-pn", "5"]
    argv += ["--omega0-hz", hz] if hz else []
    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    u = ax.Units()
    re, im = (float(t) for t in gain.split(","))
    params = ax.Params(
        p=0.0,
        kl=1e6,
        m0=float(u.moment_from_pn(5.0)),
        normal_re=re,
        normal_im=im,
        omega0=float(u.omega0_from_hz(float(hz))) if hz else 0.0,
    )
    lam = _scipy_eigenvalues(ax.models.two(n_elements=8), params)
    rightmost = lam[np.argmax(lam.real)]
    d = doc["dominant"]["eigenvalue"]
    assert abs(complex(d[0], d[1]) - rightmost) < 1e-8 * abs(rightmost)
    listed = doc["eigenvalues"][0]
    assert abs(complex(*listed) - rightmost) < 1e-8 * abs(rightmost)
    if hz:
        w = 1j * params.omega0
        near = lam[np.argmin(np.abs(lam - w))]
        b = doc["beat"]["eigenvalue"]
        assert abs(complex(b[0], b[1]) - near) < 1e-8 * abs(near)
    assert main(argv) == 0  # the text report
    assert "normal-force control, gain" in capsys.readouterr().out


def test_zero_gain_leaves_the_spectrum_as_it_was():
    """With g = 0 the augmented pencil's finite eigenvalues are the plain model's (seven, an
    imbalance: a static bend and four pairs), and its q part of A, C is the plain one."""
    model = ax.models.seven(n_elements=3)
    params = ax.Params(imbalance=2.0, normal_re=0.0)
    plain = ax.assemble(model, params)
    lam_plain = sl.eig(-np.asarray(plain.A), np.asarray(plain.C), right=False)
    lam = _scipy_eigenvalues(model, params)
    assert lam.size == lam_plain.size
    key = lambda z: (np.round(z.real, 6), np.round(z.imag, 6))  # noqa: E731
    np.testing.assert_allclose(sorted(lam, key=key), sorted(lam_plain, key=key), rtol=1e-8)


def test_assembly_is_jit_and_vmap_able_in_the_gain():
    model = ax.models.two(n_elements=4)
    params = ax.Params(p=0.0, m0=M0, omega0=SP)
    gains = jnp.array([0.0, 0.3, -0.7])
    batch = jax.jit(
        jax.vmap(lambda g: assemble_normal(model, params.replace(normal_re=g, normal_im=g)).C)
    )(gains)
    for g, C in zip(np.asarray(gains), np.asarray(batch)):
        one = assemble_normal(model, params.replace(normal_re=float(g), normal_im=float(g)))
        np.testing.assert_allclose(C, np.asarray(one.C), rtol=1e-12, atol=1e-12)


# -- derivatives: the bordered solve against finite differences ---------------------------
@pytest.mark.parametrize("name", ["normal_re", "normal_im", "m0", "chi_re"])
@pytest.mark.parametrize("friction", [0.0, -0.9])
def test_beat_derivatives_equal_central_differences(name, friction):
    """d lambda / d(name) and d|psi|^2 / d(name) of the beat nearest i omega0
    (:class:`axojax.eigen.NormalForce`, jax.jvp through the bordered solve) equal
    fourth-order central differences of the same eigenpair (1e-6 relative), whose
    eigenvalue is scipy's QZ on the assembled pencil (1e-8), with g'' = 0 (C' singular)
    and g'' != 0 alike; |psi|^2 along the axoneme is free of the eigenvector's gauge."""
    model = ax.models.two(n_elements=6)
    params = ax.Params(
        p=0.0, kl=1e3, m0=M0, omega0=SP, normal_re=-0.3, normal_im=friction, chi_re=2.0
    )
    shift = 1j * SP
    solver = ax.eigen.NormalForce()
    x0 = float(getattr(params, name))

    def pair(x):
        lam, v, _ = solver.nearest(model, params.replace(**{name: x}), shift)
        return lam, jnp.abs(v) ** 2

    (lam, amp), (dlam, damp) = jax.jvp(pair, (x0,), (1.0,))
    ev = _scipy_eigenvalues(model, params)
    assert abs(complex(lam) - ev[np.argmin(np.abs(ev - shift))]) < 1e-8 * abs(complex(lam))
    h = 1e-3 * max(abs(x0), 1.0)
    lams, amps = zip(*(pair(x0 + k * h) for k in (-2, -1, 1, 2)))
    stencil = np.array([1.0, -8.0, 8.0, -1.0]) / (12 * h)
    fd_lam = stencil @ np.asarray(lams)
    fd_amp = stencil @ np.asarray(amps)
    assert abs(complex(dlam) - complex(fd_lam)) < 1e-6 * max(abs(complex(fd_lam)), 1.0), (
        dlam,
        fd_lam,
    )
    np.testing.assert_allclose(
        np.asarray(damp), fd_amp, rtol=1e-5, atol=1e-6 * np.abs(fd_amp).max()
    )


def test_the_solver_has_no_dominant_mode():
    """NormalForce follows the beat nearest a shift only (one line otherwise)."""
    with pytest.raises(ValueError, match="nearest"):
        ax.eigen.NormalForce().eigenpair(ax.models.two(n_elements=4), ax.Params(m0=M0))


# -- refusals, each in one line ------------------------------------------------------------
def _fit_normal_gain():
    from axojax.beats import Target
    from axojax.inverse import Condition, Problem

    condition = Condition({}, [Target("frequency_hz", 30.0, 1.0)])
    Problem(ax.models.two(n_elements=3), [condition], ["normal_re"])


@pytest.mark.parametrize(
    "call,word",
    [
        (lambda: ax.assemble(ax.models.two(n_elements=3), ax.Params(normal_re=0.5)), "normal_re"),
        (
            lambda: ax.dominant_mode(ax.models.two(n_elements=3), ax.Params(normal_re=0.5)),
            "normal_re",
        ),
        (
            lambda: assemble_normal(ax.models.two(n_elements=3).with_base("free"), ax.Params()),
            "'free'",
        ),
        (lambda: assemble_normal(ax.models.single(n_elements=3), ax.Params()), "'single'"),
        (
            lambda: assemble_normal(
                ax.models.two(n_elements=3), ax.Params(p_knots=np.array([1.0, 0.5]))
            ),
            "p_knots",
        ),
        (lambda: ax.Params(normal_im=0.5).validate(), "normal_im"),
        (lambda: _fit_normal_gain(), "normal_re"),
        (
            lambda: ax.sweep(ax.models.two(n_elements=3), ax.Params(), {"normal_re": [0.0, 1.0]}),
            "normal_re",
        ),
    ],
)
def test_library_refuses_in_one_line(call, word):
    with pytest.raises(ValueError) as err:
        call()
    assert word in str(err.value) and "\n" not in str(err.value)


NF = ["--mechanism", "normal-force", "--normal-gain"]


@pytest.mark.parametrize(
    "argv,flag",
    [
        (["modes", "--normal-gain", "1,0"], "--normal-gain"),
        (["modes", "--mechanism", "normal-force"], "--normal-gain"),
        (["modes", *NF, "1"], "--normal-gain"),
        (["modes", *NF, "1,0", "--p", "0"], "no static normal force"),
        (["modes", *NF, "1,2", "--static-moment-pn", "5"], "--omega0-hz"),
        (["modes", *NF, "1,0", "--p", "100", "--grad", "p"], "--grad"),
        (["modes", *NF, "1,0", "--p", "9", "--base", "free"], "clamped"),
        (["simulate", *NF, "1,0", "--t-end", "0.1"], "only axojax modes"),
    ],
)
def test_cli_refuses_in_one_line(argv, flag, capsys):
    from axojax.cli.main import main

    assert main([argv[0], "--model", "two", "--elements", "4", *argv[1:]]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and flag in err
