"""The docs pages speak of the product, not of its making: no issue numbers, commit hashes,
machine paths, remarks on the load of the machine that measured, test-file paths, or remarks on
how the code was before (the changelog is the page for that).

Checked on every page source of the site (docs/**/*.md, the README and the gallery scripts,
whose printed output lands on the gallery pages). HTML comments (not shown) are skipped; the
development page may name test files and the CI script (it is about running them). Benchmark
results that the pages include are records of a run and are not checked here.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted(p for p in (ROOT / "docs").rglob("*.md")
               if not {"_build", "gallery", "_generated"} & set(p.relative_to(ROOT).parts))
PAGES += [ROOT / "README.md", *sorted((ROOT / "examples").glob("plot_*.py"))]

FORBIDDEN = {
    "an issue number": re.compile(r"\bissues? #?\d+", re.I),
    # 7-40 hex digits with a letter and a digit: a commit hash (not a plain number, not a word)
    "a commit hash": re.compile(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*\d)[0-9a-f]{7,40}\b"),
    "a machine path": re.compile(r"(?<![\w.])/(?:work|tmp|home|root)/"),
    "a remark on machine load": re.compile(r"load average|loaded (?:2-core )?machine|"
                                           r"shared 2-core|2 shared cores|machine's load", re.I),
    "a CI script": re.compile(r"\.ci/run"),
    # how the code was before: the pages describe what it does (the changelog is exempt)
    "a remark on the project's history": re.compile(
        r"\b(?:used\s+to\s+(?:pick|be|take|run|give|use|say)|previously|formerly|"
        r"no\s+longer\s+(?:relies|uses|picks|takes)|"
        r"now\s+(?:says|iterates?|takes?|picks?|uses?)|ran\s+into\s[\w\s]{0,30}before)\b", re.I),
}
TEST_PATH = re.compile(r"\btests/[\w/*.-]*\.py")


def _text(path: Path) -> str:
    text = path.read_text(encoding="utf-8")
    text = re.sub(r"<!--.*?-->", "", text, flags=re.S)
    return re.sub(r"https?://\S+", "", text)      # DOIs and links may hold anything


@pytest.mark.parametrize("path", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_page_speaks_of_the_product(path: Path) -> None:
    text = _text(path)
    checks = dict(FORBIDDEN)
    if path.name == "changelog.md":     # the page about the project's history
        del checks["a remark on the project's history"]
    if path.name != "development.md":   # the page about running the tests and CI
        checks["a test-file path"] = TEST_PATH
    else:
        del checks["a CI script"]
    found = [f"{what}: {m.group(0)!r}" for what, rx in checks.items() for m in rx.finditer(text)]
    assert not found, found


def test_the_check_finds_what_it_looks_for() -> None:
    """Each pattern matches what it is for and leaves numbers, DOIs and words alone."""
    assert FORBIDDEN["an issue number"].search("the target of issue 15")
    assert FORBIDDEN["a commit hash"].search("at commit 1fb3afe, before")
    assert not FORBIDDEN["a commit hash"].search("0.000785988 s, 10000000, facade, 1758252")
    assert FORBIDDEN["a machine path"].search("wrote /tmp/x/relief.png")
    assert not FORBIDDEN["a machine path"].search("docs/_build/html, benchmarks/out/")
    assert TEST_PATH.search("(tests/fmu/test_fmu_sdof.py)")
    history = FORBIDDEN["a remark on the project's history"]
    assert history.search("`auto` used to pick LSODA there")
    assert history.search("(it ran into the iteration cap before, 60 evaluations)")
    assert not history.search("Where Newton no longer converges (the branch ended at a fold)")
    assert not history.search("the model is no longer `mesh_periodic`")


SUBSTITUTION = re.compile(r"\{\{\s*(\w+)\s*\}\}")


def test_pages_quote_the_demo_through_its_substitutions() -> None:
    """Every ``{{ name }}`` on a page is one the build defines, and the quick start types none
    of the demo's figures (four-decimal numbers) itself: they come from the demo's run."""
    import sys

    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    try:
        import demo_output
    finally:
        sys.path.remove(str(ROOT / "docs" / "_ext"))
    defined = set(demo_output.QUOTED) | {"version"}
    for page in PAGES:
        if page.suffix == ".md":
            used = set(SUBSTITUTION.findall(_text(page)))
            assert used <= defined, (page.name, used - defined)
    quick = _text(ROOT / "docs" / "quickstart.md")
    assert "{{ demo_dynamic_factor }}" in quick
    assert not re.findall(r"\b\d\.\d{4}\b", quick)


def test_demo_substitutions_are_the_demo_run(tmp_path: Path) -> None:
    """The build's figures are those of ``gear-dyn demo``: the same as the packaged scene's
    run through the Python API (the demo's scene and default settings)."""
    import sys

    import gear_dyn as gd

    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    try:
        import demo_output
    finally:
        sys.path.remove(str(ROOT / "docs" / "_ext"))
    subs = demo_output.run_demo(tmp_path)
    printed = (tmp_path / "_generated" / "demo_output.txt").read_text()
    assert not FORBIDDEN["a machine path"].search(printed)
    assert "gear_dyn_demo/summary.json" in printed
    res = gd.run_scene(gd.load_scene("helicopter_tail"))
    assert subs["demo_dynamic_factor"] == f"{res.dynamic_factor:.4f}"
    assert subs["demo_peak_force_ratio"] == f"{res.peak_force_ratio:.4f}"
    assert subs["demo_mesh_frequency"] == f"{res.mesh_frequency:.1f} Hz"
    assert f"dynamic factor      {subs['demo_dynamic_factor']}" in printed


def test_commands_table_names_every_command_and_real_files() -> None:
    """The table at the top of the commands page has a row for every subcommand of the CLI,
    and every output file it names is one a command module writes."""
    import argparse

    from gear_dyn.cli.app import build_parser

    commands = set()
    for action in build_parser()._actions:
        if isinstance(action, argparse._SubParsersAction):  # noqa: SLF001
            commands = set(action.choices)
    assert commands
    rows = [line.split("|")[1:4] for line in
            (ROOT / "docs" / "commands.md").read_text(encoding="utf-8").splitlines()
            if line.startswith("| `gear-dyn ")]
    named = {m for first, _, _ in rows for m in re.findall(r"`(?:gear-dyn )?([a-z-]+)", first)}
    assert commands <= named, commands - named
    written = "\n".join(p.read_text(encoding="utf-8")
                        for p in (ROOT / "gear_dyn" / "cli").glob("*.py"))
    output = re.compile(r"`([\w.]+\.(?:png|csv|json|md|toml))`")
    files = {f for _, _, out in rows for f in output.findall(out)}
    assert files and all(f'"{f}"' in written for f in files), sorted(
        f for f in files if f'"{f}"' not in written)
