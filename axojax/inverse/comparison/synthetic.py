"""A beat made with one row of a comparison: the check that ``compare`` finds what made it
(benchmarks/check_compare_synthetic.py, tests/comparison/test_nested.py), and a way for a user
to try the pipeline on a beat whose truth is known.

:func:`synthetic_beat` takes the row (mechanism, base) on the ``two`` preset in an
organism's units (:data:`axojax.units.ORGANISMS`: its kappa and xi_n) at one of the row's
exact Hopf points at the given frequency (so both pins hold), scales its psi_1 to a peak
of ``peak_rad`` and adds Gaussian noise of ``noise_rad`` on each of Re and Im; the result
is a Fourier-mode beat file (docs/own_beat.md) with that sigma and a 1 % frequency sigma.
"""

from __future__ import annotations

import pathlib

import numpy as np

from ...beats import ShapeTarget
from ...units import ORGANISMS
from .mechanisms import build_model, row, row_problem
from .starts import hopf_starts, values_to_u


def synthetic_beat(
    path: str | pathlib.Path,
    organism: str,
    truth: tuple[str, str],
    length_um: float,
    frequency_hz: float,
    rng: np.random.Generator,
    *,
    n_elements: int = 16,
    points: int = 41,
    peak_rad: float = 0.8,
    noise_rad: float = 0.02,
) -> tuple[str, dict[str, float]]:
    """Write the beat of row ``truth`` = (mechanism, base) for ``organism`` to ``path``
    (a ``.npz`` Fourier-mode file: ``points`` arc lengths over ``length_um`` um, the
    frequency in Hz) and return the path and the truth's values (dimensionless, by name).
    One-line ``ValueError`` when the row has no Hopf point at that frequency."""
    units = ORGANISMS[organism].flagellum.units(length_um, 2)
    spec = row(*truth, build_model("two", n_elements, truth[1], units), units, frequency_hz)
    s = np.linspace(0.0, length_um, points)
    problem = row_problem(spec, ShapeTarget(s, np.exp(-1j * s / length_um), 1.0), units)
    hopf = values_to_u(problem, hopf_starts(spec))
    if not len(hopf):
        raise ValueError(f"truth: {'/'.join(truth)} has no Hopf point at {frequency_hz:g} Hz")
    u = hopf[rng.integers(len(hopf))]
    psi1 = np.asarray(problem.evaluate(u)["conditions"][0]["psi1_fit"])
    psi1 = peak_rad * psi1 / np.abs(psi1).max()
    psi1 = psi1 + noise_rad * (rng.normal(size=s.size) + 1j * rng.normal(size=s.size))
    write_fourier_modes(path, s, psi1, noise_rad, frequency_hz, length_um, psi0=np.zeros_like(s))
    return str(path), problem.values(u)


def write_fourier_modes(
    path,
    s_um: np.ndarray,
    psi1: np.ndarray,
    sigma_rad,
    frequency_hz: float,
    length_um: float,
    *,
    psi0: np.ndarray | None = None,
    frequency_sigma_hz: float | None = None,
) -> None:
    """Write a Fourier-mode beat file (docs/own_beat.md: ``s_um``, ``psi1_re_rad``,
    ``psi1_im_rad``, ``psi1_sigma_rad``, ``psi0_rad`` when given, ``length_um``,
    ``frequency_hz`` and ``frequency_sigma_hz``, default 1 % of the frequency) to ``path``."""
    s_um = np.asarray(s_um, dtype=float)
    psi1 = np.asarray(psi1, dtype=complex)
    fields = dict(
        s_um=s_um,
        psi1_re_rad=psi1.real,
        psi1_im_rad=psi1.imag,
        psi1_sigma_rad=np.broadcast_to(np.asarray(sigma_rad, dtype=float), s_um.shape),
        length_um=length_um,
        frequency_hz=frequency_hz,
        frequency_sigma_hz=0.01 * frequency_hz
        if frequency_sigma_hz is None
        else frequency_sigma_hz,
    )
    if psi0 is not None:
        fields["psi0_rad"] = np.asarray(psi0, dtype=float)
    np.savez(path, **fields)
