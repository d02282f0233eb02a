"""Published beat observations bundled with axojax, with their sources.

Values are those quoted in Woodhams, Shen & Bayly (2022), J. R. Soc. Interface 19:20220264
(section 3.7.1 and the introduction), citing Geyer et al. (2016) for Chlamydomonas
axonemes. Where a range is quoted (wavelengths), the target is its centre with half the
range as the uncertainty.
"""

from __future__ import annotations

from .targets import Target

OBSERVATIONS: dict[str, dict] = {
    "chlamydomonas-wt": {
        "description": "Chlamydomonas reinhardtii wild-type axonemes (reactivated)",
        "source": "Geyer et al. 2016, as quoted in Woodhams, Shen & Bayly 2022, section 3.7.1",
        "frequency_hz": (68.0, 3.0),
        "wavelength_um": (15.0, 5.0),  # cilia wavelengths 10-20 um (paper, introduction)
        "static_curvature_rad_per_um": (-0.24, 0.02),
    },
    "chlamydomonas-mbo2": {
        "description": "Chlamydomonas mbo2 mutant axonemes (symmetric beat)",
        "source": "Geyer et al. 2016, as quoted in Woodhams, Shen & Bayly 2022, section 3.7.1",
        "frequency_hz": (28.0, 7.0),
        "wavelength_um": (15.0, 5.0),
        "static_curvature_rad_per_um": (-0.04, 0.01),
    },
    "sperm": {
        "description": "sperm flagella (wavelength range only)",
        "source": "Woodhams, Shen & Bayly 2022, introduction (sperm wavelengths 20-30 um)",
        "wavelength_um": (25.0, 5.0),
    },
}


def observation_targets(
    name: str, include: tuple[str, ...] = ("frequency_hz", "wavelength_um")
) -> list[Target]:
    """Targets of a bundled observation (only the scalar observables a fit can use)."""
    if name not in OBSERVATIONS:
        raise ValueError(f"unknown observation {name!r}; choose from {', '.join(OBSERVATIONS)}")
    obs = OBSERVATIONS[name]
    return [Target(k, *obs[k]) for k in include if k in obs]
