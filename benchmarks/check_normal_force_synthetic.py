"""Normal-force rows on synthetic beats (issue 55's second acceptance item).

Ten asymmetric Chlamydomonas-sized beats made with normal-force control and ten made
with curvature control (12 um, 50-70 Hz, static curvature -0.15 to -0.2 rad/um, the
``chlamydomonas`` organism's kappa and xi_n, preset ``two`` at 16 elements, seeds 0-9):

- normal-force: the static moment whose equilibrium has the drawn static curvature, the
  gain of smallest modulus at which i omega0 is an eigenvalue of the augmented pencil
  (scipy, on the assembled matrices: K0 + g U_g is singular), psi_1 of that mode;
- curvature: chi' = 0 and the beta of smallest modulus at which i omega0 is an
  eigenvalue (scipy), psi_1 of that mode; psi_0 the same static line as above;

psi_1 scaled to a peak of 0.9 rad, noise of 5 % of the mean |psi_1| on Re and Im of psi_1
and that over sqrt 2 on psi_0 (a kymograph's ratio: the same frames average to both),
the base angle 0.5 rad. Each is compared (:func:`axojax.compare`, clamped base, the
regulated mechanisms: sliding, curvature, sliding+curvature, normal-force,
sliding+normal-force). Printed per beat: the normal-force row's status, its dBIC to the
best row, |g - truth| / SE (the row's reported error: the data's and the measured static
curvature's, :func:`~axojax.inverse.comparison.static_state.add_static_errors`), the best
row and the verdict's indistinguishable rows.
Acceptance: on the normal-force beats the row converges in all ten, is within 2 BIC of
the best in at least 8 and recovers g within 2 SE in at least 8; on the curvature beats
it is not ahead of the curvature row by more than 2 BIC in at least 8.

    python benchmarks/check_normal_force_synthetic.py [--beats 10] [--elements 16]
        [--truths normal-force,curvature]

Timings are for one machine and one run, not assertions (the machine may be shared).
"""

from __future__ import annotations

import argparse
import pathlib
import tempfile
import time
import warnings

import numpy as np
import scipy.linalg as sl

import axojax as ax
from axojax.assembly import assemble, assemble_normal
from axojax.assembly.normal_force import passive_equilibrium
from axojax.beats.targets import ShapeTarget
from axojax.eigen import normal_force_mode
from axojax.inverse.comparison.mechanisms import build_model, row
from axojax.inverse.comparison.static_state import matching_moment
from axojax.inverse.comparison.synthetic import write_fourier_modes
from axojax.inverse.predictions import model_psi1
from axojax.units import ORGANISMS
from axojax.waveform.shapes import centreline

LENGTH_UM, POINTS, BASE_ANGLE, PEAK = 12.0, 31, 0.5, 0.9
MECHANISMS = ["sliding", "curvature", "sliding+curvature", "normal-force", "sliding+normal-force"]


def smallest_root(k0: np.ndarray, unit: np.ndarray) -> complex:
    """The g of smallest modulus with k0 + g unit singular (scipy's QZ)."""
    g = sl.eig(k0, -unit, right=False)
    g = g[np.isfinite(g) & (np.abs(g) < 1e12)]
    return complex(g[np.argmin(np.abs(g))])


def make_beat(path, truth: str, seed: int, elements: int):
    """Write the beat (module docstring) to ``path``; return the truth's gain or beta."""
    rng = np.random.default_rng(seed)
    hz, c0 = 50.0 + 20.0 * rng.random(), -0.15 - 0.05 * rng.random()
    units = ORGANISMS["chlamydomonas"].flagellum.units(LENGTH_UM, 2)
    model = build_model("two", elements, "clamped", units)
    s = np.linspace(0.0, LENGTH_UM, POINTS)
    line = ShapeTarget(s, np.ones(POINTS, complex), 0.01, psi0=c0 * s)
    spec = row("normal-force", "clamped", model, units, hz)
    prm = spec.params.replace(m0=matching_moment(model, spec.params, line, units))
    w = 1j * float(prm.omega0)
    normal = truth == "normal-force"
    field = "normal" if normal else "beta"

    def pencil(p):  # at lambda = i omega0, linear in the complex gain of ``field``
        m = (assemble_normal if normal else assemble)(model, p)
        return np.asarray(m.A) + w * np.asarray(m.C)

    k0 = pencil(prm)
    value = smallest_root(k0, pencil(prm.replace(**{f"{field}_re": 1.0})) - k0)
    params = prm.replace(**{f"{field}_re": value.real, f"{field}_im": value.imag})
    if normal:
        mode = normal_force_mode(model, params, w)
    else:
        mode = ax.nearest_mode(model, params, w, solver=ax.eigen.Dense())
    psi1 = np.asarray(model_psi1(model, mode, s / LENGTH_UM))
    psi1 = PEAK * psi1 / np.abs(psi1).max() * np.exp(2j * np.pi * rng.random())
    q0 = np.asarray(passive_equilibrium(model, prm))
    psi0 = np.asarray(centreline(model, q0[None], s / LENGTH_UM, 1))[0, 0] + BASE_ANGLE
    noise = 0.05 * float(np.mean(np.abs(psi1)))
    psi1 = psi1 + noise * (rng.normal(size=POINTS) + 1j * rng.normal(size=POINTS))
    psi0 = psi0 + noise / np.sqrt(2.0) * rng.normal(size=POINTS)  # a kymograph's ratio
    write_fourier_modes(path, s, psi1, noise, hz, LENGTH_UM, psi0=psi0)
    return value


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--beats", type=int, default=10)
    p.add_argument("--elements", type=int, default=16)
    p.add_argument("--truths", default="normal-force,curvature")
    args = p.parse_args()
    tally = {"nf_converged": 0, "nf_close": 0, "nf_recovered": 0, "cv_not_ahead": 0}
    with tempfile.TemporaryDirectory() as folder, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for truth in args.truths.split(","):
            for seed in range(args.beats):
                t0 = time.perf_counter()
                path = pathlib.Path(folder) / f"{truth}_{seed}.npz"
                value = make_beat(path, truth, seed, args.elements)
                result = ax.compare(
                    path,
                    mechanisms=MECHANISMS,
                    bases=["clamped"],
                    compliance=False,
                    n_elements=args.elements,
                    organism="chlamydomonas",
                )
                rows = {r.mechanism: r for r in result.rows}
                nf, cv = rows["normal-force"], rows["curvature"]
                best = result.rows[0]
                d_bic = None if nf.delta_bic is None else nf.delta_bic
                line = (
                    f"{truth:13s} seed {seed}  normal-force {nf.status:28s} dBIC "
                    f"{d_bic if d_bic is not None else float('nan'):8.2f}  best {best.mechanism}"
                )
                if truth == "normal-force":
                    z = max(  # the row's errors: the data's and the static state's
                        abs(nf.params.get(n, np.nan) - v) / (nf.physical_stderr.get(n) or np.nan)
                        for n, v in (("normal_re", value.real), ("normal_im", value.imag))
                    ) if nf.fit is not None else float("nan")  # fmt: skip
                    tally["nf_converged"] += nf.successful
                    tally["nf_close"] += d_bic is not None and d_bic <= 2.0
                    tally["nf_recovered"] += bool(z <= 2.0)
                    line += f"  |g - truth| {z:5.2f} SE"
                else:
                    ahead = nf.bic is not None and cv.bic is not None and cv.bic - nf.bic > 2.0
                    tally["cv_not_ahead"] += not ahead
                    line += f"  curvature dBIC {cv.delta_bic if cv.delta_bic is not None else float('nan'):6.2f}"
                close = result.to_json()["verdict"].get("indistinguishable", [])
                line += f"  indistinguishable: {', '.join(close) or '-'}"
                print(line + f"  {time.perf_counter() - t0:5.0f} s", flush=True)
    n = args.beats
    print(
        f"normal-force beats: converged {tally['nf_converged']}/{n} (need {n}), within 2 BIC "
        f"{tally['nf_close']}/{n} (need {int(0.8 * n)}), g within 2 SE {tally['nf_recovered']}/{n} "
        f"(need {int(0.8 * n)}); curvature beats: normal-force not ahead by > 2 BIC "
        f"{tally['cv_not_ahead']}/{n} (need {int(0.8 * n)})"
    )


if __name__ == "__main__":
    main()
