"""The CLI on bad input: exit code 2 (user error, one line on stderr) or 3 (solver failure),
tracebacks only with --debug, and never a partial output file.

The mutation test runs ``gear-dyn run`` in-process on every key of every scene in
examples/scenes mutated six ways (deleted, negated, NaN, a string, a wrong unit, huge), with
``--periods 2`` and the plot functions replaced by a blank figure (the figures are not what is
tested here, and drawing them would make the test take minutes); a few real subprocess runs
check the one-line stderr end to end.
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import io
import json
import os
import shutil
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from matplotlib.figure import Figure
from scene_cases import (
    DOCUMENTED_EXIT_CODES,
    dump_toml,
    example_scenes,
    load,
    mutated_scenes,
)

import gear_dyn.plots.run
from gear_dyn.cli.app import build_parser, main

HELI = Path(__file__).resolve().parents[2] / "examples" / "scenes" / "helicopter_tail.toml"


def _run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def _hidden_leftovers(folder: Path) -> list[str]:
    """Temporary files/folders of the atomic writers (.NAME.*.tmp / .partial / .old)."""
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


class _Timeout(BaseException):
    pass


@contextlib.contextmanager
def _time_limit(seconds: int, label: str) -> Iterator[None]:
    """Fail (instead of hanging the suite) if one CLI run takes longer than ``seconds``."""

    def handler(signum: int, frame: Any) -> None:
        raise _Timeout(label)

    old = signal.signal(signal.SIGALRM, handler)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


@pytest.fixture
def blank_plots(monkeypatch: pytest.MonkeyPatch) -> None:
    """Plot functions return a blank 1x1 inch figure (still saved through gear_dyn.io)."""

    def blank(*args: Any, **kwargs: Any) -> Figure:
        return Figure(figsize=(1, 1))

    for name in dir(gear_dyn.plots.run):
        if name.startswith("plot_"):
            monkeypatch.setattr(gear_dyn.plots.run, name, blank)


def _check_outcome(label: str, code: int, err: str, out_dir: Path) -> list[str]:
    bad = []
    if code not in DOCUMENTED_EXIT_CODES:
        bad.append(f"{label}: exit code {code}: {err.strip()[:300]}")
    if "Traceback" in err:
        bad.append(f"{label}: traceback on stderr")
    if code == 2 and not (err.count("\n") == 1 and err.startswith("gear-dyn: error: ")):
        bad.append(f"{label}: exit 2 but stderr is not one 'gear-dyn: error:' line: {err!r}")
    if code == 3 and not (err.count("\n") == 1 and err.startswith("gear-dyn: solver failure: ")):
        bad.append(f"{label}: exit 3 but stderr is not one 'solver failure' line: {err!r}")
    if code != 0 and out_dir.exists():
        bad.append(f"{label}: failed (exit {code}) but left {out_dir.name}/")
    if code == 0:
        names = sorted(p.name for p in out_dir.iterdir())
        if "summary.json" not in names or any(n.startswith(".") for n in names):
            bad.append(f"{label}: output folder incomplete or with temporary files: {names}")
        csv = "\n".join(line for line in (out_dir / "timeseries.csv").read_text().lower()
                        .splitlines() if not line.startswith("#"))  # values, not the notes
        if "nan" in csv or "inf" in csv:
            bad.append(f"{label}: exit 0 with non-finite values in timeseries.csv")
    leftovers = _hidden_leftovers(out_dir.parent)
    if leftovers:
        bad.append(f"{label}: temporary files left next to the output: {leftovers}")
    return bad


@pytest.fixture
def reuse_identical_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    """``run_scene`` computes each distinct physical scene once: mutations such as deleting
    ``scene.name`` or a key equal to its default give the same validated tables, and the result
    is reused (the CLI still loads, validates and writes everything for each mutation)."""
    import gear_dyn.scene

    real = gear_dyn.scene.run_scene
    cache: dict[str, Any] = {}

    def run_scene(scene: Any, **overrides: Any) -> Any:
        tables = {k: dict(v) for k, v in scene.tables.items()}
        tables.get("scene", {}).pop("name", None)
        tables.get("scene", {}).pop("description", None)
        if "periods" in overrides:  # --periods resets the steady window too
            tables.get("solver", {}).pop("periods", None)
            tables.get("solver", {}).pop("steady_periods", None)
        key = json.dumps([tables, overrides], sort_keys=True, default=repr)
        if key not in cache:
            try:
                cache[key] = real(scene, **overrides)
            except Exception as exc:  # noqa: BLE001 - replayed below, whatever it is
                cache[key] = exc
        hit = cache[key]
        if isinstance(hit, Exception):
            raise hit.with_traceback(None)
        return hit

    monkeypatch.setattr(gear_dyn.scene, "run_scene", run_scene)


@pytest.mark.parametrize("path", example_scenes(), ids=lambda p: p.stem)
def test_every_key_mutated_exits_0_2_or_3_without_partial_output(
    path: Path, tmp_path: Path, blank_plots: None, reuse_identical_runs: None
) -> None:
    """Every key deleted/negated/NaN/string/wrong unit/huge, plus a deleted table, a table that
    is a string, an unknown key and an unknown table: documented exit code, one stderr line,
    the scene file untouched, and either a complete output folder or none."""
    data = load(path)
    bad: list[str] = []
    codes: dict[int, int] = {}
    for i, (label, scene) in enumerate(mutated_scenes(data, core=True)):
        scene_file = tmp_path / f"{path.stem}.toml"
        scene_file.write_text(dump_toml(scene))
        digest = hashlib.sha256(scene_file.read_bytes()).hexdigest()
        out_dir = tmp_path / f"out{i}"
        with _time_limit(120, label):
            code, _, err = _run(["run", str(scene_file), "--out", str(out_dir), "--periods", "2"])
        codes[code] = codes.get(code, 0) + 1
        bad += _check_outcome(label, code, err, out_dir)
        if code == 2 and path.stem not in err:
            bad.append(f"{label}: the error does not name the scene file: {err.strip()}")
        if hashlib.sha256(scene_file.read_bytes()).hexdigest() != digest:
            bad.append(f"{label}: the input scene was modified")
    assert not bad, "\n".join(bad)
    # both outcomes occur: some mutations are harmless (deleting an optional key), most not
    assert codes.get(0, 0) > 0 and codes.get(2, 0) > 0


def test_failed_run_keeps_the_previous_output_whole(tmp_path: Path, blank_plots: None) -> None:
    """A good run, then a bad scene into the same folder: the first output is untouched."""
    out_dir = tmp_path / "out"
    assert _run(["run", str(HELI), "--out", str(out_dir), "--periods", "2"])[0] == 0
    before = {p.name: p.read_bytes() for p in out_dir.iterdir()}
    bad = tmp_path / "bad.toml"
    bad.write_text(HELI.read_text().replace('module = "6 mm"', 'module = "6 kg"'))
    code, _, err = _run(["run", str(bad), "--out", str(out_dir), "--periods", "2"])
    assert code == 2 and "gear.module" in err and "kg" in err
    assert {p.name: p.read_bytes() for p in out_dir.iterdir()} == before
    assert _hidden_leftovers(tmp_path) == []


# ---------------------------------------------------------------------------------------------
# every subcommand: argparse errors, bad scene paths, --help


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    for action in parser._actions:  # noqa: SLF001 - the only way to list subparsers
        if isinstance(action, argparse._SubParsersAction):  # noqa: SLF001
            return dict(action.choices)
    raise AssertionError("no subcommands")


#: sample values for required options other than --out
_SAMPLES = {"speeds": "1000:2000:3"}


def _command_lines(sub: argparse.ArgumentParser, scene: str, out: str,
                   other: str) -> list[list[str]]:
    """Command lines with every required argument (nested actions such as ``fmu build``
    expanded): a positional ``scene`` gets ``scene``, other file positionals (an FMU) ``other``,
    --out gets ``out``."""
    lines: list[list[str]] = [[]]
    for action in sub._actions:  # noqa: SLF001
        if isinstance(action, argparse._SubParsersAction):  # noqa: SLF001
            lines = [[*line, name, *rest] for line in lines
                     for name, subsub in action.choices.items()
                     for rest in _command_lines(subsub, scene, out, other)]
        elif action.option_strings:
            if action.required:
                value = out if action.dest == "out" else _SAMPLES.get(action.dest)
                if value is None and action.choices:
                    value = str(next(iter(action.choices)))
                if value is None:
                    return []
                lines = [[*line, action.option_strings[0], value] for line in lines]
        elif action.nargs in (None, 1, "+"):
            if action.choices:
                value = str(next(iter(action.choices)))
            else:
                value = scene if action.dest == "scene" else other
            lines = [[*line, value] for line in lines]
    return lines


def _scene_commands(scene: str, out: str, other: str | None = None) -> list[list[str]]:
    """Every command line (subcommand first) that reads ``scene`` (or ``other`` as its input
    file, when given)."""
    wanted = {scene} if other is None else {scene, other}
    return [[name, *line] for name, sub in _subcommands().items()
            for line in _command_lines(sub, scene, out, other or "-unused-")
            if wanted & set(line)]


def test_every_subcommand_registered_and_has_help() -> None:
    """Each registered subcommand answers --help with exit code 0."""
    subs = _subcommands()
    assert {"run", "demo"} <= set(subs)
    for name in subs:
        code, out, err = _run([name, "--help"])
        assert code == 0 and out.startswith("usage: gear-dyn"), (name, err)


@pytest.mark.parametrize("flag", ["--no-such-flag", "--rtol=abc"])
def test_every_subcommand_rejects_bad_flags_with_exit_2(flag: str) -> None:
    """Unknown flags (and, where the command has --rtol, a non-number) end in exit 2 with one
    line on stderr naming the command, never a traceback."""
    for name, sub in _subcommands().items():
        opts = {s for a in sub._actions for s in a.option_strings}  # noqa: SLF001
        if flag.startswith("--rtol") and "--rtol" not in opts:
            continue
        code, _, err = _run([name, flag])
        assert code == 2, (name, err)
        assert err.count("\n") == 1 and err.startswith("gear-dyn: error: "), (name, err)
        assert "Traceback" not in err


@pytest.mark.parametrize("problem", ["missing", "directory", "not_toml", "binary"])
def test_every_scene_command_rejects_a_bad_scene_file_with_exit_2(
    problem: str, tmp_path: Path
) -> None:
    """Every subcommand that reads a file (a scene, or an FMU for fmu validate / cosim): a
    missing file, a folder, broken TOML or binary junk end in exit 2 with one line that names
    the file, and no output."""
    scene = tmp_path / "scene.toml"
    if problem == "directory":
        scene.mkdir()
    elif problem == "not_toml":
        scene.write_text("[gear\nteeth_pinion = = 3\n")
    elif problem == "binary":
        scene.write_bytes(b"\xff\xfe\x00\x01garbage")
    out = tmp_path / "out.fmu"  # a folder name for most commands, the FMU file for fmu build
    tested = []
    for argv in _scene_commands(str(scene), str(out), other=str(scene)):
        code, _, err = _run(argv)
        tested.append(argv[0])
        assert code == 2, (argv, err)
        assert err.count("\n") == 1 and "scene.toml" in err, (argv, err)
        assert not out.exists()
    assert {"run", "sweep", "fmu", "cosim"} <= set(tested)


def test_every_scene_command_rejects_a_bad_value_with_exit_2(tmp_path: Path) -> None:
    """Each scene-reading subcommand given the helicopter scene with module = "6 kg" or a
    NaN torque: exit 2, one line naming the key, no output."""
    out = tmp_path / "out.fmu"
    for old, new, key in (('module = "6 mm"', 'module = "6 kg"', "gear.module"),
                          ('torque = "1474.4 N*m"', "torque = nan", "operating.torque")):
        scene = tmp_path / "bad.toml"
        scene.write_text(HELI.read_text().replace(old, new))
        for argv in _scene_commands(str(scene), str(out)):
            code, _, err = _run(argv)
            assert code == 2, (argv, err)
            assert err.count("\n") == 1 and key in err and "bad.toml" in err, (argv, err)
            assert not out.exists()


def test_bad_override_values_exit_2() -> None:
    """Solver flags out of range: --rtol 5, --periods 1, --method Euler, --atol -1."""
    for flags, needle in ((["--rtol", "5"], "rtol"), (["--periods", "1"], "periods"),
                          (["--method", "Euler"], "method"), (["--atol", "-1"], "atol"),
                          (["--rtol", "nan"], "rtol")):
        code, _, err = _run(["run", str(HELI), "--out", "/nonexistent/never", *flags])
        assert code == 2, (flags, err)
        assert needle in err and err.count("\n") == 1


def test_debug_shows_the_traceback_anywhere_on_the_line(tmp_path: Path) -> None:
    """--debug before or after the subcommand prints the traceback; without it, one line."""
    bad = tmp_path / "bad.toml"
    bad.write_text(HELI.read_text().replace("teeth_pinion = 23", "teeth_pinion = 2"))
    for argv in (["--debug", "run", str(bad), "--out", str(tmp_path / "o")],
                 ["run", str(bad), "--out", str(tmp_path / "o"), "--debug"]):
        code, _, err = _run(argv)
        assert code == 2
        assert "Traceback" in err and "gear.teeth_pinion" in err
    code, _, err = _run(["run", str(bad), "--out", str(tmp_path / "o")])
    assert code == 2 and "Traceback" not in err and err.count("\n") == 1


# ---------------------------------------------------------------------------------------------
# real processes: the installed entry point, stderr as the user sees it


def _cli(*args: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "gear_dyn.cli", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=300,
                          env={**os.environ, "MPLBACKEND": "Agg"})


def test_subprocess_user_error_is_one_line_exit_2(tmp_path: Path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text(HELI.read_text().replace('module = "6 mm"', 'module = "6 kg"'))
    p = _cli("run", str(bad), "--out", str(tmp_path / "o"), cwd=tmp_path)
    assert p.returncode == 2
    assert p.stderr.count("\n") == 1 and "gear.module" in p.stderr and "bad.toml" in p.stderr
    p = _cli("run", str(bad), "--out", str(tmp_path / "o"), "--rtol", "x", cwd=tmp_path)
    assert p.returncode == 2 and p.stderr.count("\n") == 1 and "--rtol" in p.stderr
    assert not (tmp_path / "o").exists()


def test_subprocess_solver_failure_is_one_line_exit_3(tmp_path: Path) -> None:
    """A solve that cannot finish within the right-hand-side budget is a SolverError (exit 3)
    naming the method, the advice and the flag that raises the budget; checked through a tiny
    budget set by that flag."""
    p = subprocess.run([sys.executable, "-m", "gear_dyn.cli", "run", str(HELI), "--out",
                        str(tmp_path / "o"), "--method", "RK45", "--periods", "50",
                        "--max-nfev", "1000"],
                       capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert p.returncode == 3, p.stderr
    assert p.stderr.count("\n") == 1 and p.stderr.startswith("gear-dyn: solver failure: ")
    assert "RK45" in p.stderr and "implicit method" in p.stderr and "--max-nfev" in p.stderr
    assert not (tmp_path / "o").exists() and _hidden_leftovers(tmp_path) == []


def _leaf_parsers(sub: argparse.ArgumentParser, prefix: list[str]
                  ) -> list[tuple[list[str], argparse.ArgumentParser]]:
    for action in sub._actions:  # noqa: SLF001
        if isinstance(action, argparse._SubParsersAction):  # noqa: SLF001
            return [leaf for name, s in action.choices.items()
                    for leaf in _leaf_parsers(s, [*prefix, name])]
    return [(prefix, sub)]


@pytest.mark.parametrize("value", ["abc", "nan", "-1", "1e309"])
def test_every_option_of_every_subcommand_with_junk_values(
    value: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, blank_plots: None
) -> None:
    """Each value-taking option of each (nested) subcommand given junk on an otherwise valid
    command line: exit 0, 2 or 3 with one stderr line, never an internal error."""
    monkeypatch.chdir(tmp_path)  # options that name an output file write here
    bad = []
    n = 0
    for name, sub in _subcommands().items():
        for prefix, leaf in _leaf_parsers(sub, [name]):
            lines = _command_lines(leaf, str(HELI), str(tmp_path / "out.fmu"), str(HELI))
            if not lines:
                continue
            for action in leaf._actions:  # noqa: SLF001
                if not action.option_strings or action.nargs == 0 or action.dest in (
                        "help", "out"):
                    continue
                argv = [*prefix, *lines[0], action.option_strings[0], value]
                n += 1
                with _time_limit(120, " ".join(argv)):
                    code, _, err = _run(argv)
                label = " ".join([*prefix, action.option_strings[0], value])
                if code not in DOCUMENTED_EXIT_CODES or "Traceback" in err or (
                        code != 0 and err.count("\n") != 1):
                    bad.append(f"{label}: exit {code}: {err.strip()[:300]}")
                if _hidden_leftovers(tmp_path):
                    bad.append(f"{label}: temporary files left: {_hidden_leftovers(tmp_path)}")
                shutil.rmtree(tmp_path / "out.fmu", ignore_errors=True)
                with contextlib.suppress(FileNotFoundError):
                    (tmp_path / "out.fmu").unlink()
    assert n > 20
    assert not bad, "\n".join(bad)
