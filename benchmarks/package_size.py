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

A second count takes the history commit by commit: the net lines each commit since the baseline
changed in the package (against its parent), summed over issue 22's commits. Those are the
commits of the branches that did issue 22's work (:data:`ISSUE_22_BRANCHES`, every commit that a
merge ``Merge branch 'NAME'`` brought) and issue 22's commits made on main itself
(:data:`ISSUE_22_ON_MAIN`). Every other commit counts as the later issues' (or earlier work's);
what merges changed by themselves (conflict resolutions) is shown apart, so that the parts add
up to the package's whole change. Each of issue 22's commits is listed in the output.

Writes ``package_size.md`` into ``benchmarks/out/``; ``--record`` into ``benchmarks/results/``.
"""

from __future__ import annotations

import argparse
import ast
import fnmatch
import subprocess
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: the commit issue 22 was measured on (21 624 lines)
BASELINE = "5d51172"
TARGET = 1500
#: modules added for issues 23 (native FMU), 24 (first week) and 25 (nonlinear response)
ADDED_BY_LATER_ISSUES = {
    "23 native FMU": [
        "gear_dyn/fmu/native/gd_*", "gear_dyn/solvers/kernel/gd_*", "gear_dyn/fmu/export*.py",
        "gear_dyn/fmu/hosts.py",
        "gear_dyn/fmu/toolchain.py", "gear_dyn/fmu/fmu_info.py",
    ],
    "24 first week": [
        "gear_dyn/analysis/dynamic_factor.py", "gear_dyn/analysis/sweep/smooth.py",
        "gear_dyn/solvers/linear_maps.py",  # sweep/smooth.py, moved
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


#: branches that did issue 22's work; every commit a ``Merge branch 'NAME'`` brought counts
ISSUE_22_BRANCHES = (
    "docs", "names", "oneproc", "plainsweep", "slim", "slim3", "slim4",
    "chains", "cutanalysis", "cutfmu", "cutnonlin", "cutphysics", "cutshell", "testref",
    "cut2fmu", "cut2solvers", "cut2analysis", "cut2physics", "cut2shell",
)
#: issue 22's commits made on main itself that change package lines (the rest changed none)
ISSUE_22_ON_MAIN = (
    "b96d9cb",  # draw in the command's own process (forerunner, forks, compositing removed)
    "2639b43",  # find_root cannot divide by zero (the 1 rpm defect)
    "6c3bd24",  # break the import circles
    "6903e64",  # one meaning per name (simulate_bare)
    "8966480",  # README of one screen
    "f747bf8",  # tip-relief rule seed001 -> wang2024 (old name warns)
    "9034792",  # Weber modulus seed -> jiang2018 (old name warns)
    "861f302",  # sources cited by author and year
    "6e8ff36",  # the other sources the code cites
    "2486168",  # the tooth beam's running integrals in one function (review of the cut2 branches)
    "5025ca5",  # tqdm imported where a bar is drawn
    "ed7740c",  # contact_exact docstring: when a piece is not searched
    "aab9b9f",  # one list of each user choice (parser-time copies removed)
    "0fbaa9b",  # plots/bifurcation: the f_m/f_n axis factor without a _teeth helper
)


def _git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=ROOT, check=True, capture_output=True,
                          text=True).stdout


def line_counts(rev: str) -> dict[str, int]:
    """Lines per package source file at ``rev`` (vendored FMI headers left out)."""
    files = package_files(_git("ls-tree", "-r", "--name-only", rev, "gear_dyn").split())
    return {f: _git("show", f"{rev}:{f}").count("\n") for f in files}


def package_files(paths: list[str]) -> list[str]:
    """The package's counted source files among ``paths`` (vendored FMI headers left out)."""
    return [f for f in paths
            if f.startswith("gear_dyn/") and f.endswith((".py", ".c", ".h"))
            and not f.startswith(("gear_dyn/fmu/native/fmi2/", "gear_dyn/fmu/native/fmi3/"))]


KINDS = ("code", "docstring", "comment", "blank")


def line_kinds(text: str, path: str) -> Counter[str]:
    """The lines of one source file by kind (:data:`KINDS`); a C file's non-blank lines count
    as code, a Python file's docstrings are those of the module, classes and functions."""
    doc: set[int] = set()
    if path.endswith(".py"):
        for node in ast.walk(ast.parse(text)):
            if (isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef
                           | ast.AsyncFunctionDef)
                    and node.body and isinstance(node.body[0], ast.Expr)
                    and isinstance(node.body[0].value, ast.Constant)
                    and isinstance(node.body[0].value.value, str)):
                doc.update(range(node.body[0].lineno, (node.body[0].end_lineno or 0) + 1))
    kinds: Counter[str] = Counter()
    for number, line in enumerate(text.splitlines(), 1):
        stripped = line.strip()
        kinds["docstring" if number in doc else "blank" if not stripped
              else "comment" if stripped.startswith("#") and path.endswith(".py")
              else "code"] += 1
    return kinds


def _file_at(rev: str, path: str) -> str:
    shown = subprocess.run(["git", "show", f"{rev}:{path}"], cwd=ROOT, capture_output=True,
                           text=True)
    return shown.stdout if shown.returncode == 0 else ""


def commit_delta(commit: str, parent: str) -> Counter[str]:
    """Net package lines by kind (:data:`KINDS`) that ``commit`` changed against ``parent``."""
    net: Counter[str] = Counter()
    changed = _git("diff", "--name-only", "--no-renames", parent, commit, "--",
                   "gear_dyn").split()
    for path in package_files(changed):
        net.update(line_kinds(_file_at(commit, path), path))
        net.subtract(line_kinds(_file_at(parent, path), path))
    return net


def issue_22_commits(rev: str) -> tuple[list[tuple[str, Counter[str], str]], int, int]:
    """Issue 22's commits since :data:`BASELINE` up to ``rev`` with their net package lines,
    the net lines of every other non-merge commit, and what merges changed by themselves."""
    merges = _git("rev-list", "--merges", f"{BASELINE}..{rev}").split()
    branch_of: dict[str, str] = {}
    for merge in reversed(merges):  # oldest first: a commit belongs to the first merge of it
        subject = _git("log", "-1", "--format=%s", merge)
        if not subject.startswith("Merge branch '"):
            continue
        branch = subject.split("'")[1]
        for c in _git("rev-list", "--no-merges", f"{merge}^1..{merge}^2").split():
            branch_of.setdefault(c, branch)
    on_main = {_git("rev-parse", h).strip() for h in ISSUE_22_ON_MAIN}
    ours: list[tuple[str, Counter[str], str]] = []
    others = 0
    for c in _git("rev-list", "--reverse", "--no-merges", f"{BASELINE}..{rev}").split():
        net = commit_delta(c, f"{c}^")
        if c in on_main or branch_of.get(c) in ISSUE_22_BRANCHES:
            if any(net.values()):
                ours.append((c[:7], net, _git("log", "-1", "--format=%s", c).strip()))
        else:
            others += sum(net.values())
    whole = sum(line_counts(rev).values()) - sum(line_counts(BASELINE).values())
    return ours, others, whole - others - sum(sum(n.values()) for _, n, _ in ours)


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
    ours, others, merged = issue_22_commits(rev)
    kinds: Counter[str] = Counter()
    for _, net, _ in ours:
        kinds.update(net)
    own = sum(kinds.values())
    verdict = "met" if -own >= TARGET else "NOT met"
    lines += [
        "",
        "## Commit by commit",
        "",
        "The net package lines each commit since the baseline changed (against its parent), "
        "summed over issue 22's commits and over all the others:",
        "",
        "| | lines |",
        "|---|---|",
        f"| issue 22's {len(ours)} commits that change package lines (listed below) | {own:+d} |",
        f"| every other commit since {BASELINE} (issues 23-25, earlier work) | {others:+d} |",
        f"| what merges changed by themselves (conflict resolutions) | {merged:+d} |",
        f"| the package's whole change | {own + others + merged:+d} |",
        "",
        f"Issue 22's work made the package {-own} lines smaller. Target: at least {TARGET} "
        f"lines: **{verdict}**.",
        "",
        "Those lines by kind (docstrings of the module, classes and functions; comments; "
        "blank lines; the rest is code, C files' lines included): "
        + ", ".join(f"{k} {kinds[k]:+d}" for k in KINDS) + ".",
        "",
        "| commit | lines | of which code | subject |",
        "|---|---|---|---|",
    ]
    lines += [f"| {c} | {sum(n.values()):+d} | {n['code']:+d} | "
              f"{subj.replace('|', '/')[:100]} |" for c, n, subj in ours]
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
