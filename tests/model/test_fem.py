"""Filament matrices against textbook closed forms of the cubic Hermite beam element."""

import numpy as np
import pytest

from axojax.fem import Profiles, filament_matrices, interpolation_matrix, make_mesh


def element_closed_forms(h):
    k = (
        np.array(
            [
                [12, 6 * h, -12, 6 * h],
                [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                [-12, -6 * h, 12, -6 * h],
                [6 * h, 2 * h * h, -6 * h, 4 * h * h],
            ]
        )
        / h**3
    )
    m = (
        h
        / 420
        * np.array(
            [
                [156, 22 * h, 54, -13 * h],
                [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                [54, 13 * h, 156, -22 * h],
                [-13 * h, -3 * h * h, -22 * h, 4 * h * h],
            ]
        )
    )
    d = (
        1
        / (30 * h)
        * np.array(
            [
                [36, 3 * h, -36, 3 * h],
                [3 * h, 4 * h * h, -3 * h, -h * h],
                [-36, -3 * h, 36, -3 * h],
                [3 * h, -h * h, -3 * h, 4 * h * h],
            ]
        )
    )
    return k, m, d


def assemble_closed(ne):
    h = 1 / ne
    k, m, d = element_closed_forms(h)
    n = 2 * (ne + 1)
    out = [np.zeros((n, n)) for _ in range(3)]
    for e in range(ne):
        sl = slice(2 * e, 2 * e + 4)
        for big, small in zip(out, (k, m, d)):
            big[sl, sl] += small
    return [a[2:, 2:] for a in out]


@pytest.mark.parametrize("ne", [1, 3, 10])
def test_matrices_match_closed_forms(ne):
    mats = filament_matrices(make_mesh(ne))
    K, M, D = assemble_closed(ne)
    np.testing.assert_allclose(mats.K0, K, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(mats.M0, M, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(mats.D0, D, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(mats.Mk, M, rtol=1e-12, atol=1e-14)


def test_follower_matrices_identities():
    mats = filament_matrices(make_mesh(6))
    # F0 + F0^T = int (phi phi^T)' = phi(1) phi(1)^T (clamped base)
    tip = interpolation_matrix(6, np.array([1.0]))[0]
    np.testing.assert_allclose(mats.F0 + mats.F0.T, np.outer(tip, tip), atol=1e-12)
    # G0 with weight (1 - x): symmetric, and G0 + int x phi'phi'^T = D0 (checked with an independent quadrature)
    x = np.linspace(0, 1, 20001)
    dphi = interpolation_matrix(6, x, 1)
    wts = np.full_like(x, x[1])
    wts[[0, -1]] /= 2
    G_ref = np.einsum("q,qr,qs->rs", wts * (1 - x), dphi, dphi)
    np.testing.assert_allclose(mats.G0, G_ref, atol=1e-6)
    np.testing.assert_allclose(mats.G0, mats.G0.T, atol=1e-13)


def test_profiles_uniform_equal_default_and_scale():
    mesh = make_mesh(5)
    plain = filament_matrices(mesh)
    ones = filament_matrices(
        mesh,
        Profiles(
            ei=lambda x: np.ones_like(x), p=lambda x: np.ones_like(x), k=lambda x: 1.0 + 0 * x
        ),
    )
    for name in ("K0", "G0", "F0", "Mk"):
        np.testing.assert_allclose(getattr(ones, name), getattr(plain, name), atol=1e-12)
    double = filament_matrices(mesh, Profiles(ei=lambda x: 2.0 + 0 * x))
    np.testing.assert_allclose(double.K0, 2 * plain.K0, rtol=1e-12)
    with pytest.raises(ValueError, match="profile 'ei'"):
        filament_matrices(mesh, Profiles(ei=lambda x: -x))


def test_interpolation_reproduces_cubic():
    # u = x^2 (1 - x/3) is cubic: nodal values/slopes reproduce it exactly.
    ne = 4
    nodes = np.arange(1, ne + 1) / ne
    q = np.ravel(np.column_stack([nodes**2 - nodes**3 / 3, 2 * nodes - nodes**2]))
    x = np.linspace(0, 1, 37)
    np.testing.assert_allclose(interpolation_matrix(ne, x) @ q, x**2 - x**3 / 3, atol=1e-13)
    np.testing.assert_allclose(interpolation_matrix(ne, x, 1) @ q, 2 * x - x**2, atol=1e-12)


def test_models_built_alike_are_equal_and_share_compiled_programs():
    """A model is a static argument of jax.jit, compared by value: two calls of a preset
    give equal models (one compiled program between them); any difference of structure,
    mesh, imbalance reading or profile makes them unequal."""
    import jax

    import axojax as ax
    from axojax.eigen.mode import dominant_mode_impl

    a, b = ax.models.two(n_elements=2), ax.models.two(n_elements=2)
    assert a is not b and a == b and hash(a) == hash(b)
    ramp = lambda x: 1.0 + x  # noqa: E731
    others = [
        ax.models.two(n_elements=3),
        ax.models.single(n_elements=2),
        a.with_imbalance_kind("force"),
        ax.models.seven(n_elements=2),
        ax.models.seven(n_elements=2, rotation_deg=10.0),
        ax.models.two(n_elements=2, profiles=Profiles(ei=ramp)),
    ]
    for other in others:
        assert a != other
    assert others[3] != others[4]
    assert ax.models.two(n_elements=2, profiles=Profiles(ei=ramp)) == ax.models.two(
        n_elements=2, profiles=Profiles(ei=ramp)
    )
    f = jax.jit(
        lambda model, p: dominant_mode_impl(model, ax.Params(p=p), ax.eigen.Dense()).eigenvalue,
        static_argnums=0,
    )
    assert complex(f(a, 300.0)) == complex(f(b, 300.0))
    assert f._cache_size() == 1
    f(others[0], 300.0)
    assert f._cache_size() == 2


def test_a_models_arrays_cannot_be_edited_in_place():
    """Compiled programs hold a model's values (it is a static argument, compared by value
    once): an edit in place would silently not reach them, so it is refused."""
    import axojax as ax

    model = ax.models.two(n_elements=2)
    for arr in (model.link_B, model.matrices.K0, model.mesh.phi, model.section.positions):
        with pytest.raises(ValueError, match="read-only"):
            arr[...] = 0.0


def test_models_copy_their_inputs_and_pickle_without_their_key():
    """The model freezes its own copies, not the caller's arrays; a pickled or copied model
    is frozen again and keyed anew."""
    import copy
    import pickle

    from axojax.models.section import ActivePair, CrossSection, Link, build_model

    pos, ei = np.array([[0.0, 0.0], [1.0, 0.0]]), np.array([1.0, 2.0])
    model = build_model(
        CrossSection("u", pos, links=(Link(0, 1),), active_pairs=(ActivePair(0, 1),), ei=ei), 2
    )
    pos[0, 0], ei[0] = 0.5, 3.0  # the caller's arrays stay the caller's
    assert model.section.positions[0, 0] == 0.0 and model.section.ei[0] == 1.0
    hash(model)
    for twin in (pickle.loads(pickle.dumps(model)), copy.deepcopy(model)):
        assert "_key" not in vars(twin)  # keyed anew, from its own arrays
        assert twin == model and hash(twin) == hash(model)
        with pytest.raises(ValueError, match="read-only"):
            twin.link_B[...] = 0.0
