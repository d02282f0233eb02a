"""Beat rows of the paper table: the asymmetric beat of section 3.7.1 (figure 12b).

The paper simulates the seven-filament model with dynein forces 5 : 1 on the two sides
and reports the beat's wavelength, frequency, dynamic amplitude and static curvature
(Geyer et al.'s measures), without stating p, the arm spacing or the nonlinearity.
axojax runs :func:`axojax.simulate` (public API only) just past the Hopf point of the
imbalanced model, as ``notebooks/time_domain_beating.ipynb`` does; :data:`FULL` is the
table's setting and :data:`FAST` a coarse, short one for trying things out.

The beat's wavelength is axojax's one wavelength (docs/model.md, "Mode metrics";
:mod:`axojax.waveform.measures`): psi_1(s) the first Fourier mode of the simulated
tangent angle along the beat direction, k the least-squares slope of its unwrapped phase
over the saved points (trapezoidal weights), wavelength 2 pi / |k|.
"""

from __future__ import annotations

import dataclasses
import pathlib
from typing import Sequence

import numpy as np

from ..critical import critical_force
from ..dynamics import Simulation, simulate
from ..params import DEFAULT_CUBIC, Params
from ..units import Units
from .claims import ELASTICITIES, Claim, Row
from .modes import evaluate, preset_model


@dataclasses.dataclass(frozen=True)
class BeatSettings:
    """How the asymmetric beat is simulated.

    Attributes:
        n_elements: elements per filament.
        t_end_s: simulated time (s).
        p_factor: p as a multiple of the Hopf point p_c of the imbalanced model.
        imbalance: force ratio of the two dynein groups (paper: about 5).
        imbalance_kind: its reading, ``"moment"`` (the paper's: a static couple, forces
            balanced) or ``"force"`` (group 1 carries p / imbalance); docs/model.md section 3.
        cubic: link stiffening kappa (1/L^2).
        perturbation_um: initial tip displacement (um).
    """

    n_elements: int = 10
    t_end_s: float = 0.6
    p_factor: float = 1.04
    imbalance: float = 5.0
    imbalance_kind: str = "moment"
    cubic: float = DEFAULT_CUBIC
    perturbation_um: float = 3.0

    def describe(self, units: Units = Units()) -> str:
        return (
            f"here p = {self.p_factor:g} p_c of the {self.imbalance:g}:1 model "
            f"({self.imbalance_kind} reading), a0 = {Params().a0 * units.length_um:g} um, "
            f"cubic {self.cubic:g}, N_e = {self.n_elements}, {self.t_end_s:g} s"
        )


DIGITS = {
    "frequency_hz": 2,
    "wavelength_um": 1,
    "dynamic_amplitude_rad": 2,
    "static_curvature_rad_per_um": 3,
}
"""Decimals a beat row shows of each waveform measure (the fig. 12 rows, stated and
inferred)."""

FULL = BeatSettings()
FAST = BeatSettings(n_elements=4, t_end_s=0.3)


@dataclasses.dataclass(frozen=True)
class BeatRun:
    """A simulated asymmetric beat and where it sits.

    Attributes:
        sim: the simulation.
        params: its parameters (p = ``p_factor`` p_c).
        p_c: Hopf point of the imbalanced model.
        onset_hz: frequency at the Hopf point.
    """

    sim: Simulation
    params: Params
    p_c: float
    onset_hz: float


def run_beat(
    settings: BeatSettings = FULL,
    units: Units = Units(),
    progress: bool = False,
    saved: str | pathlib.Path | None = None,
) -> BeatRun:
    """Simulate the asymmetric beat.

    ``saved``: a ``.npz`` path; a simulation saved there with the same model, parameters,
    nonlinearity and duration is reused instead of simulated again, and a new one is saved
    there.
    """
    model = preset_model("seven", settings.n_elements).with_imbalance_kind(settings.imbalance_kind)
    base = Params(imbalance=settings.imbalance)
    crit = critical_force(model, base)
    p_c = float(crit.p)
    params = base.replace(p=settings.p_factor * p_c)
    sim = _load_matching(saved, model.n_elements, params, settings) if saved else None
    if sim is None:
        sim = simulate(
            model,
            params,
            settings.t_end_s,
            cubic=settings.cubic,
            units=units,
            perturbation_um=settings.perturbation_um,
            progress=progress,
        )
        if saved:
            sim.save(saved)
    return BeatRun(sim, params, p_c, float(crit.frequency_hz(units)))


def _load_matching(
    path: str | pathlib.Path, n_elements: int, params: Params, settings: BeatSettings
) -> Simulation | None:
    path = pathlib.Path(path)
    if not path.is_file():
        return None
    sim = Simulation.load(path)
    m = sim.meta
    same = (
        m["model"] == "seven"
        and m["n_elements"] == n_elements
        and m["cubic"] == settings.cubic
        and m.get("imbalance_kind", "force") == settings.imbalance_kind
        and m["t_end_s"] == settings.t_end_s
        and m["perturbation_um"] == settings.perturbation_um
        and all(
            np.isclose(m["params"][k], float(v), rtol=1e-9, atol=0.0)
            for k, v in params.as_dict().items()
        )
    )
    return sim if same else None


def beat_measures(sim: Simulation) -> dict[str, float] | None:
    """Frequency, wavelength, dynamic amplitude and static curvature of a limit cycle
    (None when the run did not settle on one).

    Also returns ``phase_span_rad`` (how far the phase of psi_1 turns from base to tip),
    ``direction`` (+1 base to tip, -1 tip to base, 0 standing) and ``beat_angle_deg``
    (beat direction from y towards z). The wavelength is inf for a standing wave.
    """
    lc = sim.limit_cycle
    if lc is None:
        return None
    modes = sim.settled_modes()
    phase = np.unwrap(np.angle(modes.psi1[1:]))  # psi_1 = 0 at the clamped base
    return {
        "frequency_hz": lc["frequency_hz"],
        "wavelength_um": modes.wavelength,
        "dynamic_amplitude_rad": lc["dynamic_amplitude_rad"],
        "static_curvature_rad_per_um": lc["static_curvature_rad_per_um"],
        "phase_span_rad": float(abs(phase[-1] - phase[0])),
        "direction": modes.direction,
        "beat_angle_deg": float(np.degrees(sim.beat_angle_rad)),
    }


def beat_rows(
    claims: Sequence[Claim],
    settings: BeatSettings = FULL,
    units: Units = Units(),
    progress: bool = False,
    saved: str | pathlib.Path | None = None,
) -> list[Row]:
    """Rows for the ``kind == "beat"`` claims (``saved``: see :func:`run_beat`).

    Frequency and wavelength rows carry the elasticities of the linear dominant mode at
    the simulated parameters."""
    claims = [c for c in claims if c.kind == "beat"]
    if not claims:
        return []
    run = run_beat(settings, units, progress, saved)
    m = beat_measures(run.sim)
    linear = evaluate(
        preset_model("seven", settings.n_elements).with_imbalance_kind(settings.imbalance_kind),
        [run.params],
        units=units,
    )
    context = settings.describe(units)
    rows = []
    for c in claims:
        note = [c.unstated, context]
        if m is None:
            rows.append(Row(c, None, f"no limit cycle ({run.sim.state})", None, "; ".join(note)))
            continue
        value = m[c.quantity]
        elast = None
        if c.quantity in linear.values:
            elast = dict(zip(ELASTICITIES, map(float, linear.elasticity[c.quantity][0])))
            note.append("elasticities of the linear mode at these parameters")
        if c.quantity == "frequency_hz":
            note.append(
                f"the {settings.imbalance:g}:1 model starts beating at p_c = {run.p_c:.1f} "
                f"with {run.onset_hz:.1f} Hz, and the "
                f"frequency rises with p past it; this beat runs {m['beat_angle_deg']:.0f} deg "
                "from y towards z (the linear "
                f"mode's out-of-plane ratio is {float(linear.values['out_of_plane_ratio'][0]):.2f})"
            )
        if c.quantity == "wavelength_um":
            span = m["phase_span_rad"]
            note.append(
                f"the phase of psi_1 turns {span:.1f} rad from base to tip, running "
                f"{'base to tip' if m['direction'] > 0 else 'tip to base'}, unevenly: the wavelength is 2 pi over "
                "its least-squares slope (docs/model.md section 5)"
            )
        if c.quantity in ("dynamic_amplitude_rad", "static_curvature_rad_per_um"):
            note.append(
                "the amplitude is set by the unstated nonlinearity and p, the static bend by "
                "the moment p a0 (1 - 1/imbalance)"
            )
        if c.quantity == "static_curvature_rad_per_um":
            note.append("its sign depends on which side carries the larger force")
        digits = DIGITS[c.quantity]
        rows.append(Row(c, float(value), f"{value:.{digits}f} {c.unit}", elast, "; ".join(note)))
    return rows
