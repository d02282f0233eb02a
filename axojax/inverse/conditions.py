"""One observed condition of an inverse problem: fixed parameter values, targets, a label.

A *condition* is one experiment (one axoneme at one ATP level, one figure panel): the
parameter values that are known for it (e.g. its dynein force ``p``), what was observed
(scalar :class:`~axojax.beats.Target` s with sigmas, optionally a psi_1 shape
:class:`~axojax.beats.ShapeTarget`) and where that came from. Several conditions share
the free parameters of an :class:`~axojax.inverse.Problem` that are not fitted per
condition.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any

from ..beats.targets import ShapeTarget, Target
from ..models.section import Model
from ..params import PARAM_NAMES, Params


@dataclasses.dataclass(frozen=True)
class Condition:
    """One observed condition.

    Attributes:
        params: fixed (dimensionless) parameter values of this condition, e.g.
            ``{"p": 150.0}``, or a whole :class:`~axojax.Params`; they override the
            problem's base parameters. For a free parameter they are this condition's
            starting value.
        targets: scalar targets (physical units, each with its sigma).
        shape: optional observed psi_1(s) (and psi_0) of this condition.
        label: a short name (default: the condition's index); per-condition free
            parameters are named ``"<name>@<label>"``.
        source: where the targets come from (a file, a figure), for the report.
        model: this condition's model, when it differs from the problem's.
    """

    params: dict[str, float] | Params = dataclasses.field(default_factory=dict)
    targets: Sequence[Target] = ()
    shape: ShapeTarget | None = None
    label: str | None = None
    source: str | None = None
    model: Model | None = None

    def __post_init__(self) -> None:
        values = self.params.as_dict() if isinstance(self.params, Params) else dict(self.params)
        for name in values:
            if name not in PARAM_NAMES:
                raise ValueError(
                    f"condition {self.label or ''}: unknown parameter {name!r}; choose from "
                    f"{', '.join(PARAM_NAMES)}".replace("condition : ", "condition: ")
                )
        object.__setattr__(self, "params", {k: float(v) for k, v in values.items()})
        object.__setattr__(self, "targets", tuple(self.targets))
        for t in self.targets:
            if not isinstance(t, Target):
                raise TypeError(f"condition targets must be axojax.beats.Target, got {t!r}")
        if not self.targets and self.shape is None:
            raise ValueError(
                f"condition {self.label if self.label is not None else ''}: give at least one "
                "target or a shape".replace("condition : ", "condition: ")
            )

    def describe(self) -> dict[str, Any]:
        return {
            "label": self.label,
            "params": dict(self.params),
            "source": self.source,
            "targets": [{"name": t.key, "value": t.value, "sigma": t.sigma} for t in self.targets],
        }
