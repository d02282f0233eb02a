"""Does any preset couple twist and bending at linear order? (issue 55 item 2, a first
measurement; docs/model.md section 8 argues that the four and seven presets cannot.)

Twist is the cross-section's rigid rotation Theta(x) in its own plane: filament f at
(y_f, z_f) moves by Theta (-z_f, y_f); bending is the section's rigid translation w(x) in
y or z. With T and B the matrices whose columns span these in the model's unknowns
(:func:`axojax.models.section_motions`), the script prints per preset and load:

- |T^T A B| / |T^T A T| and |B^T A T| / |B^T A B|: the stiffness's coupling of twist and
  bending, relative to each block (0 to rounding: no coupling at linear order);
- |T^T C B| / |C|: the same for the damping;
- the static state's twist: the largest Theta of q0 = A^-1 b projected on T, beside its
  largest bending translation.

    python benchmarks/check_twist_coupling.py [--elements 4]

Measured 2026-12-07 (4 elements): four and seven couple nothing (1e-15), passive or under
the steady load p = 300; nine couples nothing passive or with a static moment, but under
the steady load p = 300 its stiffness couples twist and bending by 3 % of the twist block
(1.8 % of the bending block); the damping never. Every loaded static state carries a
twist: under the balanced steady load (imbalance 1) four and seven twist (Theta up to 0.34
and 1.5) without bending, as dynein arms that all act in one rotational sense would; nine
also bends (0.17). What that static twist means for the beat, and whether twist control
is built on nine, is issue 55 item 2's to settle.
"""

import argparse

import numpy as np

import axojax as ax
from axojax.models import section_motions

LOADS = {
    "passive": ax.Params(p=0.0),
    "steady p=300": ax.Params(p=300.0),
    "p=300, imbalance 2": ax.Params(p=300.0, imbalance=2.0),
    "static moment m0=10": ax.Params(p=0.0, m0=10.0),
}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--elements", type=int, default=4)
    args = p.parse_args()
    print(
        f"{'preset':7s} {'load':22s} {'TAB/TAT':>9s} {'BAT/BAB':>9s} {'TCB/C':>9s} {'twist':>8s} {'bend':>8s}"
    )
    for name in ("four", "seven", "nine"):
        model = getattr(ax.models, name)(n_elements=args.elements)
        T, B = section_motions(model)
        for label, prm in LOADS.items():
            s = ax.assemble(model, prm)
            A, C, b = np.asarray(s.A), np.asarray(s.C), np.asarray(s.b)
            tab = np.linalg.norm(T.T @ A @ B) / np.linalg.norm(T.T @ A @ T)
            bat = np.linalg.norm(B.T @ A @ T) / np.linalg.norm(B.T @ A @ B)
            tcb = np.linalg.norm(T.T @ C @ B) / np.linalg.norm(C)
            q0 = np.linalg.solve(A, b) if np.any(b) else np.zeros(model.n_unknowns)
            twist = np.abs(np.linalg.lstsq(T, q0, rcond=None)[0]).max()
            bend = np.abs(np.linalg.lstsq(B, q0, rcond=None)[0]).max()
            print(
                f"{name:7s} {label:22s} {tab:9.2e} {bat:9.2e} {tcb:9.2e} {twist:8.3g} {bend:8.3g}"
            )


if __name__ == "__main__":
    main()
