"""The README's whole-command and sweep speed figures are the recorded benchmark results
(benchmarks/results/cli.md, sweep.md): re-recording without updating the README fails here."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SPREAD = r"[0-9.]+ \([0-9.]+\.\.[0-9.]+\)"


def _readme() -> str:
    return " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())


def test_whole_command_ratios_are_the_recorded_ones() -> None:
    recorded = (ROOT / "benchmarks" / "results" / "cli.md").read_text(encoding="utf-8")
    readme = _readme()
    for scene in ("helicopter_tail", "helicopter_tail_backlash"):
        row = next(ln for ln in recorded.splitlines() if ln.startswith(f"| {scene} |"))
        ratio = re.findall(rf"\*\*({SPREAD})x\*\*", row)
        assert ratio, row
        assert f"{ratio[0]}x" in readme, (scene, ratio[0])


def test_matplotlib_import_times_are_the_recorded_ones() -> None:
    recorded = (ROOT / "benchmarks" / "results" / "cli.md").read_text(encoding="utf-8")
    readme = _readme()
    for label in ("(as usual)", "quick import"):
        row = next(ln for ln in recorded.splitlines() if label in ln)
        value = re.findall(rf"\| ({SPREAD}) \|", row)
        assert value and f"{value[0]} s" in readme, (label, row)


def test_sweep_fixed_cost_is_the_recorded_one() -> None:
    recorded = (ROOT / "benchmarks" / "results" / "sweep.md").read_text(encoding="utf-8")
    fixed = re.search(rf"Fixed cost beyond start-up: \*\*({SPREAD}) s\*\*", recorded)
    assert fixed is not None
    assert f"fixed cost beyond start-up (two figures, CSV, JSON) is {fixed.group(1)} s" in _readme()
