"""Lines of the package now and when issue 22 ("Simple enough to live in") was filed.

Run:  python benchmarks/package_size.py [--rev REV] [--record]

Issue 22 asks for a package at least 1,500 lines smaller, with every capability intact. Issues
23-25 (native FMU, a gear engineer's first week, the nonlinear response) then added
capabilities, mostly in modules of their own. This script counts, from git (the clone needs its
history), the lines of ``gear_dyn`` (``.py``, ``.c``, ``.h``; the FMI standard's own headers in
``fmu/native/fmi2`` and ``fmi3`` left out) at :data:`BASELINE`, the commit the issue measured,
and at ``REV`` (default ``HEAD``), and splits them:

- modules that the later issues added (:data:`ADDED_BY_LATER_ISSUES`, matched by path);
- everything else: the code that was there, the modules that issue 22 itself split off, and
  whatever the later issues added to files that were already there.

The change of the second part is a lower bound of what the simplification removed: lines that
the later issues wrote into files that were already there count against it.

Writes ``package_size.md`` into ``benchmarks/out/``; ``--record`` into ``benchmarks/results/``.
"""

from __future__ import annotations

import argparse
import fnmatch
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: the commit issue 22 was measured on (21 624 lines)
BASELINE = "5d51172"
TARGET = 1500
#: modules added for issues 23 (native FMU), 24 (first week) and 25 (nonlinear response)
ADDED_BY_LATER_ISSUES = {
    "23 native FMU": [
        "gear_dyn/fmu/native/gd_*", "gear_dyn/fmu/export*.py", "gear_dyn/fmu/hosts.py",
        "gear_dyn/fmu/toolchain.py", "gear_dyn/fmu/fmu_info.py",
    ],
    "24 first week": [
        "gear_dyn/analysis/dynamic_factor.py", "gear_dyn/analysis/sweep/smooth.py",
        "gear_dyn/cli/compare.py", "gear_dyn/scene/operating.py",
    ],
    "25 nonlinear response": [
        "gear_dyn/analysis/continuation/*", "gear_dyn/analysis/motion/*",
        "gear_dyn/analysis/executor.py", "gear_dyn/analysis/sweep/jump.py",
        "gear_dyn/analysis/sweep/orbit_jumps.py", "gear_dyn/cli/response.py",
        "gear_dyn/cli/bifurcation.py", "gear_dyn/cli/jump_map.py",
        "gear_dyn/plots/bifurcation.py", "gear_dyn/plots/continuation.py",
        "gear_dyn/plots/fold_map.py", "gear_dyn/scene/bifurcation.py",
        "gear_dyn/solvers/harmonic_forcing.py", "gear_dyn/plots/_labels.py",
    ],
}


def _git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=ROOT, check=True, capture_output=True,
                          text=True).stdout


def line_counts(rev: str) -> dict[str, int]:
    """Lines per package source file at ``rev`` (vendored FMI headers left out)."""
    files = [f for f in _git("ls-tree", "-r", "--name-only", rev, "gear_dyn").split()
             if f.endswith((".py", ".c", ".h"))
             and not f.startswith(("gear_dyn/fmu/native/fmi2/", "gear_dyn/fmu/native/fmi3/"))]
    return {f: _git("show", f"{rev}:{f}").count("\n") for f in files}


def later_issue(path: str, baseline: dict[str, int]) -> str | None:
    """The later issue whose new module ``path`` is (None: not one, or there at the baseline)."""
    if path in baseline:
        return None
    for issue, patterns in ADDED_BY_LATER_ISSUES.items():
        if any(fnmatch.fnmatch(path, p) for p in patterns):
            return issue
    return None


def report(rev: str) -> str:
    base = line_counts(BASELINE)
    now = line_counts(rev)
    added: dict[str, int] = dict.fromkeys(ADDED_BY_LATER_ISSUES, 0)
    for f, n in now.items():
        issue = later_issue(f, base)
        if issue is not None:
            added[issue] += n
    total_base, total_now = sum(base.values()), sum(now.values())
    rest = total_now - sum(added.values())
    removed = total_base - rest
    verdict = "met" if removed >= TARGET else "NOT met"
    head = _git("rev-parse", "--short", rev).strip()
    lines = [
        "# Package size: issue 22's line count",
        "",
        f"Produced by `python benchmarks/package_size.py --record` at commit {head}: lines of "
        "gear_dyn's .py, .c and .h files (the FMI standard's headers left out), counted from git.",
        "",
        "| | lines |",
        "|---|---|",
        f"| package at {BASELINE} (issue 22 filed) | {total_base} |",
        f"| package at {head} | {total_now} |",
    ]
    lines += [f"| of which modules added by issue {k} | {v} |" for k, v in added.items()]
    lines += [
        f"| of which the rest (the code that was there, and what the later issues added to it) "
        f"| {rest} |",
        "",
        f"The rest is {removed} lines smaller than the package at {BASELINE}: a lower bound of "
        "what the simplification removed (lines the later issues wrote into files that were "
        f"already there count against it). Target: at least {TARGET} lines: **{verdict}**.",
        "",
        f"The whole package grew by {total_now - total_base} lines: the capabilities of issues "
        "23-25.",
    ]
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rev", default="HEAD")
    ap.add_argument("--record", action="store_true")
    args = ap.parse_args()
    text = report(args.rev)
    out = ROOT / "benchmarks" / ("results" if args.record else "out") / "package_size.md"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(text, end="")


if __name__ == "__main__":
    main()
