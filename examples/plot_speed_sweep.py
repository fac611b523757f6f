"""
Speed sweep, locally and on a Dask cluster
==========================================

A speed sweep of the helicopter tail scene in this process and on a Dask cluster (a
``LocalCluster`` here): the same numbers, bit for bit. Needs the ``dask`` extra
(``pip install "gear_dyn[dask]"``; the docs build installs it). For a real cluster replace the
LocalCluster by ``Client("tcp://scheduler:8786")``, or run
``gear-dyn sweep SCENE --speeds "500 rpm:12000 rpm:300" --out DIR --dask tcp://scheduler:8786``.

Usage: ``python examples/plot_speed_sweep.py [OUT_DIR]``; writes ``sweep.png``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import gear_dyn as gd
from gear_dyn.io import save_figure
from gear_dyn.plots.sweep import plot_sweep_response


def main(out: Path, fast: bool = False) -> dict[str, float]:
    scene = gd.load_scene("helicopter_tail")
    # speeds carry their unit, as everywhere in gear_dyn (a plain number is refused)
    speeds = "2000 rpm:12000 rpm:8" if fast else "500 rpm:12000 rpm:200"   # START:STOP:N
    local = gd.sweep_scene(scene, speeds, workers=1)            # in this process
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        sys.exit("this example runs a Dask cluster: pip install 'gear_dyn[dask]'")

    with LocalCluster(n_workers=1, processes=False, threads_per_worker=2,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        remote = gd.sweep_scene(scene, speeds, executor=client.get_executor(), block=4)
    a, b = local.curves[0], remote.curves[0]
    same = bool(np.array_equal(a.dynamic_factor, b.dynamic_factor))
    i = int(np.nanargmax(a.dynamic_factor))
    print(f"max dynamic factor {a.dynamic_factor[i]:.4f} at {a.speed[i] * 30 / np.pi:.0f} rpm; "
          f"local and Dask identical: {same}")
    out.mkdir(parents=True, exist_ok=True)
    save_figure(plot_sweep_response(local), out / "sweep.png", dpi=100)
    return {"identical": float(same), "max_dynamic_factor": float(a.dynamic_factor[i]),
            "natural_frequency_hz": local.natural_frequency}


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "speed_sweep_out"))
