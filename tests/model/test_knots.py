"""Non-uniform EI(x), drag c(x) and dynein force p(x) at knots (docs/model.md section 8).

The reference is independent of axojax: the strong form of the `single` preset's
equations, (EI u'')'' + N(x) u'' + lambda c u = 0 with N(x) = p int_x^1 p(s) ds (a
follower load), clamped at x = 0 and free at x = 1, solved by shooting with scipy's
DOP853 across the knots (where the profiles have kinks) and a root of the tip
determinant.
"""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import root

import axojax as ax
from axojax.assembly import assemble, assemble_blocks
from axojax.eigen.solvers import Arnoldi, Dense

KNOTS = (0.0, 0.33, 0.71, 1.0)  # not on element boundaries of N_e = 10, 20, 40
EI = np.array([3.0, 1.6, 1.0, 0.7])
DRAG = np.array([1.5, 1.0, 1.0, 2.0])
PK = np.array([0.0, 1.0, 1.4, 0.8])
P = 90.0  # above the flutter load: a complex pair


def _linear(values, x):
    return np.interp(x, KNOTS, values)


def _tail(x: float) -> float:
    """N(x) = P int_x^1 p(s) ds, exactly (trapezoids of a piecewise-linear p)."""
    t, total = np.asarray(KNOTS), 0.0
    for j in range(len(t) - 1):
        a, b = max(x, t[j]), t[j + 1]
        if b > a:
            total += (_linear(PK, a) + PK[j + 1]) / 2 * (b - a)
    return P * total


def _tip_determinant(lam: complex) -> complex:
    """det [M(1), V(1)] of the two solutions with u(0) = u'(0) = 0 (state u, u', M, V)."""

    def rhs(x, y):
        u, _, M, V = y
        ei = _linear(EI, x)
        return [y[1], M / ei, V, -_tail(x) * M / ei - lam * _linear(DRAG, x) * u]

    columns = []
    for start in ([0, 0, 1, 0], [0, 0, 0, 1]):
        y = np.array(start, dtype=complex)
        for a, b in zip(KNOTS[:-1], KNOTS[1:]):
            y = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=1e-12, atol=1e-14).y[:, -1]
        columns.append(y[2:])
    return complex(np.linalg.det(np.array(columns).T))


def _params(**extra):
    return ax.Params(
        p=P,
        ei_knots=jnp.asarray(EI),
        drag_knots=jnp.asarray(DRAG),
        p_knots=jnp.asarray(PK),
        **extra,
    )


def test_single_filament_converges_to_the_shooting_reference():
    lams = {}
    for n in (10, 20, 40):
        model = ax.models.single(n).with_knots(KNOTS)
        lams[n] = complex(ax.dominant_mode(model, _params(), Dense()).eigenvalue)
    guess = lams[40]

    def equations(z):
        d = _tip_determinant(z[0] + 1j * z[1])
        return [d.real, d.imag]

    sol = root(equations, [guess.real, guess.imag], tol=1e-13)
    assert sol.success
    ref = sol.x[0] + 1j * sol.x[1]
    assert abs(ref.imag) > 100  # a flutter pair, so the follower load p(x) matters
    err = {n: abs(lam - ref) / abs(ref) for n, lam in lams.items()}
    assert err[40] < 1e-5
    assert err[10] / err[20] > 8 and err[20] / err[40] > 8
    # and the profiles matter: the uniform beam's eigenvalue is far away
    uniform = complex(ax.dominant_mode(ax.models.single(40), ax.Params(p=P), Dense()).eigenvalue)
    assert abs(uniform - ref) / abs(ref) > 0.1


@pytest.mark.parametrize("name", ["seven", "two_free", "two_head_compliance"])
def test_unit_knots_equal_the_uniform_model(name):
    model = {
        "seven": lambda: ax.models.seven(6),
        "two_free": lambda: ax.models.two(6, base="free"),
        "two_head_compliance": lambda: ax.models.two(
            6,
            base=ax.models.Base(
                "head", compliance=True, translational_drag=1.0, rotational_drag=0.1
            ),
        ),
    }[name]()
    base = ax.Params(p=120.0, imbalance=1.5, kb=3.0, xib=0.5, chi_re=2.0, beta_im=1.0, omega0=5.0)
    ones = base.replace(ei_knots=jnp.ones(4), drag_knots=jnp.ones(3), p_knots=jnp.ones(5))
    for assembler in (assemble, assemble_blocks):
        a, b = assembler(model, base), assembler(model, ones)
        for x, y in zip(jax.tree.leaves(a), jax.tree.leaves(b)):
            scale = max(1.0, float(jnp.max(jnp.abs(x)))) if x.size else 1.0
            assert float(jnp.max(jnp.abs(x - y), initial=0.0)) <= 1e-12 * scale


@pytest.mark.slow  # issue 53: the quick suite within 20 CPU-minutes, cold (CI runs -m slow)
def test_structured_equals_dense_and_gradients_equal_finite_differences():
    model = ax.models.seven(4)
    prm = ax.Params(p=260.0)
    profiles = (jnp.array([2.0, 1.0, 1.0]), jnp.array([1.0, 1.5]), jnp.array([1.0, 1.2, 0.6]))
    fields = ("ei_knots", "drag_knots", "p_knots")

    def eigenvalue(values, solver):
        return ax.dominant_mode(model, prm.replace(**dict(zip(fields, values))), solver).eigenvalue

    dense = eigenvalue(profiles, Dense())
    structured = eigenvalue(profiles, Arnoldi())
    assert abs(complex(dense - structured)) < 1e-8 * abs(complex(dense))

    growth = jax.jit(lambda values: eigenvalue(values, Dense()).real)
    h = 1e-3  # the seven-filament eigenvalue carries ~1e-9 of noise (ks = 1e6)
    for solver in (Dense(), Arnoldi()):
        grads = jax.grad(lambda values: eigenvalue(values, solver).real)(profiles)
        for i, v in enumerate(profiles):
            fd = []
            for k in range(v.shape[0]):
                up = tuple(w.at[k].add(h) if j == i else w for j, w in enumerate(profiles))
                down = tuple(w.at[k].add(-h) if j == i else w for j, w in enumerate(profiles))
                fd.append((growth(up) - growth(down)) / (2 * h))
            fd = np.array(fd)
            np.testing.assert_allclose(
                np.asarray(grads[i]), fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max()
            )


def test_a_batch_of_profiles_maps_like_a_loop():
    model = ax.models.two(6)
    values = jnp.array([[1.0, 1.0, 1.0], [3.0, 1.0, 0.5], [0.5, 2.0, 1.0]])
    batch = ax.Params(p=150.0).replace(ei_knots=values).broadcast()
    assert batch.ei_knots.shape == (3, 3) and np.shape(batch.p) == (3,)
    mapped = jax.vmap(lambda prm: ax.dominant_mode(model, prm).eigenvalue)(batch)
    for i in range(3):
        one = ax.dominant_mode(model, ax.Params(p=150.0, ei_knots=values[i])).eigenvalue
        assert abs(complex(mapped[i] - one)) < 1e-9 * abs(complex(one))


@pytest.mark.parametrize(
    "build, params, message",
    [
        (
            lambda: ax.models.two(4).with_knots((0, 0.5, 1)),
            {"ei_knots": [1.0, 2.0]},
            "ei_knots has 2 values but the model has 3 knots",
        ),
        (lambda: ax.models.two(4), {"p_knots": [1.0]}, "p_knots needs values at K >= 2 knots"),
        (lambda: ax.models.two(4), {"drag_knots": [1.0, -1.0]}, "drag_knots must be finite, >= 0"),
        (lambda: ax.models.two(4), {"ei_knots": [1.0, float("nan")]}, "ei_knots must be finite"),
        (
            lambda: ax.models.beck(4),
            {"p_knots": [1.0, 1.0]},
            "p_knots: the beck preset's load is a tip force",
        ),
        (
            lambda: ax.models.two(4, profiles=ax.models.Profiles(ei=lambda x: 2 - x)),
            {"ei_knots": [1.0, 1.0]},
            "already has a static ei profile",
        ),
    ],
)
def test_bad_profiles_are_one_line_errors(build, params, message):
    with pytest.raises(ValueError, match=message) as err:
        ax.dominant_mode(build(), ax.Params(**{k: jnp.asarray(v) for k, v in params.items()}))
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("knots", [(0, 1), (0.0, 0.2, 1.0), np.linspace(0, 1, 7)])
def test_valid_knots_are_accepted(knots):
    model = ax.models.two(4).with_knots(knots)
    prm = ax.Params(p=100.0, ei_knots=jnp.ones(len(knots)))
    uniform = ax.dominant_mode(ax.models.two(4), ax.Params(p=100.0)).eigenvalue
    assert abs(complex(ax.dominant_mode(model, prm).eigenvalue - uniform)) < 1e-9 * abs(
        complex(uniform)
    )


@pytest.mark.parametrize("knots", [(0.0,), (0.1, 1.0), (0.0, 0.5, 0.4, 1.0), (0.0, float("inf"))])
def test_bad_knot_positions_are_one_line_errors(knots):
    with pytest.raises(ValueError, match="knots must") as err:
        ax.models.two(4).with_knots(knots)
    assert "\n" not in str(err.value)


# ---- the command line: --ei-knots, --drag-knots, --p-knots, --knots (docs/interface.md)

CLI_MODEL = ["--model", "two", "--elements", "4", "--p", "120", "--top", "1", "--json"]


def _cli(argv, capsys):
    from axojax.cli.main import main

    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize(
    "flags, knots, values",
    [
        (["--ei-knots", "3,1,1"], None, {"ei_knots": [3.0, 1.0, 1.0]}),
        (
            ["--drag-knots", "1,2", "--p-knots", "0,1,1,1"],
            None,
            {"drag_knots": [1.0, 2.0], "p_knots": [0.0, 1, 1, 1]},
        ),
        (
            ["--ei-knots", "3,3,1", "--knots", "0,0.2,1"],
            (0.0, 0.2, 1.0),
            {"ei_knots": [3.0, 3.0, 1.0]},
        ),
    ],
)
def test_cli_profiles_build_the_library_model(flags, knots, values, capsys):
    code, out, err = _cli(["modes", *CLI_MODEL, *flags], capsys)
    assert code == 0, err
    model = ax.models.two(4).with_knots(knots)
    prm = ax.Params(p=120.0, **{k: jnp.asarray(v) for k, v in values.items()})
    expected = complex(ax.dominant_mode(model, prm).eigenvalue)
    got = json.loads(out)["dominant"]["eigenvalue"]
    assert abs(complex(got[0], got[1]) - expected) < 1e-9 * abs(expected)
    uniform = complex(ax.dominant_mode(ax.models.two(4), ax.Params(p=120.0)).eigenvalue)
    assert abs(uniform - expected) > 1e-3 * abs(expected)  # the profile was applied


@pytest.mark.parametrize(
    "flags, flag",
    [
        (["--ei-knots", "3"], "--ei-knots"),
        (["--ei-knots", "3,x"], "--ei-knots"),
        (["--drag-knots", "1,-2"], "--drag-knots"),
        (["--p-knots", "1,1e300"], "--p-knots"),
        (["--ei-knots", "3,1", "--knots", "0,0.5,1"], "--ei-knots"),
        (["--ei-knots", "3,1", "--knots", "0,0.7"], "--knots"),
        (["--knots", "0,1"], "--knots"),
    ],
)
def test_cli_bad_profiles_are_one_line_errors(flags, flag, capsys):
    code, out, err = _cli(["modes", *CLI_MODEL, *flags], capsys)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and f"error: {flag}:" in err


def test_cli_tip_load_refuses_a_force_profile(capsys):
    code, _, err = _cli(["modes", "--model", "beck", "--elements", "4", "--p-knots", "1,0"], capsys)
    assert code == 2 and "error: --p-knots:" in err and err.count("\n") == 1


# ---- knot values as fitted parameters


@pytest.mark.slow  # a multi-start fit: ~10 s each
def test_a_knot_value_is_fitted_like_a_field():
    """A basal stiffening ei_knots[0] and p recovered from the frequency and wavelength
    they produce (two filaments, 6 elements); the names, start and bounds of a knot value
    work as a field's do."""
    model = ax.models.two(6)
    truth = ax.Params(p=180.0, ei_knots=jnp.array([2.5, 1.0, 1.0]))
    mode = ax.dominant_mode(model, truth)
    targets = [
        ax.beats.Target(
            "frequency_hz", float(mode.frequency_hz()), 1e-3 * float(mode.frequency_hz())
        ),
        ax.beats.Target(
            "wavelength_um", float(mode.wavelength_um()), 1e-3 * float(mode.wavelength_um())
        ),
    ]
    start = ax.Params(p=160.0, ei_knots=jnp.array([1.5, 1.0, 1.0]))
    result = ax.fit(
        model, start, targets, ["p", "ei_knots[0]"], starts=2, bounds={"p": (50.0, 500.0)}
    )
    values = result.params
    assert abs(values["ei_knots[0]"] - 2.5) < 1e-3 * 2.5
    assert abs(values["p"] - 180.0) < 1e-3 * 180.0


def test_knot_value_names_are_checked():
    prm = ax.Params(ei_knots=jnp.array([2.0, 1.0]))
    assert float(prm.replace(**{"ei_knots[1]": 3.0}).ei_knots[1]) == 3.0
    assert float(prm.value_of("ei_knots[0]")) == 2.0
    with pytest.raises(ValueError, match=r"ei_knots\[2\]: ei_knots has 2 knot values"):
        prm.replace(**{"ei_knots[2]": 1.0})
    with pytest.raises(ValueError, match=r"p_knots\[0\]: p_knots has 0 knot values"):
        prm.replace(**{"p_knots[0]": 1.0})
    with pytest.raises(ValueError, match="unknown parameter"):
        prm.replace(**{"ei_knot[0]": 1.0})


@pytest.mark.slow  # a multi-start fit: ~10 s each
def test_cli_fits_a_knot_value(capsys):
    argv = ["fit", "--model", "two", "--elements", "6", "--p", "160", "--ei-knots", "1.5,1,1"]
    argv += ["--free", "p,ei-knots[0]", "--target-frequency", "20", "--target-wavelength", "17.5"]
    code, out, err = _cli([*argv, "--json"], capsys)
    assert code == 0, err
    doc = json.loads(out)
    values = doc["params"]
    assert set(values) == {"p", "ei_knots[0]"}
    # the fitted point, rebuilt in the library, has the targets' frequency and wavelength
    prm = ax.Params(p=values["p"], ei_knots=jnp.array([values["ei_knots[0]"], 1.0, 1.0]))
    mode = ax.dominant_mode(ax.models.two(6), prm)
    assert abs(float(mode.frequency_hz()) - 20.0) < 0.05 * 20 * 2
    assert abs(float(mode.wavelength_um()) - 17.5) < 0.05 * 17.5 * 2
    code, _, err = _cli([*argv[:-4], "--free", "p,ei-knots[3]", "--target-frequency", "20"], capsys)
    assert code == 2 and err.count("\n") == 1 and "ei_knots[3]" in err
