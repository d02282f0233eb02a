"""``ax.inverse.load_spec`` / ``read_spec`` (issue 32): a fit specification file read by
the library into the same Problem the command line fits; every problem one line that
starts with the file."""

import numpy as np
import pytest

import axojax as ax
from axojax.inverse import FitSpec, Problem, load_spec, read_spec

SPEC = """model = "two"
elements = 3
kl_ratio = 100
length_um = 20
free = ["ks"]
free_per_condition = ["out-of-plane"]
[params]
ks = 2e5
cl = 0.01
[bounds]
ks = [1e3, 1e7]
[[condition]]
label = "low"
p = 150
frequency_hz = 20
wavelength_um = 15
wavelength_sigma_um = 3
[[condition]]
p = 200
velocity_um_per_s = 400
data = "modes.csv"
"""


def write(tmp_path, text=SPEC):
    s = np.linspace(0, 20, 9)
    rows = [f"{a},0.1,{0.3 * np.cos(a / 3)},{-0.3 * np.sin(a / 3)}" for a in s.tolist()]
    (tmp_path / "modes.csv").write_text(
        "# length_um = 20\n# frequency_hz = 30\ns_um,psi0_rad,psi1_re_rad,psi1_im_rad\n"
        + "\n".join(rows)
        + "\n"
    )
    path = tmp_path / "fit.toml"
    path.write_text(text)
    return path


def test_load_spec_builds_the_problem_the_file_describes(tmp_path):
    path = write(tmp_path)
    spec = read_spec(path, units=ax.Units(length_um=12.0))
    assert isinstance(spec, FitSpec)
    assert spec.model.name == "two" and spec.model.n_elements == 3
    assert spec.units.length_um == 20.0  # the spec's length over the caller's
    assert spec.kl_ratio == 100.0 and float(spec.params.kl) == pytest.approx(2e5 / 100)
    assert spec.free == ("ks",) and spec.per_condition == ("out_of_plane",)
    assert spec.bounds == {"ks": (1e3, 1e7)}
    low, second = spec.conditions
    assert low.label == "low" and second.label == "1"
    assert low.params == {"p": 150.0} and second.params == {"p": 200.0}
    t = {x.name: (x.value, x.sigma) for x in low.targets}
    assert t == {"frequency_hz": (20.0, 0.05 * 20), "wavelength_um": (15.0, 3.0)}
    t = {x.name: (x.value, x.sigma) for x in second.targets}
    # the data file's frequency (sigma: the reader's 1 % floor) and the table's velocity
    assert t == {"frequency_hz": (30.0, 0.3), "velocity_um_per_s": (400.0, 40.0)}
    assert second.shape is not None and second.shape.s_um.size == 9
    assert len(spec.data) == 1 and spec.data[0]["condition"] == "1"
    problem = load_spec(path, shape_floor=0.02)
    assert isinstance(problem, Problem)
    assert tuple(problem.names) == ("ks", "out_of_plane@low", "out_of_plane@1")
    assert problem.shape_floor == 0.02 and problem.n_conditions == 2


@pytest.mark.parametrize(
    "edit, problem",
    [
        (('free = ["ks"]', 'free = ["zz"]'), "free: unknown parameter 'zz'"),
        (("elements = 3", "elements = 0"), "elements must be an integer"),
        (("elements = 3", "elements = 99999"), "GiB"),
        (("kl_ratio = 100", "kl_ratio = -1"), "kl_ratio must be > 0"),
        (("velocity_um_per_s = 400", "velocity_um_per_s = 0"), "must be > 0"),
        (('data = "modes.csv"', 'data = "none.csv"'), "condition 2: data:"),
        (("ks = [1e3, 1e7]", "ks = [1e3]"), "bounds.ks must be [low, high]"),
        (('model = "two"', 'model = "eleven"'), "model: unknown model"),
        (("wavelength_um = 15\n", ""), "wavelength_sigma_um without its target"),
        (("[params]", "colour = 1\n[params]"), "unknown key(s) colour"),
    ],
)
def test_spec_problems_are_one_line_naming_the_file(tmp_path, edit, problem):
    path = write(tmp_path, SPEC.replace(*edit))
    with pytest.raises(ValueError) as info:
        load_spec(path)
    text = str(info.value)
    assert text.startswith(str(path)) and problem in text and "\n" not in text, text


def test_missing_and_malformed_files(tmp_path):
    with pytest.raises(ValueError, match="does not exist"):
        load_spec(tmp_path / "nothing.toml")
    path = tmp_path / "bad.toml"
    path.write_text('free = ["ks"\n')
    with pytest.raises(ValueError, match="not valid TOML"):
        load_spec(path)
