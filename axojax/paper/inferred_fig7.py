"""The parameter set axojax infers for the paper's figure 7d-h, where the paper leaves it
unstated.

Figure 7d-h shows the seven-filament mode at p = 300, 150, 200, 400, 800 with
frequencies 51, 17, 22, 66, 245 Hz, "all parameters kept constant other than p". At the
caption's k_s = 1e6, k_l = 1e3, c_l = 1/200 axojax reproduces panel d only (p = 150 and
200 do not beat, 400 and 800 give 103 and 285 Hz; docs/model.md section 7).

How this set was obtained: the global fit of ``notebooks/gallery_fig07_global_fit.ipynb``
(2026-12-01): ``ax.inverse.Problem`` over the five panels (one
``ax.inverse.Condition`` per p, a frequency target with a 2 % relative sigma each), the
seven-filament preset at N_e = 10 (the paper's mesh), default units, shared free k_s,
k_l, c_l and gamma within ``ax.inverse.DEFAULT_BOUNDS``, Levenberg-Marquardt with exact
Jacobians from 16 starts (the caption's set and a Sobol design). It reproduces all five
frequencies within 2 % (51.28, 17.08, 21.58, 66.77, 244.72 Hz), matching an earlier
independent fit (docs/model.md section 7). What the five numbers determine (notebook): k_s
to about 15 %, c_l to about 10 %, gamma to +-0.03 (anti-correlated with c_l); k_l is
**not** determined (standard error a factor ~16; its profile is flat from 0.1 to 30 and
bounds it only from above, near 100): its value here is one point of a plateau, not a
measurement. With c_l held at the caption's 1/200 the best set (24 starts) misses panel g
by 20 %, and its loss implies that no such set comes within about 10 % of all five.

These are inferred values, shown beside the stated-parameter rows of the paper table,
never instead of them. Keys are the command-line flags without dashes (``axojax modes
--model seven --elements 10 --p P --ks .. --kl .. --cl .. --gamma ..`` recomputes a panel).
"""

from __future__ import annotations

INFERRED_FIG7 = {
    "params": {
        "ks": 462581.9136579539,
        "kl": 14.488673944075257,
        "cl": 1.4320599570891512,
        "gamma": -0.10785138806623129,
    },
    "elements": 10,
    "model": "seven",
}
"""Shared parameters of figure 7d-h (dimensionless, ``axojax.Params`` fields; every other
parameter at its default), the mesh and the preset they were fitted on."""

PANELS = {"7d": 300.0, "7e": 150.0, "7f": 200.0, "7g": 400.0, "7h": 800.0}
"""Panel -> its dynein force p (the paper's claims ``axojax.paper.CLAIMS`` with these keys)."""

FITTED = "2026-12-01"
"""Date of the fit (notebooks/gallery_fig07_global_fit.ipynb)."""


def panel_params(p: float):
    """The complete :class:`axojax.Params` of one panel: the inferred set at force ``p``."""
    from ..params import Params

    return Params(p=float(p), **INFERRED_FIG7["params"])


def inferred_json() -> dict:
    """The ``"fig7"`` entry of ``python -m axojax.paper --inferred --json``."""
    return {"params": dict(INFERRED_FIG7["params"]), "elements": INFERRED_FIG7["elements"]}
