"""What the linear and the whole-beat ``axojax fit`` share: which flags the command line
gave, the beat of ``--data`` (its targets, shape and units), and the report document
written to ``--out`` with the command's exit status (1 when the targets are missed or a
posterior's chains did not converge)."""

from __future__ import annotations

import argparse
import dataclasses
import json
import pathlib
import sys

from ... import _io
from ...beats import Target, beat_units, read_beat
from ...beats.reduction import PLANARITY_THRESHOLD
from ...results import RESULTS
from ...units import Units
from .. import common


def given(args, *flags: str) -> bool:
    """Whether any of ``flags`` is on the command line (not just its default)."""
    return any(a == f or a.startswith(f + "=") for a in getattr(args, "_argv", []) for f in flags)


def read_data(path, flag: str, planarity_threshold: float = PLANARITY_THRESHOLD):
    """(BeatData, its summary: what ``axojax data`` prints) of a beat file; the reader
    refuses data no fit can use (:mod:`axojax.beats.data`)."""
    try:
        beat = read_beat(path, planarity_threshold=planarity_threshold)
    except (ValueError, OSError) as err:
        raise common.CLIError(f"{flag}: {err}") from None
    return beat, beat.summary()


def data_inputs(args: argparse.Namespace, units: Units, source: str, model):
    """--data: its targets and shape (for --target limit-cycle, the whole waveform against
    the nonlinear beat), the units at the data's length, the data's summary, and where
    the units came from: EI and c_n not given (--ei, --cn) come from the data set's
    flagellum when it has one (a bundled beat; as ``axojax compare`` does:
    :func:`axojax.beats.units.beat_units`, shared by the model's filaments), else
    axojax's defaults (``source`` names them)."""
    common.check_planarity_threshold(args)
    beat, summary = read_data(args.data, "--data", args.planarity_threshold)
    length = beat.length_um
    if abs(length - units.length_um) > 1e-6 * length and given(args, "--length-um"):
        raise common.CLIError(
            f"--length-um: {units.length_um:g} um conflicts with the data's length {length:g} um ({args.data})"
        )
    ei_given, cn_given = given(args, "--ei"), given(args, "--cn")
    units, words = beat_units(  # at the data's length
        beat,
        model.n_filaments,
        ei_pn_um2=units.ei_pn_um2 if ei_given else None,
        cn_pn_s_um2=units.cn_pn_s_um2 if cn_given else None,
    )
    if beat.flagellum is not None and not (ei_given and cn_given):
        source = words
        if ei_given or cn_given:
            source += f" ({'--ei' if ei_given else '--cn'} given)"
    targets, shape = beat.targets()
    if getattr(args, "components", "in-plane") == "joint":
        if args.target == "limit-cycle":
            raise common.CLIError(
                "--components joint: the limit cycle's shape is in-plane only; leave it out or fit the linear mode"
            )
        if beat.out_of_plane is not None and model.n_dirs == 1:
            raise common.CLIError(
                f"--components joint: {args.data} beats in 3D but model {model.name!r} in one plane; "
                "use a 3D model (e.g. --model seven)"
            )
        shape = beat.joint_shape_target()
    if args.target == "limit-cycle":
        # psi_0 and psi_1 in absolute amplitude, and the data's frequency as the cycle's.
        targets = [
            Target(t.name, t.value, t.sigma, source="limit_cycle")
            for t in targets
            if t.name in ("frequency_hz", "wavelength_um")
        ]
        shape = None if shape is None else dataclasses.replace(shape, source="limit_cycle")
    return targets, shape, units, summary, source


def finish(args, result, extra: dict, sampled=None) -> dict:
    """The command's JSON document of ``result`` (a fit report) with ``extra`` and the
    posterior (``sampled``: the :class:`~axojax.inverse.Posterior` and why its sampler
    ran, or None), written to ``--out`` (the draws beside it); exit status 1 when the
    targets are not met (with one line on stderr) or the posterior's chains did not
    converge (its warnings, one line each, are on stderr already)."""
    doc = result.to_json()
    doc.update(extra)
    post = None
    if sampled is not None:
        post, why = sampled
        doc["posterior"] = {**post.to_json(), "sampler_reason": why}
        if args.out is not None:
            draws = pathlib.Path(args.out).with_suffix(".posterior.npz")
            try:
                post.save(draws)
            except OSError as err:
                raise common.CLIError(f"--out: cannot write {str(draws)!r} ({err})") from None
            doc["posterior"]["file"] = str(draws)
    if args.out is not None:
        try:
            _io.write_text(
                args.out, json.dumps(common.to_jsonable(doc), indent=1, allow_nan=False) + "\n"
            )
        except OSError as err:
            raise common.CLIError(f"--out: cannot write {args.out!r} ({err})") from None
        doc["out"] = str(args.out)
    if not result.targets_met:
        print(f"axojax: fit: {result.message}", file=sys.stderr)
    converged = post is None or post.result == RESULTS.successful
    args._exit_code = 0 if result.targets_met and converged else 1
    return doc
