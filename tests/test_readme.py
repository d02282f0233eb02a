"""README.md quotes axojax's actual output (so it cannot go stale)."""

import pathlib

from axojax.cli.main import main

README = pathlib.Path(__file__).resolve().parents[1] / "README.md"


def test_main_job_output_is_current(capsys):
    """The block under "The main job" is what `axojax modes --model seven --p 300` prints."""
    assert main(["modes", "--model", "seven", "--p", "300"]) == 0
    out = capsys.readouterr().out.rstrip("\n")
    assert f"```\n{out}\n```" in README.read_text(), (
        "README's main-job block is stale: paste the command's output"
    )
