"""``gear-dyn tolerance``: files written, figures stated, user mistakes as exit 2."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from gear_dyn.cli.app import main


def test_tolerance_writes_json_csv_and_figure(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "tol"
    code = main(["tolerance", "helicopter_tail", "--samples", "5", "--speeds",
                 "3000 rpm:8000 rpm:4", "--grade", "6", "--samples-per-period", "16",
                 "--out", str(out)])
    assert code == 0
    summary = json.loads((out / "tolerance.json").read_text())
    assert summary["n_samples"] == 5 and summary["hunting_period_mesh_cycles"] == 1472
    assert summary["seeds"] == [[1, i] for i in range(5)]
    kd = summary["metrics"]["k_dyn"]
    assert len(kd["median"]) == 4 and len(kd["median_stderr"]) == 4
    assert all(lo <= md <= hi for lo, md, hi in zip(kd["p05"], kd["median"], kd["p95"],
                                                     strict=True))
    assert summary["iso_6336_kv"]["like_for_like"].startswith("like for like")
    with (out / "tolerance.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 4 and "k_dyn_median" in rows[0] and "rms_dte_p95_m" in rows[0]
    assert (out / "tolerance.png").stat().st_size > 10_000
    text = capsys.readouterr().out
    assert "5 samples x 4 speeds" in text and "(1 s.e.)" in text and "ISO 6336-1 K_v" in text


@pytest.mark.parametrize(("args", "message"), [
    (["--samples", "0"], "samples"),
    (["--grade", "13"], "accuracy_grade"),
])
def test_tolerance_user_mistakes_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                        args: list[str], message: str) -> None:
    code = main(["tolerance", "helicopter_tail", "--speeds", "3000 rpm:4000 rpm:2",
                 "--out", str(tmp_path / "x"), *args])
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1
