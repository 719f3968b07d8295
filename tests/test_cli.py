"""The command line: ``aquagait swim`` writes a run directory; mistakes get a message, status 2."""

import json

import imageio.v2 as imageio
import pytest

from aquagait.cli import ProgressBar, main
from aquagait.io import read_run

FILES = {"config.json", "gait.json", "trajectory.npz", "metrics.json"}


def test_swim_writes_a_run_directory_and_a_summary(tmp_path, capsys):
    out = tmp_path / "eel"
    status = main(
        ["swim", "eel2d", "--fluid", "none", "--seconds", "0.2", "--no-video", "--out", str(out)]
    )
    captured = capsys.readouterr()
    assert status == 0, captured.err
    assert {p.name for p in out.iterdir()} == FILES
    assert "eel2d swam" in captured.out and "body lengths per cycle" in captured.out
    assert "less than two gait cycles" in captured.out and str(out) in captured.out
    assert "swimming [" in captured.err and "6/6 frames" in captured.err
    run = read_run(out)
    assert run.config["seconds"] == 0.2 and run.config["fluid"] == "none"
    assert len(run.trajectory.time) == 7


def test_swim_in_the_fluid_with_a_gait_file_and_a_video(tmp_path, capsys):
    first = tmp_path / "first"
    assert (
        main(
            [
                "swim",
                "eel2d",
                "--fluid",
                "none",
                "--seconds",
                "0.1",
                "--no-video",
                "--out",
                str(first),
            ]
        )
        == 0
    )
    gait = json.loads((first / "gait.json").read_text())
    gait["params"] = [0.5 * p for p in gait["params"]]
    (tmp_path / "half.json").write_text(json.dumps(gait))
    out = tmp_path / "second"
    status = main(
        [
            "swim",
            "eel2d",
            "--seconds",
            "0.1",
            "--gait",
            str(tmp_path / "half.json"),
            "--resolution",
            "32",
            "20",
            "--cell-size",
            "0.04",
            "--out",
            str(out),
        ]
    )
    assert status == 0, capsys.readouterr().err
    run = read_run(out)
    assert run.config["fluid"] == "euler" and run.trajectory.fluid.velocity.shape[2:] == (32, 20)
    assert run.config["gait"]["params"] == gait["params"] and run.config["resolution"] == [32, 20]
    assert run.config["cell_size"] == 0.04
    with imageio.get_reader(out / "swim.mp4") as video:
        assert video.count_frames() == 4
    assert "rendering [" in capsys.readouterr().err


@pytest.mark.parametrize(
    "argv,message",
    [
        (["swim", "eal"], "unknown creature 'eal'; known creatures: accordion2d, alien, eel2d"),
        (["swim", "eel2d", "--gait", "missing.json"], "gait file missing.json does not exist"),
        (["swim", "eel2d", "--fluid", "none", "--resolution", "8", "8", "8"], "has 3 entries"),
        (["swim", "fish", "--fluid", "none", "--resolution", "8", "8"], "give (nx, ny, nz)"),
        (["swim", "eel2d", "--seconds", "-1", "--fluid", "none"], "seconds must be a positive"),
        (["swim", "eel2d", "--resolution", "8", "4"], "use at least 75x20 cells"),
    ],
)
def test_swim_mistakes_get_a_message_and_status_2(tmp_path, capsys, argv, message):
    assert main([*argv, "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("aquagait swim: error: ") and message in err
    assert "Traceback" not in err and not (tmp_path / "run").exists()


@pytest.mark.parametrize("command", [["swim", "eel2d"], ["optimize", "eel2d"], ["demo"]])
def test_an_output_directory_that_cannot_be_written_stops_before_any_work(capsys, command):
    assert main([*command, "--out", "/proc/x"]) == 2
    err = capsys.readouterr().err
    assert "cannot write the run directory /proc/x" in err and "Traceback" not in err
    assert "swimming" not in err and "generation" not in err


def test_a_bad_gait_file_names_the_fix(tmp_path, capsys):
    bad = tmp_path / "gait.json"
    bad.write_text(json.dumps({"creature": "eel2d", "names": ["a"], "params": [1.0]}))
    assert main(["swim", "eel2d", "--fluid", "none", "--gait", str(bad)]) == 2
    message = capsys.readouterr().err
    assert "has 1 gait parameters; eel2d's straight gait has 8: amplitude[j1]" in message


def test_the_progress_bar_redraws_one_line_on_a_terminal():
    import io

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    stream = Terminal()
    bar = ProgressBar("swimming", width=10, stream=stream)
    for done in range(1, 5):
        bar(done, 4)
    text = stream.getvalue()
    assert text.count("\r") == 4 and text.endswith("\n") and "[##########] 4/4 frames" in text


def test_the_progress_bar_writes_a_line_per_tenth_into_a_log():
    import io

    stream = io.StringIO()
    bar = ProgressBar("swimming", width=10, stream=stream)
    for done in range(1, 101):
        bar(done, 100)
    lines = stream.getvalue().splitlines()
    assert len(lines) == 11 and "\r" not in stream.getvalue()  # the start, then each tenth
    assert lines[-1].startswith("swimming [##########] 100/100 frames")


@pytest.mark.parametrize(
    "argv, message",
    [
        (
            ["bench", "swim", "--creature", "fish"],
            "--creature is for 'optimize' and for 'swim' with --profile or --compare-*",
        ),
        (["bench", "swim", "--seeds", "2"], "--seeds is for 'optimize', not 'swim'"),
        (
            ["bench", "swim", "--compare-still", "--creature", "nessie"],
            "unknown creature 'nessie'",
        ),
        (["bench", "fluid", "--compare-boundary"], "--compare-* are for 'swim', not 'fluid'"),
        (["bench", "optimize", "--creature", "nessie"], "unknown creature 'nessie'"),
    ],
)
def test_bench_options_for_another_benchmark_or_creature_are_refused(argv, message, capsys):
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert message in err and "pinned" not in out  # refused before anything ran


@pytest.mark.parametrize(
    "argv, dest, value",
    [
        (["swim", "eel2d", "--manoeuvre", "turn-left"], "maneuver", "turn-left"),
        (["swim", "eel2d", "--maneuver", "turn-left"], "maneuver", "turn-left"),
        (["optimize", "eel2d", "--manoeuvre", "turn-right"], "maneuver", "turn-right"),
        (["optimize", "eel2d", "--gait", "hand-set"], "start", "hand-set"),
        (["optimize", "eel2d", "--start", "hand-set"], "start", "hand-set"),
    ],
)
def test_one_name_for_one_thing_both_spellings_and_both_gait_flags_are_taken(argv, dest, value):
    from aquagait.cli import build_parser

    assert getattr(build_parser().parse_args(argv), dest) == value


def test_swim_and_optimize_write_to_their_own_default_directories(tmp_path, monkeypatch):
    """A search writes runs/NAME-optimize, so that a later swim (runs/NAME) leaves its
    gait.json and checkpoint alone; a manoeuvre's search has its own too."""
    from pathlib import Path

    from aquagait.cli.optimize import default_directory

    monkeypatch.chdir(tmp_path)
    small = ["--resolution", "48", "28", "--cell-size", "0.025", "--no-video"]
    search = ["optimize", "eel2d", "--generations", "1", "--popsize", "2", "--workers", "1"]
    assert main([*search, *small]) == 0
    gait = (tmp_path / "runs/eel2d-optimize/gait.json").read_text()
    assert (tmp_path / "runs/eel2d-optimize/checkpoint.pkl").is_file()
    assert main(["swim", "eel2d", "--seconds", "0.1", *small]) == 0
    assert (tmp_path / "runs/eel2d/trajectory.npz").is_file()
    assert (tmp_path / "runs/eel2d-optimize/gait.json").read_text() == gait
    assert default_directory("eel2d", "turn-left") == Path("runs/eel2d-turn-left-optimize")


def test_every_flag_has_help_and_says_its_default():
    """``--help`` is the reference (the site's CLI page is made from the same parser): every
    option and argument has help text, and an option with a default says it."""
    import argparse

    from aquagait.cli import build_parser

    commands = next(a for a in build_parser()._actions if a.dest == "command").choices
    for name, command in commands.items():
        for action in command._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            assert action.help, (name, action.dest)
            if action.default not in (None, False) and action.option_strings:
                assert "default" in action.help, (name, action.option_strings)
