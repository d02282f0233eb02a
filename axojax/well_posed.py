"""Whether the time domain of a model is well posed: no active friction.

Regulated dynein's friction parts (chi''/omega0 and beta''/omega0, docs/model.md section
8) make the damping matrix C of ``C dq/dt + A q = b`` non-symmetric, and where the
response is *active* (chi'' < 0, every sliding-control beat; beta'' < 0, e.g. Sartori et
al.'s wild-type curvature control) its symmetric part indefinite: some motions then gain
energy from friction. In the finite-element pencil those are short-wavelength modes whose
growth rates increase without bound under mesh refinement (two filaments, p = 0:
chi''-active grows like N_e^2, beta''-active like N_e^1.5; tests/regulation/test_well_posed.py):
the friction form holds chi and beta exactly at lambda = i omega0, and nowhere near the
spurious modes. So:

- the beat near ``i omega0`` (:func:`axojax.nearest_mode`, mechanism fits) converges
  and is what a regulated mechanism predicts;
- the *dominant* mode, a time integration or a limit cycle of such a model is the
  spurious short wave, mesh-dependent and meaningless: :func:`require_passive_friction`
  refuses them with one line;
- with motor kinetics (a relaxation time tau_m, :mod:`axojax.assembly.motor_kinetics`)
  the response is bounded at large |lambda| and the time domain well posed:
  ``ax.simulate`` and ``ax.limit_cycle`` take the same row with ``tau_m=``
  (``--motor-tau-ms`` on the command line).

A passive or absent friction (symmetric part of C positive semi-definite) is well posed.
"""

from __future__ import annotations

import numpy as np

from .models.section import Model
from .params import Params

TOLERANCE = 1e-12
"""The smallest eigenvalue of (C + C^T)/2 may be below 0 by this times max |C| (rounding)."""


def friction_margin(model: Model, params: Params) -> float:
    """The smallest eigenvalue of the symmetric part of C over max |C| (dimensionless,
    concrete ``params``): >= -:data:`TOLERANCE` when no motion gains energy from friction."""
    from .assembly import assemble

    C = np.asarray(assemble(model, params).C, dtype=float)
    scale = float(np.max(np.abs(C))) or 1.0
    return float(np.linalg.eigvalsh((C + C.T) / 2)[0]) / scale


def require_passive_friction(model: Model, params: Params, what: str) -> None:
    """Raise a one-line ``ValueError`` when ``params`` hold an active friction
    (:func:`friction_margin` below -:data:`TOLERANCE`), naming the coefficient and saying
    what to use instead; ``what`` names the caller (e.g. ``"simulate"``)."""
    if float(np.max(np.abs([np.asarray(params.chi_im), np.asarray(params.beta_im)]))) == 0.0:
        return
    margin = friction_margin(model, params)
    if margin >= -TOLERANCE:
        return
    active = [
        name
        for name in ("chi_im", "beta_im")
        if float(np.min(np.asarray(getattr(params, name), dtype=float))) < 0
    ] or ["chi_im/beta_im"]
    raise ValueError(
        f"{what}: {', '.join(active)} < 0 is an active friction (docs/model.md section 8): its "
        f"short waves grow without bound as the mesh is refined, so the time domain is ill posed; "
        f"give the motors a relaxation time (tau_m=, --motor-tau-ms) to run it in time or as an "
        f"orbit, or study the beat at i omega0 with ax.nearest_mode or a mechanism fit"
    )
