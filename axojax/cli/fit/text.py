"""The text that ``axojax fit`` prints for a report (the JSON document of
:mod:`axojax.cli.fit`): fitted values with their verdicts, what each condition achieved,
the regime and mesh check, the loss, and the posterior's summary (its table with the bulk
and tail ESS, then its result, then which sampler ran and why)."""

from __future__ import annotations

from ...inverse.fitting.checks import render_checks
from ...waveform.measures import sensitive_note
from .whole_beat import render as render_whole_beat


def render(doc: dict) -> str:
    lines = [f"{'parameter':>12s}  {'value':>12s}  {'stderr':>12s}  note"]
    for k, v in doc["fitted"].items():
        se = doc["stderr"].get(k)
        note = (
            "at bound"
            if k in doc["at_bound"]
            else ("" if doc["identifiable"].get(k) else "not identifiable")
        )
        lines.append(f"{k:>12s}  {v:12.5g}  {se if se is not None else float('inf'):12.3g}  {note}")
    u = doc.get("units")
    if u:
        lines.append(
            f"units: L {u['length_um']:.4g} um; per filament EI {u['ei_pn_um2']:.4g} pN um^2, "
            f"c_n {u['cn_pn_s_um2']:.3g} pN s/um^2 ({u['source']})"
        )
    for c in doc["conditions"]:
        a = c["achieved"]
        head = f"[{c['label']}] " if len(doc["conditions"]) > 1 else ""
        if "frequency_hz" in a:
            wl = (
                "none (no travelling wave)"
                if a["wavelength_um"] is None
                else f"{a['wavelength_um']:.3f} um"
            )
            dip = a.get("amplitude_dip") if a["wavelength_um"] is not None else None
            lines.append(
                f"{head}achieved: {a['frequency_hz']:.3f} Hz, wavelength {wl}, growth {a['growth_rate_per_s']:.3f} /s"
                + sensitive_note(dip)
            )
        if "limit_cycle_frequency_hz" in a:
            f, amp, wl = (
                a.get(f"limit_cycle_{k}") for k in ("frequency_hz", "amplitude_um", "wavelength_um")
            )
            lines.append(
                f"{head}limit cycle: "
                + (
                    f"{f:.3f} Hz, tip amplitude {amp:.3f} um, wavelength {wl:.3f} um"
                    if f is not None
                    else "no orbit found"
                )
            )
        for t in c["targets"]:
            got = t["achieved"]
            lines.append(
                f"{head}  {t['name']}: {got if got is not None else float('nan'):.4g} vs "
                f"{t['value']:.4g} +- {t['sigma']:.3g} ({t['residual']:+.2f} sigma)"
            )
        if c.get("shape_rms") is not None:
            lines.append(f"{head}  mode shape rms residual {c['shape_rms']:.2f} sigma")
    lines.extend(render_checks(doc))  # regime, mesh_check
    lines.extend(render_whole_beat(doc))
    chi2 = doc.get("chi2_per_dof")
    lines.append(
        f"loss {doc['loss']:.4g}; chi2/dof {chi2:.3g}"
        if chi2 is not None
        else f"loss {doc['loss']:.4g}; chi2/dof undefined (no more residuals than fitted values)"
    )
    lines.append(f"targets met: {doc['targets_met']}; {doc['message']}")
    if doc["result"] != "successful":
        lines.append(f"solver: {doc['result_message']}")
    lines += render_posterior(doc.get("posterior"))
    if doc.get("out"):
        lines.append(f"wrote {doc['out']}")
    return "\n".join(lines)


def render_posterior(post: dict | None) -> list[str]:
    """The text of a report's posterior block (none without one)."""
    if not post:
        return []
    lines = []
    lines.append(
        f"posterior ({post['chains']} chains x {post['draws']} draws, {post['seconds']:.1f} s):"
    )
    lines.append(
        f"{'parameter':>12s}  {'mean':>12s}  {'sd':>10s}  {'q05':>12s}  {'q95':>12s}  "
        f"{'rhat':>6s}  {'bulk ess':>8s}  {'tail ess':>8s}  {'sd/Laplace':>10s}"
    )
    ratio = post.get("sd_ratio") or {}
    tail = post.get("ess_tail") or {}
    for k, m in post["mean"].items():
        lines.append(
            f"{k:>12s}  {m:12.5g}  {post['sd'][k]:10.3g}  {post['q05'][k]:12.5g}  "
            f"{post['q95'][k]:12.5g}  {post['rhat'][k]:6.3f}  {post['ess'][k]:8.0f}  "
            f"{_num(tail.get(k), '.0f'):>8s}  {_num(ratio.get(k)):>10s}"
        )
    if post.get("result"):  # the first line after the table: whether to trust it
        lines.append(
            "result: successful"
            if post["result"] == "successful"
            else f"result: {post['result']}: {post.get('message', '')}"
        )
    if post.get("sampler_reason"):
        lines.append(f"sampler: {post.get('sampler', 'nuts')} ({post['sampler_reason']})")
    if post.get("sampler") == "smc":
        lines.append(
            f"SMC: {post['chains']} independent runs from the prior, tempering stages "
            f"{', '.join(map(str, post['tempering_stages']))}; {post['gradients']} log-density "
            f"evaluations ({post['gradients_per_ess']:.1f} per effective draw)"
        )
    elif post.get("sampler") == "modes":
        lines += _render_modes(post)
    elif post.get("gradients_per_draw") is not None:
        lines.append(
            f"NUTS: mean tree depth {post['tree_depth']:.2f} (limit {post['max_num_doublings']}, "
            f"reached in {100 * post['tree_depth_saturated']:.0f} % of draws), "
            f"{post['gradients_per_draw']:.1f} gradients per draw"
            + (
                f", in coordinates straightened along the profile of {post['transport']}"
                if post.get("transport")
                else ""
            )
        )
    moved = [k for k, r in ratio.items() if r is not None and not 0.5 <= r <= 2.0]
    if moved:
        lines.append(
            f"the draws moved from the Laplace approximation ({', '.join(moved)}: sd ratio "
            "outside 0.5-2): trust the posterior, not the fit's stderr"
        )
    if post.get("file"):
        lines.append(f"wrote {post['file']} (axojax plot it for a corner plot)")
    return lines


def _render_modes(post: dict) -> list[str]:
    """``--sampler modes``: the cost, each mode's centre and mass, the switch lines met."""
    lines = [
        f"modes: {post['chains']} independence Metropolis-Hastings chains from a mixture fitted in "
        f"{post['tempering_stages'][0]} stages; acceptance {post['acceptance']:.2f}; "
        f"{post['gradients']} log-density evaluations ({post['gradients_per_ess']:.1f} per effective draw)"
    ]
    for i, mode in enumerate(post.get("modes") or []):
        centre = mode.get("centre") or {}
        where = ", ".join(f"{k} {v:.4g}" for k, v in centre.items())
        lines.append(
            f"  mode {i + 1}: {where}: mass {mode['mass']:.3f} of the draws "
            f"({mode['mass_importance']:.3f} by importance weights)"
        )
    for line in post.get("switches") or []:
        where = ", ".join(
            f"{k} {lo:.4g}" if abs(hi - lo) <= 1e-3 * abs(hi) else f"{k} {lo:.4g}-{hi:.4g}"
            for k, (lo, hi) in line["range"].items()
        )
        lines.append(
            f"  the dominant eigenmode switches at {where} (the residuals jump by {line['jump']:.3g} sigma)"
        )
    return lines


def _num(x, fmt: str = ".3g") -> str:
    return "n/a" if x is None else format(x, fmt)


def render_laplace(lap: dict) -> list[str]:
    """The Laplace approximation (``Laplace.to_json()``): centre, sd, 90 % interval per
    parameter, and the largest correlation; printed before sampling starts."""
    lines = ["Laplace approximation (J^T J at the optimum; the posterior's draws follow):"]
    lines.append(f"{'parameter':>12s}  {'centre':>12s}  {'sd':>10s}  {'q05':>12s}  {'q95':>12s}")
    for k, c in lap["centre"].items():
        lines.append(
            f"{k:>12s}  {c:12.5g}  {_num(lap['sd'][k]):>10s}  {_num(lap['q05'][k], '12.5g')}  "
            f"{_num(lap['q95'][k], '12.5g')}"
        )
    names, corr = lap["names"], lap["corr"]
    pairs = [
        (abs(corr[i][j]), corr[i][j], names[i], names[j])
        for i in range(len(names))
        for j in range(i)
        if corr[i][j] is not None
    ]
    if pairs:
        _, c, a, b = max(pairs)
        lines.append(f"largest correlation (in the fitted coordinates): {a}-{b} {c:+.3f}")
    return lines
