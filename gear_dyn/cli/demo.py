"""``gear-dyn demo``: run the helicopter tail drive of Jiang et al. (2018) and say where the plots
are."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from gear_dyn.cli.progress import Stages, add_quiet_flag


def register(sub: Any) -> None:
    p = sub.add_parser(
        "demo", help="run the helicopter tail scene (Jiang et al. 2018) into a folder",
        description="Run the packaged helicopter tail scene (examples/scenes/helicopter_tail.toml)"
        " and write plots, CSV and summary.json.",
    )
    p.add_argument("--out", type=Path, default=Path("gear_dyn_demo"),
                   help="output folder (default: ./gear_dyn_demo)")
    add_quiet_flag(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    with Stages(["load scene", "solve", "write plots and data"], args.quiet) as st:
        from gear_dyn.cli.output import write_run_outputs
        from gear_dyn.scene import load_scene, run_scene
        from gear_dyn.scene.packaged import scene_path

        scene = load_scene(scene_path("helicopter_tail"))
        st.next()
        result = run_scene(scene)
        st.next()
        s = write_run_outputs(result, args.out)
    out = args.out.resolve()
    print("gear_dyn demo: the helicopter tail drive of Jiang et al. (2018) (z 23/64, m 6 mm, "
          "3319 rpm, 1474.4 N m)")
    print(f"  mesh frequency      {s['mesh_frequency_hz']:.1f} Hz")
    print(f"  output speed        {s['output_speed_rpm']:.1f} rpm")
    print(f"  contact ratio       {s['contact_ratio']:.4f}")
    k_m = s["mean_mesh_stiffness_n_per_m"]
    print(f"  mean mesh stiffness {k_m:.4g} N/m ({s['stiffness_method']})")
    print(f"  static TE W/k_m     {s['static_transmission_error_m'] * 1e6:.4g} um")
    print(f"  dynamic factor      {s['dynamic_factor']:.4f} ({s['dynamic_factor_definition']})")
    print(f"  peak force / W      {s['peak_force_ratio']:.4f} = K_dyn x the stiffness-jump "
          f"overshoot {s['stiffness_jump_factor']:.4f} of the rectangular-wave k(t)")
    iso = s.get("iso_6336_kv")
    if iso:
        from gear_dyn.scene.iso import iso_kv_lines

        lines = iso_kv_lines(iso)
        print(f"  ISO 6336 K_v        {lines[0].split(': ', 1)[-1]}")
        for line in lines[1:]:
            print(f"                    {line}")
    print(f"  DTE                 {s['dte_definition']}")
    print(f"  RMS / p-p DTE       {s['rms_dte_m'] * 1e6:.4g} / {s['ptp_dte_m'] * 1e6:.4g} um")
    print(f"  solver              {s['solver']['method']}, {s['solver']['run_time_s']:.3g} s")
    est = s.get("estimated_error")
    if est:
        print(f"  estimated error     {est['max_rel']:.2g} of W/k_m ({est['basis']})")
    fl = s.get("floquet")
    if fl:
        state = "UNSTABLE" if fl["unstable"] else "stable"
        mu = fl["max_multiplier_modulus"]
        print(f"  Floquet check       largest multiplier {mu:.3f} ({state})")
    print(f"plots: {out / 'time_history.png'}  {out / 'spectrum.png'}")
    print(f"data:  {out / 'timeseries.csv'}  {out / 'summary.json'}")
    return 0
